/* The table of the drive's configuration limits.  See drive_limits.h.
 *
 * A derived limit that is a module's own argument check asks that module:
 * its x_check (dc_bus_check, qep_speed_check, pi_check, ifo_check, ...)
 * is the one its x_init calls, on the arguments drive_init gives it, so
 * that a configuration this table accepts is one drive_init accepts and no
 * limit is written twice; a module whose check covers several entries is
 * asked which of its arguments it refuses, and each entry refuses only its
 * own.  The rules of the drive itself (the PWM period in counts, i_M below
 * the rated peak, the target speed, ...) are written here.  The numbers
 * reported with a failure are the limit said in the user's units.  Float:
 * initialisation only. */
#include "drive_limits.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "bw_filter.h"
#include "dc_bus.h"
#include "drive.h"
#include "drive_adapt.h"
#include "drive_static.h"
#include "drive_design.h"
#include "drive_target.h"
#include "drive_vi.h"
#include "encoder_check.h"
#include "flux_obs.h"
#include "ident_regressor.h"
#include "ifo.h"
#include "param_extract.h"
#include "pi_ctrl.h"
#include "protect.h"
#include "qep_speed.h"
#include "ramp_gen.h"
#include "theta_guard.h"
#include "volt_calc.h"

#define LO_OPEN DRIVE_LIMIT_LO_OPEN
#define HI_OPEN DRIVE_LIMIT_HI_OPEN
#define BOTH_OPEN (DRIVE_LIMIT_LO_OPEN | DRIVE_LIMIT_HI_OPEN)

/* Constants of other modules that are not in their headers; used here only
 * to say a limit in the user's units (the checks are the modules' own). */
#define Q24_HEADROOM 127.0f        /* a pu value converted to Q24 (< 128) */
#define NO_UPPER FLT_MAX           /* a limit with a lower bound only */

/* The identification's target speed (drive_limits.h, DRIVE_LD_TARGET): at
 * least drive_target_least_rpm (drive_target.c says why each floor), at most
 * TARGET_MAX_OF_RATED of the rated speed; and the bus must carry its
 * no-load voltage (DRIVE_LD_BUS: drive_target.h). */
#define TARGET_MAX_OF_RATED 1.2f

/* The dead time against the voltage the identification runs on
 * (DRIVE_LD_HEADROOM): what the bridge loses per leg, vdc td f_pwm + the
 * device drop, at most HEADROOM_LOSS_OF_VOLTAGE of the believed motor's
 * no-load phase voltage at the target speed, |Rs i_M + j w Ls i_M| (w: the
 * target's electrical speed; no load current: a nameplate 30 % off moves it
 * by at most 30 %, and the adaptive sequence starts from such nameplates).
 * The drive compensates the loss in its duties and reconstructs it in the
 * regression's voltage: beyond the limit the compensated reference leaves
 * the modulator's linear range once the motor is loaded, and what is left of
 * the compensation's error reaches the regression.  Measured on the paper
 * motor (60 V, 15 kHz, rated-speed target, no-load voltage 18.9 V): the
 * published set stays within 1.5 % up to 30 % (6 us: 5.7 V; 2 us at 50 kHz,
 * 33 %: 1.3 %), and leaves it beyond: 8 us (40 %) Tr -5.1 %, 10 us (49 %)
 * Rr +21 %, 5 us at 50 kHz (81 %) Rr +121 %, the modulator clipping from
 * the middle of the acceleration on. */
#define HEADROOM_LOSS_OF_VOLTAGE 0.3f

#define ST(s) ((int16_t)(s))
#define FIELD_F(key, member, unit, st, lo, hi)                                                   \
    { DRIVE_LT(key), DRIVE_LT(unit), ST(st), DRIVE_LIMIT_F32, (uint16_t)offsetof(drive_config_t, member), 0u,   \
      lo, hi }
#define FIELD_U(key, member, unit, st, lo, hi)                                                   \
    { DRIVE_LT(key), DRIVE_LT(unit), ST(st), DRIVE_LIMIT_U16, (uint16_t)offsetof(drive_config_t, member), 0u,    \
      lo, hi }
#define DERIVED(key, unit, st, which) \
    { DRIVE_LT(key), DRIVE_LT(unit), ST(st), DRIVE_LIMIT_DERIVED, which, 0u, 1.0f, 0.0f }
#define DERIVED_RANGE(key, unit, st, which, open, lo, hi) \
    { DRIVE_LT(key), DRIVE_LT(unit), ST(st), DRIVE_LIMIT_DERIVED, which, open, lo, hi }

static const drive_limit_t k_limits[] = {
    /* every field: the bases first (the derived limits below need them) */
    FIELD_F("board.pwm_freq_Hz", board.pwm_freq_Hz, "Hz", DRIVE_CFG_BASES, 1000.0f, 50000.0f),
    FIELD_F("board.sysclk_Hz", board.sysclk_Hz, "Hz", DRIVE_CFG_BASES, 1.0e6f, 1.0e9f),
    FIELD_F("board.current_full_scale_A", board.current_full_scale_A, "A", DRIVE_CFG_BASES,
            0.1f, 5000.0f),
    FIELD_F("board.vdc_nominal_V", board.vdc_nominal_V, "V", DRIVE_CFG_BASES, 1.0f, 2000.0f),
    FIELD_F("nameplate.rated_freq_Hz", motor.rated_freq_Hz, "Hz", DRIVE_CFG_BASES, 1.0f,
            1000.0f),
    FIELD_U("nameplate.pole_pairs", motor.pole_pairs, "-", DRIVE_CFG_BASES, 1.0f, 32.0f),
    /* up to 1000 ohm: small motors at 575-690 V (0.2 kW: Rr 104 ohm); their
     * per-unit values are checked by the derived limits below */
    FIELD_F("nameplate.Rs_ohm", motor.Rs_ohm, "ohm", DRIVE_CFG_MOTOR, 1.0e-4f, 1000.0f),
    FIELD_F("nameplate.Rr_ohm", motor.Rr_ohm, "ohm", DRIVE_CFG_MOTOR, 1.0e-4f, 1000.0f),
    FIELD_F("nameplate.Lm_H", motor.Lm_H, "H", DRIVE_CFG_MOTOR, 1.0e-5f, 10.0f),
    FIELD_F("nameplate.rated_speed_rpm", motor.rated_speed_rpm, "r/min", DRIVE_CFG_MOTOR, 1.0f,
            1.0e5f),
    FIELD_F("nameplate.rated_current_A", motor.rated_current_A_rms, "A rms", DRIVE_CFG_MOTOR,
            0.01f, 2000.0f),
    FIELD_F("controller.magnetizing_current_A", motor.magnetizing_current_A, "A peak",
            DRIVE_CFG_MOTOR, 0.01f, 5000.0f),
    FIELD_F("board.vdc_full_scale_V", board.vdc_adc_full_scale_V, "V at 3.0 V", DRIVE_CFG_SENSORS,
            1.0f, 5000.0f),
    FIELD_U("board.encoder_lines", board.encoder_lines, "lines", DRIVE_CFG_SENSORS, 16.0f,
            (float)QEP_SPEED_LINES_MAX),
    FIELD_F("controller.speed_filter_Hz", control.speed_filter_Hz, "Hz", DRIVE_CFG_SENSORS, 1.0f,
            5000.0f),
    FIELD_F("controller.current_bw_Hz", control.current_bw_Hz, "Hz", DRIVE_CFG_CURRENT_LOOP,
            10.0f, 3000.0f),
    FIELD_F("controller.speed_bw_Hz", control.speed_bw_Hz, "Hz", DRIVE_CFG_SPEED_LOOP, 0.1f,
            200.0f),
    FIELD_F("controller.inertia_kgm2", control.inertia_kgm2, "kg m^2", DRIVE_CFG_SPEED_LOOP,
            1.0e-7f, 100.0f),
    FIELD_F("controller.max_torque_current_A", control.max_torque_current_A, "A peak",
            DRIVE_CFG_SPEED_LOOP, 0.01f, 5000.0f),
    FIELD_F("controller.speed_ramp_rpm_s", control.speed_ramp_rpm_s, "r/min/s",
            DRIVE_CFG_SPEED_LOOP, 1.0f, 1.0e6f),
    FIELD_U("controller.orientation", control.orientation, "0 IFO, 1 observer",
            DRIVE_CFG_ORIENTATION, 0.0f, 1.0f),
    FIELD_F("board.dead_time_s", board.dead_time_s, "s", DRIVE_CFG_VOLTAGE_MODEL, 0.0f, 1.0e-5f),
    FIELD_F("board.device_drop_V", board.device_drop_V, "V", DRIVE_CFG_VOLTAGE_MODEL, 0.0f, 5.0f),
    FIELD_U("controller.dead_time_comp", board.dead_time_comp, "0/1", DRIVE_CFG_VOLTAGE_MODEL,
            0.0f, 1.0f),
    FIELD_F("board.dead_time_band_A", board.dead_time_band_A, "A", DRIVE_CFG_VOLTAGE_MODEL,
            1.0e-3f, 100.0f),
    FIELD_U("ident.euler_passes", ident.euler_passes, "-", DRIVE_CFG_IDENT, 1.0f,
            (float)BW_FILTER_N_MAX),
    FIELD_U("ident.paper_regressor", ident.paper_regressor, "0/1", DRIVE_CFG_IDENT, 0.0f, 1.0f),
    FIELD_U("ident.period_mean", ident.period_mean, "0/1", DRIVE_CFG_IDENT, 0.0f, 1.0f),
    FIELD_F("ident.rls_p0", ident.rls_p0, "pu", DRIVE_CFG_IDENT, 1.0e-3f, 1.0e6f),
    FIELD_F("ident.forgetting", ident.forgetting, "-", DRIVE_CFG_IDENT, 0.9f, 1.0f),
    FIELD_U("ident.passes", ident.passes, "-", DRIVE_CFG_IDENT, 1.0f, (float)ID_PASSES_MAX),
    FIELD_U("ident.standstill", ident.standstill, "0/1", DRIVE_CFG_IDENT, 0.0f, 1.0f),
    FIELD_U("ident.vi_test", ident.vi_test, "0/1", DRIVE_CFG_VOLTAGE_MODEL, 0.0f, 1.0f),
    FIELD_U("ident.track_rr", ident.track_rr, "0/1", DRIVE_CFG_IDENT, 0.0f, 1.0f),
    FIELD_U("ident.static_id", ident.static_id, "0/1", DRIVE_CFG_IDENT, 0.0f, 1.0f),
    FIELD_F("ident.track_memory_s", ident.track_memory_s, "s", DRIVE_CFG_IDENT, 0.2f, 20.0f),
    FIELD_F("ident.magnetize_s", ident.magnetize_time_s, "s", DRIVE_CFG_SEQUENCE, 0.001f, 100.0f),
    FIELD_F("ident.target_speed_rpm", ident.target_speed_rpm, "r/min (0: rated)",
            DRIVE_CFG_SEQUENCE, 0.0f, 1.0e5f),
    FIELD_F("ident.rls_tail_s", ident.rls_tail_s, "s", DRIVE_CFG_SEQUENCE, 0.0f, 3.0f),
    FIELD_F("controller.overcurrent_A", board.overcurrent_A, "A peak", DRIVE_CFG_PROTECTION,
            0.01f, 5000.0f),
    FIELD_F("controller.vdc_max_V", board.vdc_max_V, "V", DRIVE_CFG_PROTECTION, 1.0f, 5000.0f),
    FIELD_F("controller.vdc_min_V", board.vdc_min_V, "V", DRIVE_CFG_PROTECTION, 1.0f, 5000.0f),

    /* derived, in drive_init's order (host_sim/sim/sim_limits.c says each in words) */
    DERIVED_RANGE("nameplate.Lls_H", "H", DRIVE_CFG_MOTOR, DRIVE_LD_LLS, 0u, 1.0e-6f, 1.0f),
    DERIVED_RANGE("nameplate.Llr_H", "H", DRIVE_CFG_MOTOR, DRIVE_LD_LLR, 0u, 1.0e-6f, 1.0f),
    DERIVED("controller.magnetizing_current_A", "A", DRIVE_CFG_MOTOR, DRIVE_LD_IM_RATED),
    DERIVED_RANGE("T1PR", "counts", DRIVE_CFG_PWM, DRIVE_LD_T1PR, 0u, 100.0f, 65535.0f),
    DERIVED("board.vdc_full_scale_V", "V", DRIVE_CFG_SENSORS, DRIVE_LD_VDC_FS),
    DERIVED("board.encoder_lines", "lines", DRIVE_CFG_SENSORS, DRIVE_LD_QEP_RES),
    DERIVED("controller.speed_filter_Hz", "Hz", DRIVE_CFG_SENSORS, DRIVE_LD_SPEED_FILT),
    DERIVED("Ls", "H", DRIVE_CFG_CURRENT_LOOP, DRIVE_LD_LS_Q24),
    DERIVED("Lr", "H", DRIVE_CFG_CURRENT_LOOP, DRIVE_LD_LR_Q24),
    DERIVED("controller.current_bw_Hz", "Hz", DRIVE_CFG_CURRENT_LOOP, DRIVE_LD_WC_PU),
    DERIVED_RANGE("current-loop Kp", "pu", DRIVE_CFG_CURRENT_LOOP, DRIVE_LD_CUR_KP,
                  0u, 0.0f, PI_KP_MAX),
    DERIVED_RANGE("current-loop Ki", "pu", DRIVE_CFG_CURRENT_LOOP, DRIVE_LD_CUR_KI,
                  0u, 0.0f, PI_KI_MAX),
    DERIVED("controller.max_torque_current_A", "A", DRIVE_CFG_SPEED_LOOP, DRIVE_LD_IMAX),
    DERIVED_RANGE("speed-loop Kp", "pu", DRIVE_CFG_SPEED_LOOP, DRIVE_LD_SPD_KP,
                  0u, 0.0f, PI_KP_MAX),
    DERIVED_RANGE("speed-loop Ki", "pu", DRIVE_CFG_SPEED_LOOP, DRIVE_LD_SPD_KI,
                  0u, 0.0f, PI_KI_MAX),
    DERIVED("controller.speed_ramp_rpm_s", "r/min/s", DRIVE_CFG_SPEED_LOOP, DRIVE_LD_RAMP),
    DERIVED("controller.magnetizing_current_A", "A", DRIVE_CFG_ORIENTATION, DRIVE_LD_IMR),
    DERIVED("Tr", "s", DRIVE_CFG_ORIENTATION, DRIVE_LD_TR),
    DERIVED_RANGE("board.pwm_freq_Hz / nameplate.rated_freq_Hz", "-", DRIVE_CFG_ORIENTATION,
                  DRIVE_LD_FTS, BOTH_OPEN, 128.0f, 2000.0f),
    DERIVED_RANGE("slip bound", "pu", DRIVE_CFG_ORIENTATION, DRIVE_LD_SLIP,
                  0u, 1.0f / 32.0f, NO_UPPER),
    DERIVED("nameplate.rated_freq_Hz", "Hz", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_FBASE),
    DERIVED("board.pwm_freq_Hz", "Hz", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_PWM),
    DERIVED("nameplate.Rs_ohm", "ohm", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_RS),
    DERIVED("nameplate.Lm_H", "H", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_LM),
    DERIVED("Lr / Lm", "-", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_LR),
    DERIVED("Ls", "H", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_LS),
    DERIVED("sigma Ls", "H", DRIVE_CFG_ORIENTATION, DRIVE_LD_OBS_SLS),
    DERIVED("board.dead_time_s", "s", DRIVE_CFG_VOLTAGE_MODEL, DRIVE_LD_DEAD),
    DERIVED("board.device_drop_V", "V", DRIVE_CFG_VOLTAGE_MODEL, DRIVE_LD_DROP),
    DERIVED("ident.vi_test", "s", DRIVE_CFG_VOLTAGE_MODEL, DRIVE_LD_VI_HOLD),
    DERIVED("nameplate.Rs_ohm", "pu", DRIVE_CFG_VOLTAGE_MODEL, DRIVE_LD_VI_GAINS),
    DERIVED("board.dead_time_band_A", "A", DRIVE_CFG_VOLTAGE_MODEL, DRIVE_LD_BAND),
    DERIVED_RANGE("ident.filter_cutoff_Hz", "Hz", DRIVE_CFG_IDENT, DRIVE_LD_FILT, 0u, 0.5f, 500.0f),
    DERIVED("ident.filter_cutoff_Hz", "Hz", DRIVE_CFG_IDENT, DRIVE_LD_FILT_WB),
    DERIVED("ident.filter_cutoff_Hz", "Hz", DRIVE_CFG_IDENT, DRIVE_LD_FILT_STEP),
    DERIVED_RANGE("nominal -K1", "pu", DRIVE_CFG_IDENT, DRIVE_LD_K1,
                  BOTH_OPEN, 0.0f, RLS_THETA_MAX),
    DERIVED_RANGE("nominal K2", "pu", DRIVE_CFG_IDENT, DRIVE_LD_K2, BOTH_OPEN, 0.0f, RLS_THETA_MAX),
    DERIVED_RANGE("nominal K3", "pu", DRIVE_CFG_IDENT, DRIVE_LD_K3, BOTH_OPEN, 0.0f, RLS_THETA_MAX),
    DERIVED_RANGE("nominal -K4", "pu", DRIVE_CFG_IDENT, DRIVE_LD_K4,
                  BOTH_OPEN, 0.0f, RLS_THETA_MAX),
    DERIVED("nameplate.Rs_ohm", "ohm", DRIVE_CFG_IDENT, DRIVE_LD_PE_RS),
    DERIVED("nameplate.Rr_ohm", "ohm", DRIVE_CFG_IDENT, DRIVE_LD_PE_RR),
    DERIVED("nameplate.Lm_H", "H", DRIVE_CFG_IDENT, DRIVE_LD_PE_LM),
    DERIVED("Lr", "H", DRIVE_CFG_IDENT, DRIVE_LD_PE_LR),
    DERIVED("rated flux", "Wb", DRIVE_CFG_IDENT, DRIVE_LD_PE_PSI),
    DERIVED_RANGE("controller.orientation", "-", DRIVE_CFG_IDENT, DRIVE_LD_FEATURES,
                  0u, 1.0f, 1.0f),
    DERIVED("ident.standstill", "-", DRIVE_CFG_IDENT, DRIVE_LD_STANDSTILL),
    DERIVED("ident.track_rr", "-", DRIVE_CFG_IDENT, DRIVE_LD_TRACKER),
    DERIVED("ident.static_id", "-", DRIVE_CFG_IDENT, DRIVE_LD_STATIC),
    DERIVED_RANGE("ident.period_mean", "-", DRIVE_CFG_IDENT, DRIVE_LD_PERIOD_MEAN, 0u, 0.0f,
                  0.0f),
    DERIVED("ident.target_speed_rpm", "r/min", DRIVE_CFG_SEQUENCE, DRIVE_LD_TARGET),
    DERIVED("ident.target_speed_rpm", "r/min", DRIVE_CFG_SEQUENCE, DRIVE_LD_TARGET_PU),
    DERIVED("board.vdc_nominal_V", "V", DRIVE_CFG_SEQUENCE, DRIVE_LD_BUS),
    DERIVED("board.dead_time_s", "s", DRIVE_CFG_VOLTAGE_MODEL, DRIVE_LD_HEADROOM),
    DERIVED("controller.overcurrent_A", "A", DRIVE_CFG_PROTECTION, DRIVE_LD_OC_FS),
    DERIVED("controller.max_torque_current_A", "A", DRIVE_CFG_PROTECTION, DRIVE_LD_TORQUE_OC),
    DERIVED("controller.vdc_min_V", "V", DRIVE_CFG_PROTECTION, DRIVE_LD_VDC_MIN),
    DERIVED("controller.vdc_max_V", "V", DRIVE_CFG_PROTECTION, DRIVE_LD_VDC_MAX),
    DERIVED("board.encoder_lines", "lines", DRIVE_CFG_PROTECTION, DRIVE_LD_ENC_JUMP),
};

#define N_LIMITS ((uint16_t)(sizeof k_limits / sizeof k_limits[0]))

/* What the derived limits are computed from. */
typedef struct {
    const drive_config_t *c;
    base_values_t b;
    drive_design_t g;
} limit_ctx_t;

uint16_t drive_limits_count(void)
{
    return N_LIMITS;
}

const drive_limit_t *drive_limit_get(uint16_t i)
{
    return (i < N_LIMITS) ? &k_limits[i] : NULL;
}

const drive_limit_t *drive_limit_find(const char *key)
{
    uint16_t i;
    for (i = 0u; i < N_LIMITS; i++) {
        if (strcmp(k_limits[i].key, key) == 0) {
            return &k_limits[i];
        }
    }
    return NULL;
}

static int16_t in_range(float x, float lo, float hi, uint16_t open)
{
    int16_t above = (int16_t)(((open & LO_OPEN) != 0u) ? (x > lo) : (x >= lo));
    int16_t below = (int16_t)(((open & HI_OPEN) != 0u) ? (x < hi) : (x <= hi));
    return (int16_t)(above != 0 && below != 0);
}

int16_t drive_limit_field_ok(const drive_limit_t *l, float v)
{
    return in_range(v, l->lo, l->hi, l->open);
}

static float field_value(const drive_config_t *c, const drive_limit_t *l)
{
    const char *p = (const char *)(const void *)c + l->where;
    if (l->kind == DRIVE_LIMIT_U16) {
        return (float)*(const uint16_t *)(const void *)p;
    }
    return *(const float *)(const void *)p;
}

/* A failed derived limit as the user reads it; returns 1 (failed). */
static int16_t report(drive_limit_fail_t *f, float value, float lo, float hi, uint16_t open)
{
    f->value = value;
    f->lo = lo;
    f->hi = hi;
    f->open = open;
    return 1;
}

/* The same, for a derived limit whose fault lies with another key. */
static int16_t report_as(drive_limit_fail_t *f, const char *key, const char *unit, float value,
                         float lo, float hi, uint16_t open)
{
    f->key = key;
    f->unit = unit;
    return report(f, value, lo, hi, open);
}

/* 0 if @p ok, else report_as. */
static int16_t report_as_if(int16_t ok, drive_limit_fail_t *f, const char *key, const char *unit,
                            float value, float lo, float hi, uint16_t open)
{
    if (ok != 0) {
        return 0;
    }
    return report_as(f, key, unit, value, lo, hi, open);
}

/* 0 if @p ok, else 1 with the limit reported. */
static int16_t verdict(int16_t ok, drive_limit_fail_t *f, float value, float lo, float hi,
                       uint16_t open)
{
    if (ok != 0) {
        return 0;
    }
    return report(f, value, lo, hi, open);
}

/* 1 (and @p f filled) unless @p ok; @p v reported against the entry's own
 * constant range. */
static int16_t own_verdict(const drive_limit_t *l, int16_t ok, float v, drive_limit_fail_t *f)
{
    return verdict(ok, f, v, l->lo, l->hi, l->open);
}

/* 1 (and @p f filled) unless @p v is in the entry's own constant range. */
static int16_t own_range(const drive_limit_t *l, float v, drive_limit_fail_t *f)
{
    return own_verdict(l, in_range(v, l->lo, l->hi, l->open), v, f);
}

/* A quantity that becomes Q24 somewhere: below Q24_HEADROOM of its base. */
static int16_t q24(float v, float base, drive_limit_fail_t *f)
{
    return verdict((int16_t)(v / base < Q24_HEADROOM), f, v, 0.0f, Q24_HEADROOM * base, BOTH_OPEN);
}

static int16_t check_motor_and_scaling(const drive_limit_t *l, const limit_ctx_t *x,
                                       drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_config_t *c = x->c;
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &x->b;
    float v;

    switch (which) {
    case DRIVE_LD_LLS:
        return own_range(l, m->Ls_H - m->Lm_H, f);
    case DRIVE_LD_LLR:
        return own_range(l, m->Lr_H - m->Lm_H, f);
    case DRIVE_LD_IM_RATED:
        v = 1.41421356f * m->rated_current_A_rms;
        return verdict((int16_t)(m->magnetizing_current_A < v), f, m->magnetizing_current_A, 0.0f,
                       v, BOTH_OPEN);
    case DRIVE_LD_T1PR:
        return own_range(l, x->g.t1pr, f);
    case DRIVE_LD_VDC_FS:   /* dc_bus_init */
        return verdict((int16_t)(dc_bus_check(c->board.vdc_adc_full_scale_V, b,
                                              DRIVE_VDC_FILTER_HZ) == DC_BUS_OK),
                       f, c->board.vdc_adc_full_scale_V, 0.0f,
                       DC_BUS_FULL_SCALE_MAX_PU * b->V_base_V * (65520.0f / 65536.0f), BOTH_OPEN);
    case DRIVE_LD_QEP_RES: {   /* qep_speed_init (its cut-off: DRIVE_LD_SPEED_FILT) */
        qep_speed_status_t st = qep_speed_check(c->board.encoder_lines, b,
                                                c->control.speed_filter_Hz, DRIVE_QEP_WINDOW);
        return verdict((int16_t)(st == QEP_SPEED_OK || st == QEP_SPEED_ERR_CUTOFF), f,
                       (float)c->board.encoder_lines,
                       (float)b->pole_pairs / (4.0f * b->Ts_s * b->f_base_Hz),
                       (float)QEP_SPEED_LINES_MAX, LO_OPEN);
    }
    case DRIVE_LD_SPEED_FILT:   /* qep_speed_init's and qep_speed_set_decim's: the filter
                                   runs in the slow task */
        v = 0.5f / (b->Ts_s * (float)DRIVE_SLOTS);
        return verdict((int16_t)(qep_speed_check(c->board.encoder_lines, b,
                                                 c->control.speed_filter_Hz,
                                                 DRIVE_QEP_WINDOW) == QEP_SPEED_OK &&
                                 qep_speed_decim_check(DRIVE_SLOTS, DRIVE_QEP_WINDOW, b,
                                                       c->control.speed_filter_Hz) ==
                                     QEP_SPEED_OK),
                       f, c->control.speed_filter_Hz, 0.0f, v, BOTH_OPEN);
    case DRIVE_LD_LS_Q24:
        return q24(m->Ls_H, b->L_base_H, f);
    case DRIVE_LD_LR_Q24:
        return q24(m->Lr_H, b->L_base_H, f);
    case DRIVE_LD_WC_PU:   /* drive_adapt_init's w_c in pu */
        v = DRIVE_TWO_PI_F * c->control.current_bw_Hz / b->w_base_rad_s;
        return verdict((int16_t)(v < Q24_HEADROOM),
                       f, c->control.current_bw_Hz, 0.0f, Q24_HEADROOM * b->f_base_Hz, BOTH_OPEN);
    default:
        return 0;
    }
}

/* pi_check of the PIs drive_init sets up (init_current_loops, init_speed_loop) */
static pi_status_t cur_pi(const drive_design_t *g)
{
    return pi_check(g->cur_kp, g->cur_ki, -DRIVE_CUR_PI_OUT_MAX, DRIVE_CUR_PI_OUT_MAX);
}

static pi_status_t spd_pi(const drive_design_t *g)
{
    return pi_check(g->spd_kp, g->spd_ki, -g->i_max, g->i_max);
}

static int16_t check_loops(const drive_limit_t *l, const limit_ctx_t *x,
                           drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_config_t *c = x->c;
    const base_values_t *b = &x->b;
    const drive_design_t *g = &x->g;

    /* pi_init of the current PIs and of the speed PI (its limit +-i_max:
     * DRIVE_LD_IMAX before it), each gain its own entry (kp first) */
    switch (which) {
    case DRIVE_LD_CUR_KP:
        return own_verdict(l, (int16_t)(cur_pi(g) != PI_ERR_KP), g->cur_kp, f);
    case DRIVE_LD_CUR_KI:
        return own_verdict(l, (int16_t)(cur_pi(g) != PI_ERR_KI), g->cur_ki, f);
    case DRIVE_LD_IMAX:
        return verdict(drive_design_imax_ok(g->i_max), f,
                       c->control.max_torque_current_A, 0.0f, b->I_base_A, LO_OPEN);
    case DRIVE_LD_SPD_KP:
        return own_verdict(l, (int16_t)(spd_pi(g) != PI_ERR_KP), g->spd_kp, f);
    case DRIVE_LD_SPD_KI:
        return own_verdict(l, (int16_t)(spd_pi(g) != PI_ERR_KI), g->spd_ki, f);
    case DRIVE_LD_RAMP:   /* ramp_gen_init: the ramp steps in the slow task */
        return verdict((int16_t)(ramp_gen_check(g->ramp, g->Ts_slow, -DRIVE_SPEED_REF_MAX_PU,
                                                DRIVE_SPEED_REF_MAX_PU) == RAMP_GEN_OK),
                       f, c->control.speed_ramp_rpm_s,
                       RAMP_GEN_STEP_MIN_PU * b->n_base_rpm / g->Ts_slow,
                       b->n_base_rpm / g->Ts_slow, 0u);
    default:
        return 0;
    }
}

/* ifo_set_tr's test of the believed Tr held in Q20 (ifo_tr_check, also
 * flux_obs_set_tr's bounds), on the Ts and guard ifo_init holds; @p st is
 * ifo_check's verdict: a Tr it refuses (beyond the Q20 range: _IQ20()
 * would overflow) is not converted */
static ifo_status_t ifo_q20(const limit_ctx_t *x, ifo_status_t st, float imr, float tr_pu)
{
    if (st == IFO_ERR_TR) {
        return st;
    }
    return ifo_tr_check(_IQ(x->b.Ts_pu), _IQ(imr), _IQ20(tr_pu));
}

/* ifo_init (ifo_check: the guard, Tr's Q20 headroom, f_base Ts) and
 * ifo_set_tr (ifo_tr_check: Tr's bounds and the slip bound on the Q20 Tr) */
static int16_t check_orientation(const drive_limit_t *l, const limit_ctx_t *x,
                                 drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_config_t *c = x->c;
    const base_values_t *b = &x->b;
    float imr = DRIVE_IMR_MIN_OF_IM * c->motor.magnetizing_current_A / b->I_base_A;
    float tr_pu = x->g.tr / b->t_base_s;
    float fts = b->f_base_Hz * b->Ts_s;
    ifo_status_t st = ifo_check(x->g.tr, b, imr);

    switch (which) {
    case DRIVE_LD_IMR:
        return verdict((int16_t)(st != IFO_ERR_IMR_MIN), f, c->motor.magnetizing_current_A,
                       0.0f, b->I_base_A / DRIVE_IMR_MIN_OF_IM, LO_OPEN);
    case DRIVE_LD_TR:
        return verdict((int16_t)(ifo_q20(x, st, imr, tr_pu) != IFO_ERR_TR), f, x->g.tr,
                       IFO_TR_MIN_SAMPLES * b->Ts_s, IFO_TR_MAX_PU * b->t_base_s, 0u);
    case DRIVE_LD_FTS:
        return verdict((int16_t)(st != IFO_ERR_BASE), f, 1.0f / fts, l->lo, l->hi, l->open);
    case DRIVE_LD_SLIP:
        return verdict((int16_t)(ifo_q20(x, st, imr, tr_pu) != IFO_ERR_IMR_MIN), f, tr_pu * imr,
                       IFO_I_T_MAX / IFO_SLIP_MAX, NO_UPPER, HI_OPEN);
    default:
        return 0;
    }
}

/* flux_obs_init's check of drive_init's arguments */
static flux_obs_status_t obs_init(const limit_ctx_t *x)
{
    const drive_motor_t *m = &x->c->motor;
    return flux_obs_check(&x->b, m->Rs_ohm, m->Ls_H, m->Lr_H, m->Lm_H, x->g.tr, FOBS_WC_HZ,
                          FOBS_WS_LPF_HZ);
}

/* flux_obs_set_step's: the observer steps once a slow period, on the Q20 Tr
 * flux_obs_init holds (DRIVE_LD_TR before: within the Q20 range) */
static flux_obs_status_t obs_step(const limit_ctx_t *x)
{
    return flux_obs_step_check(&x->b, DRIVE_SLOTS, FOBS_WC_HZ, FOBS_WS_LPF_HZ,
                               _IQ20(x->g.tr / x->b.t_base_s));
}

/* The table's entry for an inductance flux_obs_l_check refuses (none: an
 * index no entry has) */
static uint16_t obs_l_entry(flux_obs_l_fault_t lf)
{
    switch (lf) {
    case FLUX_OBS_L_LM:
        return DRIVE_LD_OBS_LM;
    case FLUX_OBS_L_LR:
        return DRIVE_LD_OBS_LR;
    case FLUX_OBS_L_LS:
        return DRIVE_LD_OBS_LS;
    case FLUX_OBS_L_SLS:
        return DRIVE_LD_OBS_SLS;
    default:
        return 0xFFFFu;
    }
}

/* flux_obs_init, flux_obs_set_step, for orientation 1 only; the
 * inductances by flux_obs_l_check, the test flux_obs_init applies to them,
 * which names the one it refuses (flux_obs_init's status does not) */
static int16_t check_observer(const drive_limit_t *l, const limit_ctx_t *x,
                              drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_motor_t *m = &x->c->motor;
    const base_values_t *b = &x->b;
    flux_obs_l_fault_t lf;

    if (x->c->control.orientation != DRIVE_ORIENT_FLUX_OBS) {
        return 0;
    }
    switch (which) {
    case DRIVE_LD_OBS_FBASE:   /* the crossover in pu, and against the observer's step */
        return verdict((int16_t)(obs_init(x) != FLUX_OBS_ERR_WC &&
                                 obs_step(x) != FLUX_OBS_ERR_WC),
                       f, b->f_base_Hz, FOBS_WC_HZ / FLUX_OBS_WC_MAX_PU, NO_UPPER, HI_OPEN);
    case DRIVE_LD_OBS_PWM: {
        /* its step DRIVE_SLOTS Ts (flux_obs_set_step's): the ws low-pass at
         * most 1 rad a step, the believed Tr at least FLUX_OBS_TR_MIN_SAMPLES
         * steps */
        const flux_obs_status_t st = obs_step(x);
        const float f_min = fmaxf(6.2831853f * FOBS_WS_LPF_HZ,
                                  FLUX_OBS_TR_MIN_SAMPLES / x->g.tr) * (float)DRIVE_SLOTS;
        return verdict((int16_t)(st != FLUX_OBS_ERR_WS_LPF && st != FLUX_OBS_ERR_TR),
                       f, 1.0f / b->Ts_s, f_min, NO_UPPER, HI_OPEN);
    }
    case DRIVE_LD_OBS_RS:
        return verdict((int16_t)(obs_init(x) != FLUX_OBS_ERR_RS), f, m->Rs_ohm, 0.0f,
                       FLUX_OBS_RS_MAX * b->Z_base_ohm, 0u);
    default:
        break;
    }
    /* the pu floats flux_obs_check gives flux_obs_design_l; each entry
     * fails on its own fault only (an earlier one has been reported) */
    lf = flux_obs_l_check(m->Lm_H / b->L_base_H, m->Lr_H / b->L_base_H, m->Ls_H / b->L_base_H);
    if (which != obs_l_entry(lf)) {
        return 0;
    }
    /* the value in the user's units; the divisions are defined here: Lm
     * passed before Lr, Ls and sigma Ls are tested, Lr before sigma Ls */
    switch (lf) {
    case FLUX_OBS_L_LM:
        return report(f, m->Lm_H, 0.0f, FLUX_OBS_LM_MAX * b->L_base_H, LO_OPEN);
    case FLUX_OBS_L_LR:
        return report(f, m->Lr_H / m->Lm_H, 1.0f, FLUX_OBS_LR_LM_MAX, LO_OPEN);
    case FLUX_OBS_L_LS:
        return report(f, m->Ls_H, m->Lm_H, 2.0f * FLUX_OBS_LM_MAX * b->L_base_H, LO_OPEN);
    default:
        return report(f, m->Ls_H - m->Lm_H * m->Lm_H / m->Lr_H, 0.0f,
                      FLUX_OBS_SIGMA_LS_MAX * b->L_base_H, LO_OPEN);
    }
}

/* volt_calc_init (volt_calc_check, with drive_init's arguments) and the
 * bridge's curve test (vi_curve_init) */
static int16_t check_voltage_model(const drive_limit_t *l, const limit_ctx_t *x,
                                   drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_board_t *bd = &x->c->board;
    const base_values_t *b = &x->b;
    volt_calc_status_t vc = volt_calc_check(bd->dead_time_s, x->g.Ts,
                                            bd->device_drop_V / b->V_base_V,
                                            drive_design_volt_band_pu(x->c, b),
                                            drive_design_volt_comp(x->c));
    float v;

    switch (which) {
    case DRIVE_LD_DEAD:
        return verdict((int16_t)(vc != VOLT_CALC_ERR_DEADTIME), f, bd->dead_time_s, 0.0f,
                       VOLT_CALC_DT_FRAC_MAX * x->g.Ts, 0u);
    case DRIVE_LD_DROP:
        return verdict((int16_t)(vc != VOLT_CALC_ERR_DROP), f, bd->device_drop_V, 0.0f,
                       VOLT_CALC_DROP_MAX_PU * b->V_base_V, 0u);
    case DRIVE_LD_VI_HOLD:
    case DRIVE_LD_VI_GAINS: {
        /* the bridge's curve test (drive_vi_init: vi_curve_check on its
         * arguments); its zone is measured (drive_vi.c) and checked when it
         * is (volt_calc_curve_design) */
        float kp, ki, u_max;
        pi_status_t st;
        if (x->c->ident.vi_test == 0u || bd->dead_time_comp == 0u) {
            return 0;
        }
        drive_vi_gains(x->c, b, x->g.Ts_slow, x->g.sls, &kp, &ki, &u_max);
        if (which == DRIVE_LD_VI_HOLD) {
            /* a current level held 6 Tr in a 16-bit count of slow samples */
            v = 65535.0f * x->g.Ts_slow / 6.0f;
            return verdict((int16_t)(vi_curve_check(x->g.Ts_slow, drive_vi_i1_pu(x->c, b),
                                                    x->g.tr, kp, ki, u_max) !=
                                     VI_CURVE_ERR_TIME),
                           f, x->g.tr, 0.0f, v, LO_OPEN);
        }
        /* its PI within PI_KP_MAX, PI_KI_MAX (a large Rs against Z_base
         * makes ki large): pi_check names the gain */
        st = pi_check(kp, ki, -u_max, u_max);
        if (st == PI_ERR_KP) {
            return verdict(0, f, kp, 0.0f, PI_KP_MAX, 0u);
        }
        return verdict((int16_t)(st != PI_ERR_KI), f, ki, 0.0f, PI_KI_MAX, 0u);
    }
    case DRIVE_LD_BAND:
        /* (with ident.vi_test the fallback zone is unused, the test measures
         * it: drive_design_volt_band_pu passes) */
        return verdict((int16_t)(vc == VOLT_CALC_OK), f, bd->dead_time_band_A,
                       VOLT_CALC_ITH_MIN_PU * b->I_base_A, VOLT_CALC_ITH_MAX_PU * b->I_base_A, 0u);
    default:
        return 0;
    }
}

/* ident_regressor_init (its filters: bw_filter_init), theta_guard_init,
 * param_extract_init */
static int16_t check_estimator(const drive_limit_t *l, const limit_ctx_t *x,
                               drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    /* the model's signs, only to report -K1, K2, K3, -K4 as the keys say */
    static const float k_sign[RLS_N] = {-1.0f, 1.0f, 1.0f, -1.0f};
    const drive_config_t *c = x->c;
    const base_values_t *b = &x->b;
    float wc = c->ident.filter_wc_rad_s;
    float k[RLS_N];
    param_limits_t lim;
    param_status_t bad = PARAM_OK;
    uint16_t bad_k = RLS_N;
    uint16_t i;
    bw_filter_status_t st;

    switch (which) {
    case DRIVE_LD_FILT:
        return own_range(l, wc / DRIVE_TWO_PI_F, f);
    case DRIVE_LD_FILT_WB:
    case DRIVE_LD_FILT_STEP:
        /* the filters run in the slow task (DRIVE_SLOTS_LOG2) */
        st = ident_regressor_check(wc, c->ident.euler_passes, x->g.Ts, b->w_base_rad_s,
                                   DRIVE_SLOTS_LOG2);
        if (which == DRIVE_LD_FILT_WB) {
            return verdict((int16_t)(st != BW_FILTER_ERR_WC), f, wc / DRIVE_TWO_PI_F, 0.0f,
                           BW_FILTER_WC_MAX_PU * b->f_base_Hz, BOTH_OPEN);
        }
        return verdict((int16_t)(st != BW_FILTER_ERR_STEP), f, wc / DRIVE_TWO_PI_F, 0.0f,
                       BW_FILTER_A_MAX / (DRIVE_TWO_PI_F * x->g.Ts_slow), LO_OPEN);
    case DRIVE_LD_K1:
    case DRIVE_LD_K2:
    case DRIVE_LD_K3:
    case DRIVE_LD_K4:
        /* theta_guard_init: each K with the model's sign in (0, RLS_THETA_MAX),
         * the first one refused named */
        drive_design_k_nominal(k, c, b);
        (void)theta_guard_check(k, DRIVE_THETA_GUARD_SPAN, &bad_k);
        i = (uint16_t)(which - (uint16_t)DRIVE_LD_K1);
        return own_verdict(l, (int16_t)(bad_k != i), k_sign[i] * k[i], f);
    default:
        break;
    }
    /* param_extract_init: each range 0.25 .. 4 times the believed value,
     * capped at 120 pu, must stay a range below 127 pu; the first range
     * refused named */
    drive_design_param_limits(&lim, c, b);
    (void)param_extract_check(b, &lim, &bad);
    switch (which) {
    case DRIVE_LD_PE_RS:
        return verdict((int16_t)(bad != PARAM_ERR_RS), f, c->motor.Rs_ohm, 0.0f,
                       480.0f * b->Z_base_ohm, BOTH_OPEN);
    case DRIVE_LD_PE_RR:
        return verdict((int16_t)(bad != PARAM_ERR_RR), f, c->motor.Rr_ohm, 0.0f,
                       480.0f * b->Z_base_ohm, BOTH_OPEN);
    case DRIVE_LD_PE_LM:
        return verdict((int16_t)(bad != PARAM_ERR_LM), f, c->motor.Lm_H, 0.0f,
                       480.0f * b->L_base_H, BOTH_OPEN);
    case DRIVE_LD_PE_LR:
        return verdict((int16_t)(bad != PARAM_ERR_LR), f, c->motor.Lr_H, 0.0f,
                       480.0f * b->L_base_H, BOTH_OPEN);
    case DRIVE_LD_PE_PSI:
        return verdict((int16_t)(bad != PARAM_ERR_PSI), f,
                       c->motor.Lm_H * c->motor.magnetizing_current_A, 0.0f,
                       PARAM_EXTRACT_PU_MAX / 4.0f * b->psi_base_Wb, BOTH_OPEN);
    default:
        return 0;
    }
}

/* drive_adapt_init: the features need the observer; the standstill test and
 * the tracker on scratch instances, set up exactly as drive_adapt_init does */
static int16_t check_adaptation(const drive_limit_t *l, const limit_ctx_t *x,
                                drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_config_t *c = x->c;
    const drive_ident_t *id = &c->ident;
    const base_values_t *b = &x->b;
    float Ts = x->g.Ts;

    if (which == DRIVE_LD_FEATURES) {
        return verdict((int16_t)((id->passes <= 1u && id->standstill == 0u && id->track_rr == 0u) ||
                                 c->control.orientation == DRIVE_ORIENT_FLUX_OBS),
                       f, (float)c->control.orientation, 1.0f, 1.0f, 0u);
    }
    if (which == DRIVE_LD_PERIOD_MEAN) {
        /* the flux it regresses on is ifo's model plus its correction
         * (ident_regressor.h), with the constant third column's rows */
        return verdict((int16_t)(id->period_mean == 0u ||
                                 (c->control.orientation != DRIVE_ORIENT_FLUX_OBS &&
                                  id->paper_regressor == 0u)),
                       f, (float)id->period_mean, 0.0f, 0.0f, 0u);
    }
    if (which == DRIVE_LD_STANDSTILL && id->standstill != 0u) {
        standstill_z_t z;
        standstill_z_status_t st = drive_adapt_ssz_init(&z, c, b, Ts);
        /* id_sequence_init's magnetisation (it counts slow-task ticks,
         * DRIVE_SLOTS periods each) in samples */
        uint32_t mag = (uint32_t)(id->magnetize_time_s / (Ts * (float)DRIVE_SLOTS) + 0.5f) *
                       DRIVE_SLOTS;
        uint32_t need = 2u * ((uint32_t)standstill_z_samples(&z) + drive_adapt_ssz_gap(Ts));
        if (st == STANDSTILL_Z_ERR_AMPL) {
            return report_as(f, DRIVE_LT("controller.magnetizing_current_A"), DRIVE_LT("A"),
                             c->motor.magnetizing_current_A, 0.0f,
                             0.5f / SSZ_AMPL_OF_IM * b->I_base_A, LO_OPEN);
        }
        if (st != STANDSTILL_Z_OK) {
            /* (the bounds: 8 to 3120 samples a period of the injection, 0.01 to
             * 30 pu of frequency: standstill_z_init) */
            return report_as(f, DRIVE_LT("standstill injection frequency"), DRIVE_LT("Hz"),
                             drive_adapt_ssz_freq_Hz(c),
                             fmaxf(1.0f / (3120.0f * Ts), 0.01f * b->f_base_Hz),
                             fminf(1.0f / (8.0f * Ts), 30.0f * b->f_base_Hz), 0u);
        }
        if (need <= mag) {
            return 0;
        }
        return report_as(f, DRIVE_LT("ident.magnetize_s"), DRIVE_LT("s"), id->magnetize_time_s, (float)need * Ts,
                         100.0f, 0u);
    }
    if (which == DRIVE_LD_STATIC && id->static_id != 0u) {
        const float tr_s = c->motor.Lr_H / c->motor.Rr_ohm;
        const float im_pu = c->motor.magnetizing_current_A / b->I_base_A;
        if (id->standstill == 0u || id->passes > 1u || id->track_rr != 0u) {
            /* the standstill sequence: its Rs and sigma Ls from the standstill
             * test, one pass, nothing to track */
            return verdict(0, f, (float)id->static_id, 0.0f, 0.0f, 0u);
        }
        if (standstill_lf_check(Ts * (float)DRIVE_SLOTS, tr_s, DRIVE_STATIC_AMPL_OF_IM * im_pu,
                                im_pu, DRIVE_STATIC_WINDOW_S) != STANDSTILL_LF_OK) {
            /* its fundamental's period 2 pi Tr / 0.5 within 64 .. 2^20 slow samples */
            return report_as(f, DRIVE_LT("Tr"), DRIVE_LT("s"), tr_s,
                             64.0f * Ts * (float)DRIVE_SLOTS * 0.5f / 6.2831853f,
                             1048576.0f * Ts * (float)DRIVE_SLOTS * 0.5f / 6.2831853f, 0u);
        }
        return 0;
    }
    if (which == DRIVE_LD_TRACKER && id->track_rr != 0u) {
        tr_track_t t;
        tr_track_status_t st = drive_adapt_track_init(&t, c, b, Ts);
        if (st == TR_TRACK_ERR_RANGE) {
            /* theta = 1/Tr in pu up to 4 times the believed one, at most 30 */
            return report_as(f, DRIVE_LT("Tr"), DRIVE_LT("s"), x->g.tr, 4.0f / 30.0f * b->t_base_s, NO_UPPER,
                             HI_OPEN);
        }
        if (st == TR_TRACK_ERR_PHI) {
            return report_as(f, DRIVE_LT("controller.max_torque_current_A"), DRIVE_LT("A"),
                             c->control.max_torque_current_A, 0.0f,
                             b->I_base_A * b->psi_base_Wb /
                                 (TRACK_PHI_MIN_OF_RATED * c->motor.Lm_H *
                                  c->motor.magnetizing_current_A), LO_OPEN);
        }
        if (st != TR_TRACK_OK) {
            return report_as(f, DRIVE_LT("ident.track_memory_s"), DRIVE_LT("s"), id->track_memory_s, 0.2f, 20.0f, 0u);
        }
    }
    return 0;
}

/* protect_init's check of drive_init's levels, those of the entries after
 * @p upto (0 the trip, 1 the undervoltage, 2 the overvoltage) as 0: not
 * yet checked (a level above Q24 would overflow), and judged after it */
static protect_args_t protect_levels(const limit_ctx_t *x, uint16_t upto)
{
    const drive_board_t *bd = &x->c->board;
    return protect_args_ok(_IQ(bd->overcurrent_A / x->b.I_base_A),
                           (upto >= 2u) ? _IQ(bd->vdc_max_V / x->b.V_base_V) : _IQ(0.0),
                           (upto >= 1u) ? _IQ(bd->vdc_min_V / x->b.V_base_V) : _IQ(0.0));
}

static int16_t check_sequence_and_protection(const drive_limit_t *l, const limit_ctx_t *x,
                                             drive_limit_fail_t *f)
{
    uint16_t which = l->where;
    const drive_config_t *c = x->c;
    const drive_board_t *bd = &c->board;
    const base_values_t *b = &x->b;
    const drive_design_t *g = &x->g;
    float target = (c->ident.target_speed_rpm > 0.0f) ? c->ident.target_speed_rpm
                                                      : c->motor.rated_speed_rpm;
    float v;
    int16_t ok;

    switch (which) {
    case DRIVE_LD_TARGET: {
        float floor_obs = (c->control.orientation == DRIVE_ORIENT_FLUX_OBS)
                              ? 60.0f * FOBS_RLS_WS_OVER_WC * FOBS_WC_HZ / (float)c->motor.pole_pairs
                              : 0.0f;
        float lo = drive_target_least_rpm(c);
        v = TARGET_MAX_OF_RATED * c->motor.rated_speed_rpm;
        if (lo > v && floor_obs >= lo) {
            /* no target can reach the observer's gate: the motor's rated
             * frequency is below it */
            return report_as(f, DRIVE_LT("controller.orientation"), DRIVE_LT("-"), 1.0f, 0.0f, 0.0f, 0u);
        }
        return verdict((int16_t)(target >= lo && target <= v), f, target, lo, v, 0u);
    }
    case DRIVE_LD_BUS: {
        /* the start's no-load limit at the nominal bus (drive_target.h): a
         * configured target must fit, and by default (0: rated, lowered to
         * what the bus gives) at least the least target, with the believed
         * Ls at its low end (the drive measures the true one) */
        drive_target_noload_t t;
        float need = (c->ident.target_speed_rpm > 0.0f) ? target : drive_target_least_rpm(c);
        float w;
        drive_target_noload_init(&t, c, b);
        if (!(c->ident.target_speed_rpm > 0.0f)) {
            t.ls_im /= 1.0f + DRIVE_TARGET_LS_TOL;
        }
        w = drive_target_noload_max_pu(&t, DRIVE_SQRT3_F, DRIVE_TARGET_NOLOAD_OF_VLIN) *
            b->n_base_rpm;
        if (c->ident.target_speed_rpm > 0.0f) {
            return report_as_if((int16_t)(need <= w), f, DRIVE_LT("ident.target_speed_rpm"),
                                DRIVE_LT("r/min"), need, 0.0f, w, 0u);
        }
        return verdict((int16_t)(need <= w), f, c->board.vdc_nominal_V,
                       drive_target_bus_for_pu(&t, need / b->n_base_rpm,
                                               DRIVE_TARGET_NOLOAD_OF_VLIN) * b->V_base_V,
                       NO_UPPER, 0u);
    }
    case DRIVE_LD_TARGET_PU:
        return verdict((int16_t)(g->target_pu <= DRIVE_SPEED_REF_MAX_PU), f, target, 0.0f,
                       DRIVE_SPEED_REF_MAX_PU * b->n_base_rpm, LO_OPEN);
    case DRIVE_LD_HEADROOM: {
        const drive_motor_t *m = &c->motor;
        float w = DRIVE_TWO_PI_F * target / 60.0f * (float)m->pole_pairs;
        float ur = m->Rs_ohm * m->magnetizing_current_A;
        float ux = w * m->Ls_H * m->magnetizing_current_A;
        float allowed = HEADROOM_LOSS_OF_VOLTAGE * sqrtf(ur * ur + ux * ux);   /* V */
        float per_s = bd->vdc_nominal_V * bd->pwm_freq_Hz;   /* V per second of dead time */
        if (!(allowed > bd->device_drop_V)) {
            /* the drop alone takes it: no dead time fits */
            return report_as(f, DRIVE_LT("board.device_drop_V"), DRIVE_LT("V"), bd->device_drop_V, 0.0f, allowed,
                             HI_OPEN);
        }
        return verdict((int16_t)(bd->dead_time_s * per_s + bd->device_drop_V <= allowed), f,
                       bd->dead_time_s, 0.0f, (allowed - bd->device_drop_V) / per_s, 0u);
    }
    case DRIVE_LD_OC_FS:   /* drive_init's (below the sensors' full scale), then protect_init's */
        ok = drive_design_oc_ok(bd);
        if (ok != 0) {
            ok = (int16_t)(protect_levels(x, 0u) != PROTECT_ERR_TRIP);
        }
        return verdict(ok, f, bd->overcurrent_A, 0.0f, bd->current_full_scale_A, BOTH_OPEN);
    case DRIVE_LD_TORQUE_OC:
        return verdict((int16_t)(c->control.max_torque_current_A <= bd->overcurrent_A), f,
                       c->control.max_torque_current_A, 0.0f, bd->overcurrent_A, LO_OPEN);
    case DRIVE_LD_VDC_MIN:   /* drive_init's (below the nominal bus), then protect_init's */
        ok = (int16_t)(bd->vdc_min_V < bd->vdc_nominal_V);
        if (ok != 0) {
            ok = (int16_t)(protect_levels(x, 1u) != PROTECT_ERR_VDC_MIN);
        }
        return verdict(ok, f, bd->vdc_min_V, 0.0f, bd->vdc_nominal_V, BOTH_OPEN);
    case DRIVE_LD_VDC_MAX:
        /* drive_init's (above the nominal bus, below the full scale, so below
         * 64 V_base: the Q24 conversions hold), then protect_init's */
        ok = (int16_t)(bd->vdc_max_V > bd->vdc_nominal_V &&
                       bd->vdc_max_V < bd->vdc_adc_full_scale_V);
        if (ok != 0) {
            ok = (int16_t)(protect_levels(x, 2u) != PROTECT_ERR_VDC_MAX);
        }
        return verdict(ok,
                       f, bd->vdc_max_V, bd->vdc_nominal_V, bd->vdc_adc_full_scale_V, BOTH_OPEN);
    case DRIVE_LD_ENC_JUMP: {   /* encoder_check_init: counts a period at DRIVE_ENC_SPEED_MAX_PU */
        float per_line = DRIVE_ENC_SPEED_MAX_PU * b->f_base_Hz / (float)c->motor.pole_pairs *
                         4.0f;
        return verdict((int16_t)(encoder_check_args_ok(
                                     g->Ts, DRIVE_ENC_FROZEN_S,
                                     DRIVE_ENC_IT_OF_IMAX * c->control.max_torque_current_A /
                                         b->I_base_A,
                                     DRIVE_ENC_SPEED_MAX_PU, b->f_base_Hz, bd->encoder_lines,
                                     c->motor.pole_pairs) == ENCODER_CHECK_OK),
                       f, (float)bd->encoder_lines, 2.0f / (per_line * b->Ts_s),
                       16384.0f / (per_line * b->Ts_s), 0u);
    }
    default:
        return 0;
    }
}

/* 1 if derived limit @p l fails (f filled); every field is in range here. */
static int16_t check_derived(const drive_limit_t *l, const limit_ctx_t *x,
                             drive_limit_fail_t *f)
{
    uint16_t w = l->where;
    if (w <= DRIVE_LD_WC_PU) {
        return check_motor_and_scaling(l, x, f);
    }
    if (w <= DRIVE_LD_RAMP) {
        return check_loops(l, x, f);
    }
    if (w <= DRIVE_LD_SLIP) {
        return check_orientation(l, x, f);
    }
    if (w <= DRIVE_LD_OBS_SLS) {
        return check_observer(l, x, f);
    }
    if (w <= DRIVE_LD_BAND) {
        return check_voltage_model(l, x, f);
    }
    if (w <= DRIVE_LD_PE_PSI) {
        return check_estimator(l, x, f);
    }
    if (w <= DRIVE_LD_PERIOD_MEAN) {
        return check_adaptation(l, x, f);
    }
    return check_sequence_and_protection(l, x, f);
}

static void fill(drive_limit_fail_t *f, const drive_limit_t *l)
{
    f->limit = l;
    f->key = l->key;
    f->unit = l->unit;
    f->status = l->status;
}

int16_t drive_config_check(const drive_config_t *c, drive_limit_fail_t *fail)
{
    drive_limit_fail_t scratch;   /* when the caller wants no report */
    drive_limit_fail_t *f;
    limit_ctx_t x;
    uint16_t i;

    memset(&scratch, 0, sizeof scratch);
    f = (fail != NULL) ? fail : &scratch;
    memset(f, 0, sizeof *f);
    for (i = 0u; i < N_LIMITS; i++) {
        const drive_limit_t *l = &k_limits[i];
        float v;
        if (l->kind == DRIVE_LIMIT_DERIVED) {
            continue;
        }
        v = field_value(c, l);
        if (!in_range(v, l->lo, l->hi, l->open)) {
            fill(f, l);
            (void)report(f, v, l->lo, l->hi, l->open);
            return f->status;
        }
    }
    /* every field in range: the bases exist (rates and scales > 0, Ts <= 1 ms) */
    x.c = c;
    if (drive_design_bases(&x.b, c) != BASE_OK) {
        return ST(DRIVE_CFG_BASES);   /* not reached with the field ranges above */
    }
    drive_design(&x.g, c, &x.b);
    for (i = 0u; i < N_LIMITS; i++) {
        const drive_limit_t *l = &k_limits[i];
        if (l->kind != DRIVE_LIMIT_DERIVED) {
            continue;
        }
        fill(f, l);
        if (check_derived(l, &x, f) != 0) {
            return f->status;
        }
    }
    memset(f, 0, sizeof *f);
    return ST(DRIVE_CFG_OK);
}
