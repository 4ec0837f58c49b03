/**
 * The bridge's voltage error at standstill (vi_curve.h), measured in
 * CALIBRATE after the sensor test, once per drive_init, and used by the
 * voltage reconstruction and the dead-time feed-forward (volt_calc.h) in
 * place of a hand-set linear zone (method §6 "Dead time").
 *
 * Who does what:
 *   - ISR, slot SEQUENCE (drive_vi_slow): the test's step (a PI step on
 *     i_alpha or a held voltage, the window sums: vi_curve_step), and once
 *     the background has answered, the curve copied into volt_calc (six
 *     words) and vi.done; a failed test, a refused curve or no answer
 *     within DRIVE_VI_WAIT_S latch FAULT_VI_CURVE (the drive never runs
 *     on a curve it did not measure);
 *   - ISR, every period of the test (drive_vi_modulate): the test's alpha
 *     voltage to the modulator, as the sensor test does;
 *   - background (drive_vi_background): the schedule (each level's window
 *     means and check, the next level: vi_curve_next), the fit (float), the
 *     plausibility against the board's dead time and drop, the curve's
 *     constants; the test's restart while the sequence is idle or
 *     calibrating.
 * Until the curve is applied the compensation is off: the test itself
 * needs the uncompensated voltage (u_ref = vdc d), and nothing runs on the
 * voltage model before MAGNETIZE.
 *
 * With [controller] dead_time_comp = 0 there is no test and no
 * compensation.
 */
#include "drive_vi.h"

#include "drive_design.h"

#include <math.h>

#define DRIVE_VI_BW_HZ 50.0f     /* the current levels' loop: a tenth of the current loops'
                                    usual bandwidth, at the slow rate (1.875 kHz: 37 samples
                                    per time constant); its levels are held 3 Tr anyway */
#define DRIVE_VI_I1_OF_IM 0.5f   /* i1 = 0.5 i_M (2 i1 = i_M): beyond a transition of
                                    b < i_M / 4 (at 0.25 i_M the family's 0.2 kW 6-pole
                                    motor, i_M 0.63 A, had its levels inside 2 b of a 0.1 A
                                    bridge and the fit refused the curve); at most the
                                    magnetising current, its flux gone after the voltage
                                    levels and the rest */
#define DRIVE_VI_RETRY_I1_OF_B 2.5f   /* a retry's i1: 2.5 b, 25 % beyond the transition's
                                    2 b (the model's saturation, vi_curve_model_V) */
#define DRIVE_VI_RETRY_E_SPLIT 0.02f  /* ... and only if the polarities' E agree within 2 %:
                                    a band refused with E split (an offset the calibration
                                    left: 2.9 % of full scale split the 15 kW motor's by
                                    6 %) is not a wide bridge but a lying sensor, and its
                                    refusal stands (healthy: below 0.1 %) */
#define DRIVE_VI_WAIT_S 1.0f     /* longest wait for the background's fit */
#define DRIVE_VI_E_FACTOR 2.0f   /* the measured E within this factor of the board's
                                    vdc td/Ts + v_drop: else the board's dead time or the
                                    test is wrong, refused */

void drive_vi_gains(const drive_config_t *c, const base_values_t *b, float Ts_slow, float sls_H,
                    float *kp, float *ki, float *u_max)
{
    const float wc = DRIVE_TWO_PI_F * fminf(DRIVE_VI_BW_HZ, 0.05f * (1.0f / Ts_slow));
    /* the PI's zero on the stator pole, as the current loops (drive_init.c) */
    *kp = wc * sls_H / b->Z_base_ohm;
    *ki = wc * Ts_slow * c->motor.Rs_ohm / b->Z_base_ohm;
    /* within half the linear modulation range vdc / sqrt(3) */
    *u_max = 0.5f * c->board.vdc_nominal_V / 1.7320508f / b->V_base_V;
}

float drive_vi_i1_pu(const drive_config_t *c, const base_values_t *b)
{
    return DRIVE_VI_I1_OF_IM * c->motor.magnetizing_current_A / b->I_base_A;
}

int16_t drive_vi_init(drive_t *d, const drive_config_t *c, float Ts_slow, float sls_H,
                      float tr_s)
{
    const base_values_t *b = &d->base;
    const float f_slow = 1.0f / Ts_slow;
    float kp, ki, u_max;

    d->vi.post = DRIVE_VI_NONE;
    d->vi.fitted = 0u;
    d->vi.wait = 0u;
    d->vi.wait_max = (uint32_t)(DRIVE_VI_WAIT_S / Ts_slow + 0.5f);
    d->vi.dt_frac = c->board.dead_time_s * f_slow * (float)DRIVE_SLOTS;
    d->vi.i1_0 = drive_vi_i1_pu(c, b);
    /* +-2 i1 within the torque-current limit (the current loops' own, at
     * least i_M: the first test's 2 i1) */
    d->vi.i1_max = 0.5f * fmaxf(c->control.max_torque_current_A, c->motor.magnetizing_current_A) /
                    b->I_base_A;
    d->vi.retried = 0u;
    if (c->board.dead_time_comp == 0u || c->ident.vi_test == 0u) {
        return 0;   /* no compensation, or on the set band (drive_init.c) */
    }
    drive_vi_gains(c, b, Ts_slow, sls_H, &kp, &ki, &u_max);
    if (vi_curve_init(&d->vi.test, Ts_slow, d->vi.i1_0, tr_s, kp, ki, u_max) != VI_CURVE_OK) {
        return 1;
    }
    d->seq.vi_test = 1u;
    return 0;
}

void drive_vi_slow(drive_t *d)
{
    vi_curve_t *v = &d->vi.test;

    if (d->seq.vi_test == 0u || d->vi.done != 0u) {
        return;
    }
    v->run = d->seq.vi_testing;
    v->i_alpha = d->sense.clarke.alpha;
    v->u_alpha = d->pwm.volt.valpha;
    v->vdc = d->sense.bus.vdc;
    vi_curve_step(v);
    if (v->done == 0u || d->seq.vi_testing == 0u) {
        return;
    }
    if (v->fail == 0u && d->vi.post == DRIVE_VI_CURVE) {
        volt_calc_apply_curve(&d->pwm.volt, &d->vi.curve);
        d->vi.done = 1u;
    } else if (v->fail != 0u || d->vi.post == DRIVE_VI_REFUSED ||
               ++d->vi.wait >= d->vi.wait_max) {
        protect_latch(&d->prot.trip, FAULT_VI_CURVE);
    } else {
        /* waiting for the background, at zero voltage */
    }
}

void drive_test_voltage(drive_t *d, hal_pwm_compare_t *out, _iq u_alpha, _iq u_beta)
{
    /* the test's voltage, not the current loops' (held at zero: no wind-up
     * against the test) */
    pi_reset(&d->loop.pi_id);
    pi_reset(&d->loop.pi_iq);
    d->pwm.svgen.ualpha = u_alpha;
    d->pwm.svgen.ubeta = u_beta;
    svgen_step(&d->pwm.svgen);
    out->cmpr[0] = d->pwm.svgen.cmpr[0];
    out->cmpr[1] = d->pwm.svgen.cmpr[1];
    out->cmpr[2] = d->pwm.svgen.cmpr[2];
}

void drive_vi_modulate(drive_t *d, hal_pwm_compare_t *out)
{
    /* along alpha only: poles b and c carry the same duty and current */
    drive_test_voltage(d, out, d->vi.test.u_cmd, _IQ(0.0));
}

/* A band measured but the current levels inside it (2 b >= i1: a small
 * motor's i_M against its bridge's transition, e.g. the family's 0.2 kW
 * 150-sigma motors, i_M 0.40 A, on the simulated 0.1 A bridge: i1 0.200 A,
 * b 0.101 A): once, the whole test again with i1 = 2.5 b, if +-2 i1 stays
 * within the current limit (vi.i1_max) and the two polarities agree on E
 * (DRIVE_VI_RETRY_E_SPLIT); else, or a second time, the refusal stands.
 * Returns 1 if the test was restarted (the ISR, waiting on the finished
 * test, steps the new one from its first level). */
static uint16_t drive_vi_retry(drive_t *d, const vi_fit_t *f)
{
    const float i1 = DRIVE_VI_RETRY_I1_OF_B * f->band_A / d->base.I_base_A;

    if (d->vi.retried != 0u || f->n_band == 0u || !(i1 > d->vi.test.i1) ||
        !(i1 <= d->vi.i1_max) || !(f->e_split <= DRIVE_VI_RETRY_E_SPLIT)) {
        return 0u;   /* also NaN: refused */
    }
    d->vi.wait = 0u;   /* before the restart: the ISR counts only while the test is done */
    if (vi_curve_retry(&d->vi.test, i1) != VI_CURVE_OK) {
        return 0u;   /* nothing restarted: the refusal stands */
    }
    d->vi.retried = 1u;
    d->vi.fitted = 0u;
    return 1u;
}

void drive_vi_background(drive_t *d)
{
    const base_values_t *b = &d->base;
    vi_fit_t fit;
    vi_fit_t *f = &fit;
    float vdc_pu, e_pu, e_board, dt, drop;

    if (d->seq.vi_test == 0u || d->vi.done != 0u) {
        return;
    }
    if (d->seq.state == ID_IDLE || d->seq.calibrating != 0u) {
        /* stopped, or a failure's fault reset: the next start measures
         * afresh (the ISR runs the test only after the calibration) */
        if (d->vi.fitted != 0u || d->vi.test.level != 0u || d->vi.test.n != 0u || d->vi.test.t != 0u ||
            d->vi.retried != 0u) {
            d->vi.retried = 0u;
            d->vi.rs = 0.0f;
            (void)vi_curve_retry(&d->vi.test, d->vi.i1_0);   /* the first i1: init accepted it */
            d->vi.post = DRIVE_VI_NONE;
            d->vi.wait = 0u;
            d->vi.fitted = 0u;
        }
        return;
    }
    (void)vi_curve_next(&d->vi.test);   /* the schedule: each level's window, the next */
    if (d->vi.test.done == 0u || d->vi.fitted != 0u) {
        return;
    }
    d->vi.fitted = 1u;
    vi_curve_fit(&d->vi.test, b->I_base_A, b->V_base_V, f);
    d->vi.status = (uint16_t)f->status;
    if (f->status == VI_FIT_BAND && drive_vi_retry(d, f) != 0u) {
        return;
    }
    if (f->status != VI_FIT_OK) {
        d->vi.post = DRIVE_VI_REFUSED;
        return;
    }
    /* the error measured at the test's bus: the part that scales with the
     * bus is the board's dead time, the rest the devices' drop (a measured
     * error below the dead time's alone: all of it scales with the bus) */
    vdc_pu = f->vdc_V / b->V_base_V;
    e_pu = f->e_pole_V / b->V_base_V;
    e_board = vdc_pu * d->vi.dt_frac + _IQtoF(d->pwm.volt.v_drop);
    if (!(vdc_pu > 0.0f) || !(e_pu <= DRIVE_VI_E_FACTOR * e_board) ||
        !(e_pu * DRIVE_VI_E_FACTOR >= e_board)) {
        d->vi.status = (uint16_t)VI_FIT_ERROR;
        d->vi.post = DRIVE_VI_REFUSED;
        return;
    }
    d->vi.rs = f->rs_ohm / b->Z_base_ohm;
    dt = d->vi.dt_frac;
    drop = e_pu - vdc_pu * dt;
    if (drop < 0.0f) {
        dt = e_pu / vdc_pu;
        drop = 0.0f;
    }
    /* a zone narrower than VOLT_CALC_ITH_MIN_PU (about one code of the
     * current channel: 2/4096 pu) is a step to a drive that reads the current
     * in codes; the narrowest zone volt_calc holds stands for it (the 15 kW
     * motor's 100 A channel: 0.05 A against a bridge's 0.03 A) */
    if (volt_calc_curve_design(&d->vi.curve, dt, drop,
                               fmaxf(f->band_A / b->I_base_A, VOLT_CALC_ITH_MIN_PU)) !=
        VOLT_CALC_OK) {
        d->vi.status = (uint16_t)VI_FIT_BAND;
        d->vi.post = DRIVE_VI_REFUSED;
        return;
    }
    d->vi.post = DRIVE_VI_CURVE;   /* last: the curve is complete */
}
