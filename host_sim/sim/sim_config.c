/* INI configuration of the simulator: the keys, the parser, the loader.
 * See sim_config.h; the checks after parsing are in sim_config_check.c, the
 * drive side's conversion in sim_config_drive.c. */
#include "sim_config.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ini.h>

#include "drive_limits.h"
#include "ini_lines.h"
#include "sim_config_check.h"
#include "sim_limits.h"


#define REQ 1  /* the key must be present */
#define OPT 0  /* the key may be omitted: its default applies */

/* Which side reads a key (--keys). */
#define DRIVE "drive"         /* into drive_config_t: the firmware */
#define SIM "sim"             /* the simulated world only */
#define BOTH "drive+sim"      /* the firmware, and the simulator models the same thing with it */
#define CHECK "check"         /* informative: checked against the other ratings, read by neither */

typedef struct {
    const char *section;
    const char *key;
    size_t offset;
    int required;
    double def;            /* default when optional and def_key is NULL */
    const char *def_key;   /* default: the value of this key (declared before this one) */
    double min, max;       /* valid closed range; min > max: drive_limits.h's */
    int integer;           /* the value must be a whole number */
    const char *unit;
    const char *side;
    const char *what;      /* what it is, for --keys */
} key_spec_t;

/* (sec.name is a member designator: it cannot be parenthesised) */
#define K(sec, name, req, def, def_key, lo, hi, integ, unit, side, what)                          \
    { #sec, #name, offsetof(sim_config_t, sec.name), /* NOLINT(bugprone-macro-parentheses) */    \
      req, def, def_key, lo, hi, integ, unit, side, what }
/* a drive-side key: range, unit and whole-number rule from the drive's table
 * (drive_limits.h), marked by min > max */
#define D(sec, name, req, def, side, what) \
    K(sec, name, req, def, NULL, 1.0, 0.0, 0, NULL, side, what)

static const key_spec_t k_keys[] = {
    /* ---- drive side: what the firmware is told ---- */
    D(nameplate, Rs_ohm, REQ, 0, DRIVE, "stator resistance"),
    D(nameplate, Rr_ohm, REQ, 0, DRIVE, "rotor resistance, referred to the stator"),
    D(nameplate, Lm_H, REQ, 0, DRIVE, "magnetising inductance"),
    D(nameplate, Lls_H, REQ, 0, DRIVE, "stator leakage (Ls = Lm_H + Lls_H)"),
    D(nameplate, Llr_H, REQ, 0, DRIVE, "rotor leakage (Lr = Lm_H + Llr_H)"),
    D(nameplate, pole_pairs, REQ, 0, BOTH, "pole pairs (the simulated motor's too)"),
    D(nameplate, rated_current_A, REQ, 0, DRIVE, "rated current"),
    D(nameplate, rated_speed_rpm, REQ, 0, BOTH,
      "rated speed (the simulated fan load is given at it)"),
    D(nameplate, rated_freq_Hz, REQ, 0, DRIVE, "rated frequency, the per-unit frequency base"),
    K(nameplate, rated_voltage_V, OPT, 0, NULL, 1, 2000, 0, "V rms line", CHECK,
      "informative; if given with rated_power_W: P <= sqrt(3) V I"),
    K(nameplate, rated_power_W, OPT, 0, NULL, 1, 1e6, 0, "W", CHECK,
      "informative; if given with rated_voltage_V: P <= sqrt(3) V I"),
    D(board, pwm_freq_Hz, OPT, 15000, BOTH, "PWM (and ISR) frequency"),
    D(board, sysclk_Hz, OPT, 150e6, DRIVE, "CPU clock (EV-A timer clock)"),
    D(board, dead_time_s, OPT, 1e-6, DRIVE, "programmed dead band: what the drive compensates"),
    D(board, device_drop_V, OPT, 0.3, DRIVE, "switch/diode drop the drive compensates"),
    D(board, vdc_nominal_V, REQ, 0, DRIVE, "nominal bus voltage: V_base = vdc_nominal_V/sqrt(3)"),
    D(board, vdc_full_scale_V, REQ, 0, BOTH, "bus voltage that reads 3.0 V at the ADC pin"),
    D(board, current_full_scale_A, REQ, 0, BOTH,
      "Hall sensors' +- full scale (0..3 V), also I_base"),
    D(board, encoder_lines, REQ, 0, BOTH, "encoder lines per revolution (x4 in the QEP)"),
    D(controller, current_bw_Hz, REQ, 0, DRIVE, "current-loop bandwidth"),
    D(controller, speed_bw_Hz, REQ, 0, DRIVE, "speed-loop bandwidth"),
    D(controller, inertia_kgm2, REQ, 0, DRIVE, "inertia the speed loop is designed for"),
    D(controller, max_torque_current_A, REQ, 0, DRIVE, "torque-current limit"),
    D(controller, speed_ramp_rpm_s, REQ, 0, DRIVE, "speed reference ramp"),
    D(controller, speed_filter_Hz, OPT, 100, DRIVE, "low-pass of the measured speed"),
    D(controller, magnetizing_current_A, REQ, 0, DRIVE, "i_M reference"),
    D(controller, overcurrent_A, REQ, 0, BOTH,
      "phase-current trip (the simulator reports when a fault crosses it)"),
    D(controller, vdc_max_V, REQ, 0, DRIVE, "bus overvoltage trip"),
    D(controller, vdc_min_V, REQ, 0, DRIVE, "bus undervoltage trip"),
    D(controller, dead_time_comp, OPT, 1, DRIVE, "1: dead-time and drop compensation"),
    D(controller, orientation, OPT, 0, DRIVE, "0: indirect (the paper's), 1: rotor-flux observer"),
    D(ident, filter_cutoff_Hz, OPT, 10, DRIVE, "Butterworth corner of the regression signals"),
    D(ident, euler_passes, OPT, 10, DRIVE, "improved-Euler corrector passes"),
    D(ident, paper_regressor, OPT, 0, DRIVE, "1: previous K2 as third regressor (eq. 9)"),
    D(ident, period_mean, OPT, 0, DRIVE,
      "1: the period-mean regression (tools/study/regression_bias.md §5; orientation 0)"),
    D(ident, rls_p0, OPT, 1e5, DRIVE, "RLS P(0) = p0 I (large: no prior pulls a weakly excited direction)"),
    D(ident, forgetting, OPT, 1, DRIVE, "RLS forgetting factor (1: none)"),
    D(ident, magnetize_s, OPT, 0.3, DRIVE, "pre-magnetisation"),
    D(ident, rls_tail_s, OPT, 0.3, DRIVE, "the RLS runs this long after the ramp"),
    /* -1: the nameplate's rated speed, or less where the bus the drive
     * measures at the start cannot carry it (drive_target.h; the drive
     * gets 0); any other value must be a speed (> 0), then the drive's
     * limits (the identification's floor and 1.2 rated: DRIVE_LD_TARGET;
     * the bus at no load: DRIVE_LD_BUS) */
    K(ident, target_speed_rpm, OPT, SIM_TARGET_RATED, NULL, SIM_TARGET_RATED, 1e5, 0,
      "r/min (-1: rated)", DRIVE,
      "speed the sequence accelerates to (at most; the drive lowers it to what the bus gives)"),
    D(ident, passes, OPT, 1, DRIVE, "identification passes (> 1: orientation 1)"),
    D(ident, standstill, OPT, 0, DRIVE, "1: Rs and sigma Ls at standstill (orientation 1)"),
    D(ident, track_rr, OPT, 0, DRIVE, "1: Rr/Tr tracked in RUN (orientation 1)"),
    D(ident, track_memory_s, OPT, 1.0, DRIVE, "the tracker's forgetting time constant"),
    D(ident, static_id, OPT, 0, DRIVE,
      "1: the standstill sequence (standstill 1, passes 1, track_rr 0): every parameter at "
      "standstill, nothing turns"),
    /* a name in the file (on_key): the keys it implies are set after the
     * defaults (apply_sequence); SIM_SEQ_NONE: not given */
    K(ident, sequence, OPT, SIM_SEQ_NONE, NULL, SIM_SEQ_NONE, SIM_SEQ_STANDSTILL, 1,
      "paper|adaptive|standstill", DRIVE,
      "the identification: sets orientation, standstill, passes, track_rr, static_id, "
      "vi_test"),
    D(ident, vi_test, OPT, 1, DRIVE,
      "1: the bridge's voltage error measured at standstill, the compensation on it "
      "(0: a study without the test; the drive then assumes a linear zone of 3 codes "
      "of the current channel, at least 0.1 A)"),
    /* ---- the simulated world ---- */
    K(plant, Rs_ohm, OPT, 0, "nameplate.Rs_ohm", 1e-4, 1000, 0, "ohm", SIM,
      "true stator resistance"),
    K(plant, Rr_ohm, OPT, 0, "nameplate.Rr_ohm", 1e-4, 1000, 0, "ohm", SIM, "true rotor resistance"),
    K(plant, Lm_H, OPT, 0, "nameplate.Lm_H", 1e-5, 10, 0, "H", SIM, "true magnetising inductance"),
    K(plant, Lls_H, OPT, 0, "nameplate.Lls_H", 1e-6, 1, 0, "H", SIM, "true stator leakage"),
    K(plant, Llr_H, OPT, 0, "nameplate.Llr_H", 1e-6, 1, 0, "H", SIM, "true rotor leakage"),
    K(plant, J_kgm2, REQ, 0, NULL, 1e-7, 100, 0, "kg m^2", SIM, "true inertia"),
    K(plant, B_Nm_s, OPT, 0, NULL, 0, 100, 0, "N m s", SIM, "viscous friction"),
    K(inverter, vdc_V, OPT, 0, "board.vdc_nominal_V", 1, 2000, 0, "V", SIM, "bus voltage"),
    K(inverter, source_resistance_ohm, OPT, 0, NULL, 0, 10, 0, "ohm", SIM, "bus source resistance"),
    K(inverter, ripple_V, OPT, 0, NULL, 0, 100, 0, "V peak", SIM, "bus ripple"),
    K(inverter, ripple_Hz, OPT, 100, NULL, 0, 1e4, 0, "Hz", SIM, "bus ripple frequency"),
    K(inverter, dead_time_s, OPT, 0, "board.dead_time_s", 0, 1e-5, 0, "s", SIM,
      "the bridge's real dead time"),
    K(inverter, device_drop_V, OPT, 0, "board.device_drop_V", 0, 5, 0, "V", SIM,
      "the bridge's real switch/diode drop"),
    K(inverter, r_on_ohm, OPT, 0, NULL, 0, 1, 0, "ohm", SIM, "switch on-resistance"),
    K(inverter, dead_time_band_A, OPT, 0.1, NULL, 1e-3, 100, 0, "A", SIM,
      "current over which the bridge's dead-time error changes sign"),
    /* the power stage's own overcurrent protection (desaturation or shunt
     * comparator per leg, on the true leg current, independent of the Hall
     * sensors): pulls PDPINTA, the bridge's outputs off after the delay */
    K(inverter, overcurrent_hw_A, OPT, -1, NULL, -1, 1e5, 0, "A (-1: 1.25 x trip, 0: none)",
      SIM, "hardware comparator level on |leg current| (above controller.overcurrent_A)"),
    K(inverter, overcurrent_hw_delay_s, OPT, 2e-6, NULL, 0, 5e-5, 0, "s", SIM,
      "comparator + gate driver response: crossing to outputs off"),
    /* residual after the production trim of the current channels; phase b
     * gets -0.6 x this (the two sensors differ) */
    K(sensors, hall_gain_error_pct, OPT, 0.1, NULL, -20, 20, 0, "%", SIM,
      "phase-a sensor gain error (phase b: -0.6 x)"),
    K(sensors, hall_offset_a_A, OPT, 0.05, NULL, -100, 100, 0, "A", SIM, "phase-a sensor offset"),
    K(sensors, hall_offset_b_A, OPT, -0.03, NULL, -100, 100, 0, "A", SIM, "phase-b sensor offset"),
    K(sensors, hall_noise_A_rms, OPT, 0.02, NULL, 0, 100, 0, "A rms", SIM, "sensor noise"),
    K(sensors, adc_noise_lsb, OPT, 0.5, NULL, 0, 100, 0, "LSB rms", SIM, "ADC noise"),
    K(sensors, seed, OPT, 1, NULL, 0, 4294967295.0, 1, "-", SIM, "noise seed"),
    /* where the rotor starts within an encoder count: the flux is built along
     * the count's angle and meets the counted angle's half-count lag once the
     * rotor turns (tools/study/regression_bias.md §10) */
    K(sensors, encoder_offset, OPT, 0.5, NULL, 0, 0.999, 0, "pitch", SIM,
      "encoder edges past the rotor's start angle (0.5: it starts mid-count)"),
    K(load, const_Nm, OPT, 0, NULL, 0, 1e4, 0, "N m", SIM,
      "Coulomb friction with stiction: opposes the motion, holds the rotor at rest"),
    K(load, prop_Nm_s, OPT, 0, NULL, 0, 1e3, 0, "N m s", SIM, "load proportional to speed"),
    K(load, fan_Nm, OPT, 0, NULL, 0, 1e4, 0, "N m at rated speed", SIM, "quadratic (fan) load"),
    K(load, locked, OPT, 0, NULL, 0, 1, 1, "0/1", SIM,
      "1: the rotor held at rest (a load that cannot turn); its reaction torque reported"),
    /* the thermal-drift scenario (--scenario drift), times after publication */
    K(drift, rr_rise_pct, OPT, 40, NULL, 0, 100, 0, "% of plant.Rr_ohm", SIM, "rotor warming"),
    K(drift, ramp_s, OPT, 60, NULL, 1, 600, 0, "s", SIM, "duration of the rise"),
    K(drift, start_s, OPT, 2, NULL, 0, 60, 0, "s after RUN", SIM, "start of the rise"),
    K(drift, load_period_s, OPT, 5, NULL, 0.5, 60, 0, "s per load level", SIM, "load steps"),
    K(simulation, substeps, OPT, 4, NULL, 1, 64, 1, "RK4 steps per PWM period", SIM,
      "integration steps"),
};

#define N_KEYS (sizeof k_keys / sizeof k_keys[0])

/* Characters of the file's path shown in a message. */
#define PATH_SHOWN 96

typedef struct {
    sim_config_t *cfg;
    int drive_only;   /* sim_config_load_drive: the simulated world's keys not required */
    unsigned char seen[N_KEYS];
    char err[SIM_CONFIG_ERR_LEN];
} parse_ctx_t;

void sim_config_set_err(char *buf, size_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    /* the analyser of clang 14 does not see va_start through glibc's array
     * va_list (a known false positive) */
    (void)vsnprintf(buf, len, fmt, ap);   /* NOLINT(clang-analyzer-valist.Uninitialized) */
    va_end(ap);
}

static double *field(sim_config_t *cfg, const key_spec_t *k)
{
    return (double *)(void *)((char *)cfg + k->offset);
}

/* The drive's limit for a drive-side key (NULL for the others). */
static const drive_limit_t *drive_limit_of(const key_spec_t *k)
{
    char name[64];
    if (!(k->min > k->max)) {
        return NULL;
    }
    snprintf(name, sizeof name, "%s.%s", k->section, k->key);
    return drive_limit_find(name);
}

static const char *unit_of(const key_spec_t *k)
{
    const drive_limit_t *l = drive_limit_of(k);
    return (l != NULL) ? l->unit : k->unit;
}

static int known_section(const char *section)
{
    size_t i;
    for (i = 0; i < N_KEYS; i++) {
        if (strcmp(k_keys[i].section, section) == 0) {
            return 1;
        }
    }
    return 0;
}

/* The range check of one value: a drive-side key against the drive's own
 * limit, on the float the firmware will hold (so that this check and
 * drive_init agree to the last bit); the others against their range. */
static int check_value(const key_spec_t *k, double v, char *err, size_t len)
{
    const drive_limit_t *l = drive_limit_of(k);
    if (strcmp(k->section, "ident") == 0 && strcmp(k->key, "target_speed_rpm") == 0 &&
        v != SIM_TARGET_RATED && !(v > 0.0)) {
        /* 0 and negative speeds once meant "rated" without a word */
        sim_config_set_err(err, len, "key 'ident.target_speed_rpm' = %g r/min is not a speed "
                           "the identification can run at: give the target (r/min, > 0) or "
                           "-1 for the nameplate's rated speed", v);
        return 1;
    }
    if (l != NULL) {
        drive_limit_fail_t f;
        float fv = (fabs(v) <= FLT_MAX) ? (float)v : (float)copysign(FLT_MAX, v);
        int whole = (l->kind == DRIVE_LIMIT_U16);
        int ok = (l->kind == DRIVE_LIMIT_DERIVED) ? (v >= l->lo && v <= l->hi)
                                                 : (fabs(v) <= FLT_MAX &&
                                                    drive_limit_field_ok(l, fv) != 0);
        if (!ok) {
            memset(&f, 0, sizeof f);
            f.limit = l;
            f.key = l->key;
            f.unit = l->unit;
            f.value = fv;
            f.lo = l->lo;
            f.hi = l->hi;
            f.open = l->open;
            sim_limit_message_value(err, len, &f, v);
            return 1;
        }
        if (whole && v != floor(v)) {
            sim_config_set_err(err, len, "key '%s.%s' = %g must be a whole number", k->section,
                               k->key, v);
            return 1;
        }
        return 0;
    }
    if (v < k->min || v > k->max) {
        sim_config_set_err(err, len, "key '%s.%s' = %g %s is outside [%g, %g] %s", k->section,
                           k->key, v, k->unit, k->min, k->max, k->unit);
        return 1;
    }
    if (k->integer && v != floor(v)) {
        sim_config_set_err(err, len, "key '%s.%s' = %g must be a whole number", k->section, k->key,
                           v);
        return 1;
    }
    return 0;
}

static const key_spec_t *find_key(const char *section_dot_key);

const char *sim_sequence_name(sim_sequence_t seq)
{
    switch (seq) {
    case SIM_SEQ_PAPER: return "paper";
    case SIM_SEQ_ADAPTIVE: return "adaptive";
    case SIM_SEQ_STANDSTILL: return "standstill";
    case SIM_SEQ_NONE:
    default: return NULL;
    }
}

/* [ident] sequence = paper | adaptive | standstill (a name, not a number) */
static int sequence_key(parse_ctx_t *ctx, size_t i, const char *value)
{
    int s;
    for (s = SIM_SEQ_PAPER; s <= SIM_SEQ_STANDSTILL; s++) {
        if (strcmp(value, sim_sequence_name((sim_sequence_t)s)) == 0) {
            *field(ctx->cfg, &k_keys[i]) = (double)s;
            ctx->seen[i] = 1;
            return 1;
        }
    }
    sim_config_set_err(ctx->err, sizeof ctx->err,
                       "key 'ident.sequence': '%s' is not a sequence (paper, adaptive or "
                       "standstill)", value);
    return 0;
}

/* The keys a sequence implies, after the defaults: each one the file also
 * gives must agree (an old file's keys alone keep working: no sequence). */
static int apply_sequence(parse_ctx_t *ctx, char *err, size_t len)
{
    static const char *const implied[] = {"controller.orientation", "ident.standstill",
                                          "ident.passes", "ident.track_rr", "ident.static_id",
                                          "ident.vi_test"};
    sim_config_t want;
    size_t i, j;
    const double seq = ctx->cfg->ident.sequence;
    if (seq == (double)SIM_SEQ_NONE) {
        return 0;
    }
    want = *ctx->cfg;
    sim_config_set_sequence(&want, (sim_sequence_t)seq);
    for (j = 0; j < sizeof implied / sizeof implied[0]; j++) {
        const key_spec_t *k = find_key(implied[j]);
        i = (size_t)(k - k_keys);
        if (ctx->seen[i] && *field(ctx->cfg, k) != *field(&want, k)) {
            sim_config_set_err(err, len, "key '%s' = %g contradicts [ident] sequence = %s "
                               "(which sets it to %g): give one of them", implied[j],
                               *field(ctx->cfg, k), sim_sequence_name((sim_sequence_t)seq),
                               *field(&want, k));
            return 1;
        }
    }
    *ctx->cfg = want;
    return 0;
}

/* [inverter] dead_time_s once was the dead time the drive compensated; it is
 * the bridge's real one now, the compensated one [board] dead_time_s (its
 * default 1 us): a file that gives the first alone likely means the second. */
static void old_layout_note(parse_ctx_t *ctx)
{
    const key_spec_t *inv = find_key("inverter.dead_time_s");
    const key_spec_t *brd = find_key("board.dead_time_s");
    const sim_config_t *c = ctx->cfg;
    if (ctx->seen[inv - k_keys] && !ctx->seen[brd - k_keys] &&
        c->inverter.dead_time_s != c->board.dead_time_s) {
        snprintf(ctx->cfg->note, sizeof ctx->cfg->note,
                 "[inverter] dead_time_s = %g s is the simulated bridge's real dead time; the "
                 "drive compensates [board] dead_time_s, not given here (its default %g s): "
                 "give [board] dead_time_s if the file meant the programmed one (an older "
                 "layout did)", c->inverter.dead_time_s, c->board.dead_time_s);
    }
}

static int on_key(void *user, const char *section, const char *name, const char *value)
{
    parse_ctx_t *ctx = (parse_ctx_t *)user;
    size_t i;
    char *end = NULL;
    double v;

    if (ctx->err[0] != '\0') {
        return 0;   /* report the first error only */
    }
    if (!known_section(section)) {
        sim_config_set_err(ctx->err, sizeof ctx->err, "unknown section [%s]", section);
        return 0;
    }
    for (i = 0; i < N_KEYS; i++) {
        if (strcmp(k_keys[i].section, section) == 0 && strcmp(k_keys[i].key, name) == 0) {
            break;
        }
    }
    if (i == N_KEYS) {
        sim_config_set_err(ctx->err, sizeof ctx->err, "unknown key '%s' in [%s]", name, section);
        return 0;
    }
    if (ctx->seen[i]) {
        sim_config_set_err(ctx->err, sizeof ctx->err, "key '%s.%s' given twice", section, name);
        return 0;
    }
    if (strcmp(section, "ident") == 0 && strcmp(name, "sequence") == 0) {
        return sequence_key(ctx, i, value);
    }
    errno = 0;
    v = strtod(value, &end);
    while (end != NULL && (*end == ' ' || *end == '\t')) {
        end++;
    }
    /* strtod's ERANGE: an overflow (1e999, +-HUGE_VAL) is no finite number;
     * an underflow (1e-320) is a finite, subnormal one, and the range check
     * below judges it with the key's range */
    if (value[0] == '\0' || end == NULL || *end != '\0' || !isfinite(v) ||
        (errno != 0 && !(errno == ERANGE && fabs(v) < 1.0))) {
        sim_config_set_err(ctx->err, sizeof ctx->err, "key '%s.%s': '%s' is not a finite number",
                           section, name, value);
        return 0;
    }
    if (check_value(&k_keys[i], v, ctx->err, sizeof ctx->err) != 0) {
        return 0;
    }
    *field(ctx->cfg, &k_keys[i]) = v;
    ctx->seen[i] = 1;
    return 1;
}

static const key_spec_t *find_key(const char *section_dot_key)
{
    size_t i, n;
    for (i = 0; i < N_KEYS; i++) {
        n = strlen(k_keys[i].section);
        if (strncmp(section_dot_key, k_keys[i].section, n) == 0 && section_dot_key[n] == '.' &&
            strcmp(section_dot_key + n + 1, k_keys[i].key) == 0) {
            return &k_keys[i];
        }
    }
    return NULL;
}

int sim_config_set(sim_config_t *c, const char *key, double v)
{
    const key_spec_t *k = find_key(key);
    if (k == NULL) {
        return -1;
    }
    *field(c, k) = v;
    return 0;
}

/* Defaults, in the table's order: a key defaulting to another key's value
 * comes after it, so that value is final. */
static int apply_defaults(parse_ctx_t *ctx, char *err, size_t len)
{
    size_t i;
    for (i = 0; i < N_KEYS; i++) {
        const key_spec_t *k = &k_keys[i];
        if (ctx->seen[i]) {
            continue;
        }
        if (k->required && !(ctx->drive_only && strcmp(k->side, SIM) == 0)) {
            sim_config_set_err(err, len, "missing key '%s.%s' (%s)", k->section, k->key,
                               unit_of(k));
            return 1;
        }
        if (k->def_key != NULL) {
            const key_spec_t *from = find_key(k->def_key);
            double v = *field(ctx->cfg, from);
            /* the source's range may be wider than this key's */
            if (check_value(k, v, err, len) != 0) {
                size_t n = strlen(err);
                snprintf(err + n, len - n, " (its default, %s)", k->def_key);
                return 1;
            }
            *field(ctx->cfg, k) = v;
        } else {
            *field(ctx->cfg, k) = k->def;
        }
    }
    if (ctx->cfg->inverter.overcurrent_hw_A < 0.0) {
        ctx->cfg->inverter.overcurrent_hw_A =
            SIM_HW_OC_OF_TRIP * ctx->cfg->controller.overcurrent_A;
    }
    return 0;
}

static int load(const char *path, sim_config_t *cfg, int drive_only, char *err,
                size_t err_len)
{
    parse_ctx_t ctx;
    line_reader_t rd;
    int rc;
    /* a long path is shown by its end, so that the reason always fits */
    const char *shown = (strlen(path) > PATH_SHOWN) ? path + strlen(path) - PATH_SHOWN : path;
    const char *ell = (shown != path) ? "..." : "";

    memset(cfg, 0, sizeof *cfg);
    memset(&ctx, 0, sizeof ctx);
    memset(&rd, 0, sizeof rd);
    ctx.cfg = cfg;
    ctx.drive_only = drive_only;
    rd.f = fopen(path, "r");
    if (rd.f == NULL) {
        sim_config_set_err(err, err_len, "%s%s: cannot open (%s)", ell, shown, strerror(errno));
        return 1;
    }
    rc = ini_parse_stream(ini_read_line, &rd, on_key, &ctx);
    (void)fclose(rd.f);
    if (rc != 0) {
        /* an error in a line before the one the reader stopped at */
        if (ctx.err[0] != '\0') {
            sim_config_set_err(err, err_len, "%s%s:%d: %s", ell, shown, rc, ctx.err);
        } else {
            sim_config_set_err(err, err_len,
                               "%s%s:%d: malformed line (expected [section] or key = value)", ell,
                               shown, rc);
        }
        return 1;
    }
    if (rd.status == RD_TOO_LONG) {
        sim_config_set_err(err, err_len, "%s%s:%u: line longer than %d characters", ell, shown,
                           rd.line, rd.max_len);
        return 1;
    }
    if (rd.status == RD_NUL) {
        sim_config_set_err(err, err_len, "%s%s:%u: NUL byte (not a text file)", ell, shown,
                           rd.line + 1u);
        return 1;
    }
    if (rd.status == RD_SYNTAX) {
        sim_config_set_err(err, err_len, "%s%s:%u: %s", ell, shown, rd.line, rd.syntax);
        return 1;
    }
    if (rd.status == RD_ERROR) {
        sim_config_set_err(err, err_len, "%s%s: read error (%s)", ell, shown,
                           strerror(rd.err_no));
        return 1;
    }
    rc = apply_defaults(&ctx, ctx.err, sizeof ctx.err);
    if (rc == 0) {
        rc = apply_sequence(&ctx, ctx.err, sizeof ctx.err);
    }
    if (rc == 0) {
        old_layout_note(&ctx);
        rc = drive_only ? sim_config_drive_check(cfg, ctx.err, sizeof ctx.err)
                        : sim_config_cross_check(cfg, ctx.err, sizeof ctx.err);
    }
    if (rc != 0) {
        sim_config_set_err(err, err_len, "%s%s: %s", ell, shown, ctx.err);
    }
    return rc;
}

int sim_config_load(const char *path, sim_config_t *cfg, char *err, size_t err_len)
{
    return load(path, cfg, 0, err, err_len);
}

int sim_config_load_drive(const char *path, sim_config_t *cfg, char *err, size_t err_len)
{
    return load(path, cfg, 1, err, err_len);
}

void sim_config_print_keys(void)
{
    size_t i;
    const char *last = "";
    printf("Each key once: its section, unit, default (or required), range, and the side that\n"
           "reads it: drive (the firmware's drive_config_t, also written into the board's\n"
           "board_config.c), sim (the simulated world), drive+sim (the firmware's, and the\n"
           "simulator models the same with it), check (informative, checked only).  The\n"
           "drive-side ranges are drive_init's (include/drive_limits.h); the derived limits\n"
           "it enforces follow the keys.\n");
    for (i = 0; i < N_KEYS; i++) {
        const key_spec_t *k = &k_keys[i];
        const drive_limit_t *l = drive_limit_of(k);
        char range[80], def[64];
        if (strcmp(last, k->section) != 0) {
            printf("[%s]\n", k->section);
            last = k->section;
        }
        if (l != NULL) {
            sim_limit_range(range, sizeof range, l->lo, l->hi, l->open);
        } else {
            snprintf(range, sizeof range, "[%g, %g]", k->min, k->max);
        }
        if (k->required) {
            snprintf(def, sizeof def, "required");
        } else if (k->def_key != NULL) {
            snprintf(def, sizeof def, "= %s", k->def_key);
        } else if (strcmp(k->side, CHECK) == 0) {
            snprintf(def, sizeof def, "optional");
        } else {
            snprintf(def, sizeof def, "%g", k->def);
        }
        printf("  %-22s %-24s %-20s %-18s %-9s %s\n", k->key, def, unit_of(k), range, k->side,
               k->what);
    }
    printf("\n");
    sim_limits_print(stdout);
}

double sim_config_target_rpm(const sim_config_t *c)
{
    return (c->ident.target_speed_rpm == SIM_TARGET_RATED) ? c->nameplate.rated_speed_rpm
                                                           : c->ident.target_speed_rpm;
}

void sim_config_set_sequence(sim_config_t *c, sim_sequence_t seq)
{
    const double a = (seq == SIM_SEQ_ADAPTIVE) ? 1.0 : 0.0;
    const double s = (seq == SIM_SEQ_STANDSTILL) ? 1.0 : 0.0;
    c->controller.orientation = a + s;
    c->ident.standstill = a + s;
    c->ident.passes = 1.0 + a;
    c->ident.track_rr = a;
    c->ident.static_id = s;
    /* the standstill sequence needs no curve of the bridge: its lock-ins
     * ride on i_M, every phase current keeps its sign and the bridge's
     * error is a constant they reject; the compensation runs on the set
     * band.  On a large motor the curve's test (3-6 Tr a level) would be
     * most of the run: 48 s of 82 s at Tr = 0.93 s (55 kW 2-pole). */
    if (seq == SIM_SEQ_STANDSTILL) {
        c->ident.vi_test = 0.0;   /* the others leave it as it is */
    }
    c->ident.sequence = (double)seq;
}
