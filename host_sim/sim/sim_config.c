/* INI configuration of the simulator.  See sim_config.h. */
#include "sim_config.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ini.h>

#define REQ 1  /* the key must be present */
#define OPT 0  /* the key may be omitted: its default applies */

typedef struct {
    const char *section;
    const char *key;
    size_t offset;
    int required;
    double def;         /* default when optional */
    double min, max;    /* valid closed range */
    int integer;        /* the value must be a whole number */
    const char *unit;
} key_spec_t;

#define K(sec, key, field, req, def, lo, hi, integ, unit) \
    { sec, key, offsetof(sim_config_t, field), req, def, lo, hi, integ, unit }

static const key_spec_t k_keys[] = {
    /* [motor] the simulated machine */
    K("motor", "Rs_ohm", Rs_ohm, REQ, 0, 1e-4, 100, 0, "ohm"),
    K("motor", "Rr_ohm", Rr_ohm, REQ, 0, 1e-4, 100, 0, "ohm"),
    K("motor", "Lm_H", Lm_H, REQ, 0, 1e-5, 10, 0, "H"),
    K("motor", "Lls_H", Lls_H, REQ, 0, 1e-6, 1, 0, "H"),
    K("motor", "Llr_H", Llr_H, REQ, 0, 1e-6, 1, 0, "H"),
    K("motor", "pole_pairs", pole_pairs, REQ, 0, 1, 32, 1, "-"),
    K("motor", "J_kgm2", J_kgm2, REQ, 0, 1e-7, 100, 0, "kg m^2"),
    K("motor", "B_Nm_s", B_Nm_s, OPT, 0, 0, 100, 0, "N m s"),
    K("motor", "rated_power_W", rated_power_W, REQ, 0, 1, 1e6, 0, "W"),
    K("motor", "rated_voltage_V", rated_voltage_V, REQ, 0, 1, 2000, 0, "V rms line"),
    K("motor", "rated_current_A", rated_current_A, REQ, 0, 0.01, 2000, 0, "A rms"),
    K("motor", "rated_speed_rpm", rated_speed_rpm, REQ, 0, 1, 1e5, 0, "r/min"),
    K("motor", "rated_freq_Hz", rated_freq_Hz, REQ, 0, 1, 1000, 0, "Hz"),
    /* [load] */
    K("load", "const_Nm", load_const_Nm, OPT, 0, 0, 1e4, 0, "N m"),
    K("load", "prop_Nm_s", load_prop_Nm_s, OPT, 0, 0, 1e3, 0, "N m s"),
    K("load", "fan_Nm", load_fan_Nm, OPT, 0, 0, 1e4, 0, "N m at rated speed"),
    /* [inverter] */
    K("inverter", "vdc_V", vdc_V, REQ, 0, 1, 2000, 0, "V"),
    K("inverter", "source_resistance_ohm", source_resistance_ohm, OPT, 0, 0, 10, 0, "ohm"),
    K("inverter", "ripple_V", ripple_V, OPT, 0, 0, 100, 0, "V peak"),
    K("inverter", "ripple_Hz", ripple_Hz, OPT, 100, 0, 1e4, 0, "Hz"),
    K("inverter", "dead_time_s", dead_time_s, OPT, 1e-6, 0, 1e-5, 0, "s"),
    K("inverter", "device_drop_V", device_drop_V, OPT, 0.3, 0, 5, 0, "V"),
    K("inverter", "r_on_ohm", r_on_ohm, OPT, 0, 0, 1, 0, "ohm"),
    K("inverter", "dead_time_band_A", dead_time_band_A_plant, OPT, 0.1, 1e-3, 100, 0, "A"),
    /* [sensors] */
    K("sensors", "hall_full_scale_A", hall_full_scale_A, REQ, 0, 0.1, 5000, 0, "A"),
    /* residual after the production trim of the current channels; phase b
     * gets -0.6 x this (the two sensors differ) */
    K("sensors", "hall_gain_error_pct", hall_gain_error_pct, OPT, 0.1, -20, 20, 0, "%"),
    K("sensors", "hall_offset_a_A", hall_offset_a_A, OPT, 0.05, -100, 100, 0, "A"),
    K("sensors", "hall_offset_b_A", hall_offset_b_A, OPT, -0.03, -100, 100, 0, "A"),
    K("sensors", "hall_noise_A_rms", hall_noise_A_rms, OPT, 0.02, 0, 100, 0, "A rms"),
    K("sensors", "adc_noise_lsb", adc_noise_lsb, OPT, 0.5, 0, 100, 0, "LSB rms"),
    K("sensors", "vdc_full_scale_V", vdc_full_scale_V, REQ, 0, 1, 5000, 0, "V at 3.0 V"),
    K("sensors", "encoder_lines", encoder_lines, REQ, 0, 16, 16384, 1, "lines/rev"),
    K("sensors", "seed", seed, OPT, 1, 0, 4294967295.0, 1, "-"),
    /* [controller] */
    K("controller", "Rs_error_pct", ctl_Rs_error_pct, OPT, 0, -90, 900, 0, "%"),
    K("controller", "Rr_error_pct", ctl_Rr_error_pct, OPT, 0, -90, 900, 0, "%"),
    K("controller", "Lm_error_pct", ctl_Lm_error_pct, OPT, 0, -90, 900, 0, "%"),
    K("controller", "current_bw_Hz", current_bw_Hz, REQ, 0, 10, 3000, 0, "Hz"),
    K("controller", "speed_bw_Hz", speed_bw_Hz, REQ, 0, 0.1, 200, 0, "Hz"),
    K("controller", "inertia_kgm2", inertia_kgm2, REQ, 0, 1e-7, 100, 0, "kg m^2"),
    K("controller", "max_torque_current_A", max_torque_current_A, REQ, 0, 0.01, 5000, 0, "A peak"),
    K("controller", "speed_ramp_rpm_s", speed_ramp_rpm_s, REQ, 0, 1, 1e6, 0, "r/min/s"),
    K("controller", "speed_filter_Hz", speed_filter_Hz, OPT, 100, 1, 5000, 0, "Hz"),
    K("controller", "magnetizing_current_A", magnetizing_current_A, REQ, 0, 0.01, 5000, 0, "A peak"),
    K("controller", "overcurrent_A", overcurrent_A, REQ, 0, 0.01, 5000, 0, "A peak"),
    K("controller", "vdc_max_V", vdc_max_V, REQ, 0, 1, 5000, 0, "V"),
    K("controller", "vdc_min_V", vdc_min_V, REQ, 0, 1, 5000, 0, "V"),
    K("controller", "dead_time_comp", dead_time_comp, OPT, 1, 0, 1, 1, "0/1"),
    K("controller", "dead_time_band_A", dead_time_band_A, OPT, 0.1, 1e-3, 100, 0, "A"),
    K("controller", "orientation", orientation, OPT, 0, 0, 1, 1, "0 IFO, 1 flux obs."),
    /* [ident] */
    K("ident", "filter_cutoff_Hz", filter_cutoff_Hz, OPT, 10, 0.5, 500, 0, "Hz"),
    K("ident", "euler_passes", euler_passes, OPT, 10, 1, 100, 1, "-"),
    K("ident", "paper_regressor", paper_regressor, OPT, 0, 0, 1, 1, "0/1"),
    K("ident", "rls_p0", rls_p0, OPT, 1e5, 1e-3, 1e6, 0, "pu"),
    K("ident", "forgetting", forgetting, OPT, 1, 0.9, 1, 0, "-"),
    K("ident", "magnetize_s", magnetize_s, OPT, 0.3, 0.001, 100, 0, "s"),
    K("ident", "rls_tail_s", rls_tail_s, OPT, 0.3, 0, 3, 0, "s after the ramp"),
    K("ident", "target_speed_rpm", target_speed_rpm, OPT, -1, -1, 1e5, 0, "r/min (-1: rated)"),
    K("ident", "passes", ident_passes, OPT, 1, 1, 4, 1, "-"),
    K("ident", "standstill", standstill, OPT, 0, 0, 1, 1, "0/1"),
    K("ident", "track_rr", track_rr, OPT, 0, 0, 1, 1, "0/1"),
    K("ident", "track_memory_s", track_memory_s, OPT, 1.0, 0.2, 20, 0, "s"),
    /* [drift] the thermal-drift scenario (--scenario drift), times after publication */
    K("drift", "rr_rise_pct", drift_rr_rise_pct, OPT, 40, 0, 100, 0, "% of motor.Rr_ohm"),
    K("drift", "ramp_s", drift_ramp_s, OPT, 60, 1, 600, 0, "s"),
    K("drift", "start_s", drift_start_s, OPT, 2, 0, 60, 0, "s after RUN"),
    K("drift", "load_period_s", drift_load_period_s, OPT, 5, 0.5, 60, 0, "s per load level"),
    /* [simulation] */
    K("simulation", "pwm_freq_Hz", pwm_freq_Hz, OPT, 15000, 1000, 50000, 0, "Hz"),
    K("simulation", "sysclk_Hz", sysclk_Hz, OPT, 150e6, 1e6, 1e9, 0, "Hz"),
    K("simulation", "substeps", substeps, OPT, 4, 1, 64, 1, "RK4 steps per PWM period"),
};

#define N_KEYS (sizeof k_keys / sizeof k_keys[0])

typedef struct {
    sim_config_t *cfg;
    unsigned char seen[N_KEYS];
    char err[SIM_CONFIG_ERR_LEN];
} parse_ctx_t;

static void set_err(char *buf, size_t len, const char *fmt, ...)
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
        set_err(ctx->err, sizeof ctx->err, "unknown section [%s]", section);
        return 0;
    }
    for (i = 0; i < N_KEYS; i++) {
        if (strcmp(k_keys[i].section, section) == 0 && strcmp(k_keys[i].key, name) == 0) {
            break;
        }
    }
    if (i == N_KEYS) {
        set_err(ctx->err, sizeof ctx->err, "unknown key '%s' in [%s]", name, section);
        return 0;
    }
    if (ctx->seen[i]) {
        set_err(ctx->err, sizeof ctx->err, "key '%s.%s' given twice", section, name);
        return 0;
    }
    errno = 0;
    v = strtod(value, &end);
    while (end != NULL && (*end == ' ' || *end == '\t')) {
        end++;
    }
    if (value[0] == '\0' || end == NULL || *end != '\0' || errno != 0 || !isfinite(v)) {
        set_err(ctx->err, sizeof ctx->err, "key '%s.%s': '%s' is not a finite number",
                section, name, value);
        return 0;
    }
    if (v < k_keys[i].min || v > k_keys[i].max) {
        set_err(ctx->err, sizeof ctx->err, "key '%s.%s' = %g %s is outside [%g, %g]", section,
                name, v, k_keys[i].unit, k_keys[i].min, k_keys[i].max);
        return 0;
    }
    if (k_keys[i].integer && v != floor(v)) {
        set_err(ctx->err, sizeof ctx->err, "key '%s.%s' = %g must be a whole number", section,
                name, v);
        return 0;
    }
    *field(ctx->cfg, &k_keys[i]) = v;
    ctx->seen[i] = 1;
    return 1;
}

/* Peak phase voltage the motor needs at rated speed with the magnetising
 * current and the rest of the rated current as torque current (steady state
 * in the rotor-flux frame: u_d = Rs i_d - w sigma Ls i_q, u_q = Rs i_q + w Ls i_d). */
static double rated_voltage_need_V(const sim_config_t *c)
{
    double Ls = c->Lm_H + c->Lls_H, Lr = c->Lm_H + c->Llr_H;
    double sigma = 1.0 - c->Lm_H * c->Lm_H / (Ls * Lr);
    double w = 2.0 * M_PI * c->rated_speed_rpm / 60.0 * c->pole_pairs;
    double ipk = sqrt(2.0) * c->rated_current_A;
    double id = c->magnetizing_current_A;
    double iq = (ipk > id) ? sqrt(ipk * ipk - id * id) : 0.0;
    double ud = c->Rs_ohm * id - w * sigma * Ls * iq;
    double uq = c->Rs_ohm * iq + w * Ls * id;
    return sqrt(ud * ud + uq * uq);
}

/* The adaptation and tracking features work in the observer's frame only
 * (drive_config.h): with indirect orientation the drive would refuse them,
 * so the file is refused first, naming the key. */
static int check_observer_features(const sim_config_t *c, char *err, size_t len)
{
    /* each key, its value, and the value that keeps the paper's sequence */
    const char *const key[3] = {"ident.passes", "ident.standstill", "ident.track_rr"};
    const double v[3] = {c->ident_passes, c->standstill, c->track_rr};
    const double paper[3] = {1.0, 0.0, 0.0};
    unsigned i;
    if (c->orientation == 1.0) {
        return 0;
    }
    for (i = 0; i < 3u; i++) {
        if (v[i] != paper[i]) {
            set_err(err, len, "key '%s' = %g needs controller.orientation = 1 (rotor-flux "
                    "observer)", key[i], v[i]);
            return 1;
        }
    }
    return 0;
}

static int cross_check(const sim_config_t *c, char *err, size_t len)
{
    double ipk = sqrt(2.0) * c->rated_current_A;
    double vmax_phase = c->vdc_V / sqrt(3.0);
    double need;
    /* (a believed Lm above the true Ls is a wrong nameplate, not an
     * unphysical model: the believed Ls = believed Lm + Lls stays above it,
     * sim_config_to_drive; issue 8 sweeps Lm +30 % on motors whose leakage
     * is 3 % of Lm) */
    if (c->magnetizing_current_A >= ipk) {
        set_err(err, len, "key 'controller.magnetizing_current_A' = %g A must be below the rated "
                "peak current %g A", c->magnetizing_current_A, ipk);
        return 1;
    }
    if (c->max_torque_current_A > c->overcurrent_A) {
        set_err(err, len, "key 'controller.max_torque_current_A' exceeds controller.overcurrent_A");
        return 1;
    }
    if (c->overcurrent_A >= c->hall_full_scale_A) {
        set_err(err, len, "key 'controller.overcurrent_A' = %g A must be below the sensor full "
                "scale sensors.hall_full_scale_A = %g A", c->overcurrent_A, c->hall_full_scale_A);
        return 1;
    }
    if (!(c->vdc_min_V < c->vdc_V && c->vdc_V < c->vdc_max_V)) {
        set_err(err, len, "key 'inverter.vdc_V' = %g V must lie between controller.vdc_min_V and "
                "controller.vdc_max_V", c->vdc_V);
        return 1;
    }
    if (c->vdc_max_V >= c->vdc_full_scale_V) {
        set_err(err, len, "key 'controller.vdc_max_V' must be below sensors.vdc_full_scale_V");
        return 1;
    }
    need = rated_voltage_need_V(c);
    if (need > 0.95 * vmax_phase) {
        set_err(err, len, "key 'inverter.vdc_V' = %g V is too low for rated speed: the motor needs "
                "%.1f V peak per phase, the bus gives %.1f V (with 5 %% margin)", c->vdc_V, need,
                0.95 * vmax_phase);
        return 1;
    }
    if (c->target_speed_rpm > 1.2 * c->rated_speed_rpm) {
        set_err(err, len, "key 'ident.target_speed_rpm' is above 1.2 x rated speed");
        return 1;
    }
    if (c->magnetize_s < 5.0 * (c->Lm_H + c->Llr_H) / c->Rr_ohm) {
        set_err(err, len, "key 'ident.magnetize_s' = %g s is shorter than 5 Tr = %g s",
                c->magnetize_s, 5.0 * (c->Lm_H + c->Llr_H) / c->Rr_ohm);
        return 1;
    }
    return check_observer_features(c, err, len);
}

/* Line reader for inih (ini_parse_stream).  inih's own reader is fgets into
 * a buffer of INI_MAX_LINE characters: it splits a longer line and parses
 * the rest as a line of its own (the tail of a long comment could become a
 * key), a NUL byte silently ends a line, and a read error (a directory given
 * as the file) looks like an empty file.  This reader stops at each of these
 * and says which, so that sim_config_load reports it. */
/* Characters of the file's path shown in a message (SIM_CONFIG_ERR_LEN 256). */
#define PATH_SHOWN 96

typedef enum { RD_OK = 0, RD_TOO_LONG, RD_NUL, RD_ERROR } read_status_t;

typedef struct {
    FILE *f;
    unsigned line;          /* lines handed to inih so far */
    int max_len;            /* longest line inih accepts, characters */
    read_status_t status;
    int err_no;             /* errno of a read error */
} line_reader_t;

static char *read_line(char *str, int num, void *stream)
{
    line_reader_t *r = (line_reader_t *)stream;
    int n = 0, c = 0;

    if (r->status != RD_OK || num < 2) {
        return NULL;
    }
    r->max_len = num - 1;
    while (n < num - 1) {
        c = getc(r->f);
        if (c == EOF || c == '\n') {
            break;
        }
        if (c == '\0') {
            r->status = RD_NUL;
            return NULL;
        }
        str[n++] = (char)c;
    }
    if (n == num - 1 && c != '\n' && c != EOF) {
        /* the buffer is full: the line must end right here */
        c = getc(r->f);
        if (c != '\n' && c != EOF) {
            r->line++;
            r->status = RD_TOO_LONG;
            return NULL;
        }
    }
    if (c == EOF && ferror(r->f)) {
        r->err_no = errno;
        r->status = RD_ERROR;
        return NULL;
    }
    if (c == EOF && n == 0) {
        return NULL;    /* end of file */
    }
    r->line++;
    str[n] = '\0';
    return str;
}

int sim_config_load(const char *path, sim_config_t *cfg, char *err, size_t err_len)
{
    parse_ctx_t ctx;
    line_reader_t rd;
    size_t i;
    int rc;
    /* a long path is shown by its end, so that the reason always fits */
    const char *shown = (strlen(path) > PATH_SHOWN) ? path + strlen(path) - PATH_SHOWN : path;
    const char *ell = (shown != path) ? "..." : "";

    memset(cfg, 0, sizeof *cfg);
    memset(&ctx, 0, sizeof ctx);
    memset(&rd, 0, sizeof rd);
    ctx.cfg = cfg;
    rd.f = fopen(path, "r");
    if (rd.f == NULL) {
        set_err(err, err_len, "%s%s: cannot open (%s)", ell, shown, strerror(errno));
        return 1;
    }
    rc = ini_parse_stream(read_line, &rd, on_key, &ctx);
    (void)fclose(rd.f);
    if (rc != 0) {
        /* an error in a line before the one the reader stopped at */
        if (ctx.err[0] != '\0') {
            set_err(err, err_len, "%s%s:%d: %s", ell, shown, rc, ctx.err);
        } else {
            set_err(err, err_len, "%s%s:%d: malformed line (expected [section] or key = value)",
                    ell, shown, rc);
        }
        return 1;
    }
    if (rd.status == RD_TOO_LONG) {
        set_err(err, err_len, "%s%s:%u: line longer than %d characters", ell, shown, rd.line,
                rd.max_len);
        return 1;
    }
    if (rd.status == RD_NUL) {
        set_err(err, err_len, "%s%s:%u: NUL byte (not a text file)", ell, shown, rd.line + 1u);
        return 1;
    }
    if (rd.status == RD_ERROR) {
        set_err(err, err_len, "%s%s: read error (%s)", ell, shown, strerror(rd.err_no));
        return 1;
    }
    for (i = 0; i < N_KEYS; i++) {
        if (!ctx.seen[i]) {
            if (k_keys[i].required) {
                set_err(err, err_len, "%s%s: missing key '%s.%s' (%s)", ell, shown,
                        k_keys[i].section, k_keys[i].key, k_keys[i].unit);
                return 1;
            }
            *field(cfg, &k_keys[i]) = k_keys[i].def;
        }
    }
    if (cfg->target_speed_rpm < 0.0) {
        cfg->target_speed_rpm = cfg->rated_speed_rpm;
    }
    if (cross_check(cfg, ctx.err, sizeof ctx.err) != 0) {
        set_err(err, err_len, "%s%s: %s", ell, shown, ctx.err);
        return 1;
    }
    return 0;
}

void sim_config_to_drive(const sim_config_t *c, drive_config_t *d)
{
    double Rs = c->Rs_ohm * (1.0 + c->ctl_Rs_error_pct / 100.0);
    double Rr = c->Rr_ohm * (1.0 + c->ctl_Rr_error_pct / 100.0);
    double Lm = c->Lm_H * (1.0 + c->ctl_Lm_error_pct / 100.0);
    /* the leakages are kept: a wrong Lm moves Ls and Lr with it */
    double Ls = Lm + c->Lls_H, Lr = Lm + c->Llr_H;

    memset(d, 0, sizeof *d);
    d->motor.Rs_ohm = (float)Rs;
    d->motor.Rr_ohm = (float)Rr;
    d->motor.Lm_H = (float)Lm;
    d->motor.Ls_H = (float)Ls;
    d->motor.Lr_H = (float)Lr;
    d->motor.pole_pairs = (uint16_t)c->pole_pairs;
    d->motor.rated_speed_rpm = (float)c->rated_speed_rpm;
    d->motor.rated_current_A_rms = (float)c->rated_current_A;
    d->motor.rated_freq_Hz = (float)c->rated_freq_Hz;
    d->motor.magnetizing_current_A = (float)c->magnetizing_current_A;

    d->board.sysclk_Hz = (float)c->sysclk_Hz;
    d->board.pwm_freq_Hz = (float)c->pwm_freq_Hz;
    d->board.dead_time_s = (float)c->dead_time_s;
    d->board.device_drop_V = (float)c->device_drop_V;
    d->board.dead_time_comp = (uint16_t)c->dead_time_comp;
    d->board.dead_time_band_A = (float)c->dead_time_band_A;
    d->board.vdc_nominal_V = (float)c->vdc_V;
    d->board.vdc_adc_full_scale_V = (float)c->vdc_full_scale_V;
    d->board.current_full_scale_A = (float)c->hall_full_scale_A;
    d->board.encoder_lines = (uint16_t)c->encoder_lines;
    d->board.overcurrent_A = (float)c->overcurrent_A;
    d->board.vdc_max_V = (float)c->vdc_max_V;
    d->board.vdc_min_V = (float)c->vdc_min_V;

    d->control.current_bw_Hz = (float)c->current_bw_Hz;
    d->control.speed_bw_Hz = (float)c->speed_bw_Hz;
    d->control.inertia_kgm2 = (float)c->inertia_kgm2;
    d->control.max_torque_current_A = (float)c->max_torque_current_A;
    d->control.speed_ramp_rpm_s = (float)c->speed_ramp_rpm_s;
    d->control.speed_filter_Hz = (float)c->speed_filter_Hz;
    d->control.orientation = (uint16_t)c->orientation;

    d->ident.filter_wc_rad_s = (float)(2.0 * M_PI * c->filter_cutoff_Hz);
    d->ident.euler_passes = (uint16_t)c->euler_passes;
    d->ident.paper_regressor = (uint16_t)c->paper_regressor;
    d->ident.rls_p0 = (float)c->rls_p0;
    d->ident.forgetting = (float)c->forgetting;
    d->ident.magnetize_time_s = (float)c->magnetize_s;
    d->ident.target_speed_rpm = (float)c->target_speed_rpm;
    d->ident.rls_tail_s = (float)c->rls_tail_s;
    d->ident.passes = (uint16_t)c->ident_passes;
    d->ident.standstill = (uint16_t)c->standstill;
    d->ident.track_rr = (uint16_t)c->track_rr;
    d->ident.track_memory_s = (float)c->track_memory_s;
}

void sim_config_print_keys(void)
{
    size_t i;
    const char *last = "";
    for (i = 0; i < N_KEYS; i++) {
        const key_spec_t *k = &k_keys[i];
        if (strcmp(last, k->section) != 0) {
            printf("[%s]\n", k->section);
            last = k->section;
        }
        if (k->required) {
            printf("  %-24s required   %-22s range [%g, %g]\n", k->key, k->unit, k->min, k->max);
        } else {
            printf("  %-24s default %-8g %-18s range [%g, %g]\n", k->key, k->def, k->unit,
                   k->min, k->max);
        }
    }
}
