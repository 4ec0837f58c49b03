/* The identification's target speed within the voltage the bus gives.  See
 * drive_target.h. */
#include "drive_target.h"

#include <float.h>
#include <math.h>

#include "drive_design.h"

/* The least target the identification can use, the largest of:
 *  - TARGET_MIN_OF_RATED of the rated speed: the RLS separates the back-EMF
 *    term K4 w_r from the resistive and dead-time voltages only with enough
 *    speed; measured (motor_sim, IQ_MATH) the worst published error rises
 *    below it: paper 50 r/min 2.3 %, 1.1 kW 100 r/min 3.8 %, 15 kW 100 r/min
 *    3.2 %; from 20 % (280-290 r/min) all three stay within 1.3 %;
 *  - TARGET_COUNTS_PER_TAU encoder counts a time constant 1/w_c of the
 *    regression's Butterworth filter: the rotor speed w_r it filters comes
 *    from the count, whose quantisation the filter averages only over that
 *    many counts (n >= 10 x 60 w_c / (4 lines) r/min: 9.4 r/min for the
 *    paper's 1000 lines at 10 Hz, 590 r/min for 16 lines);
 *  - with orientation 1, the RLS's gate: it learns only while the stator
 *    frequency is above FOBS_RLS_WS_OVER_WC FOBS_WC_HZ = 30 Hz
 *    (drive_slow.c), i.e. 60 x 30 / p r/min (900 r/min at p = 2: at
 *    700 r/min the paper motor's adaptive sequence published 14.8 % off). */
#define TARGET_MIN_OF_RATED 0.2f
#define TARGET_COUNTS_PER_TAU 10.0f

float drive_target_least_rpm(const drive_config_t *c)
{
    float floor_obs = (c->control.orientation == DRIVE_ORIENT_FLUX_OBS)
                          ? 60.0f * FOBS_RLS_WS_OVER_WC * FOBS_WC_HZ / (float)c->motor.pole_pairs
                          : 0.0f;
    float floor_enc = TARGET_COUNTS_PER_TAU * 60.0f * c->ident.filter_wc_rad_s /
                      (4.0f * (float)c->board.encoder_lines);
    return fmaxf(fmaxf(TARGET_MIN_OF_RATED * c->motor.rated_speed_rpm, floor_enc), floor_obs);
}

float drive_target_noload_max_pu(const drive_target_noload_t *t, float vdc_pu, float k_vlin)
{
    /* the phase voltage left for the motor: k vdc / sqrt(3) less the loss
     * (which grows with the bus: the dead time takes td f_pwm of it) */
    float v = vdc_pu * (k_vlin / DRIVE_SQRT3_F - t->loss_per_vdc) - t->loss_drop;
    float x2 = v * v - t->rs_im * t->rs_im;   /* (w Ls i_M)^2 */
    if (!(v > 0.0f) || !(x2 > 0.0f) || !(t->ls_im > 0.0f)) {
        return 0.0f;
    }
    return sqrtf(x2) / t->ls_im;
}

float drive_target_bus_for_pu(const drive_target_noload_t *t, float w_pu, float k_vlin)
{
    float x = w_pu * t->ls_im;
    float per_vdc = k_vlin / DRIVE_SQRT3_F - t->loss_per_vdc;
    if (!(per_vdc > 0.0f)) {
        return FLT_MAX;
    }
    return (sqrtf(t->rs_im * t->rs_im + x * x) + t->loss_drop) / per_vdc;
}

void drive_target_noload_init(drive_target_noload_t *t, const drive_config_t *c,
                              const base_values_t *b)
{
    const drive_motor_t *m = &c->motor;
    float im_pu = m->magnetizing_current_A / b->I_base_A;

    t->rs_im = m->Rs_ohm / b->Z_base_ohm * im_pu;
    t->ls_im = m->Ls_H / b->L_base_H * im_pu;
    t->loss_drop = 2.0f * c->board.device_drop_V / b->V_base_V;
    t->loss_per_vdc = c->board.dead_time_s * c->board.pwm_freq_Hz;
}

int16_t drive_target_init(drive_target_t *t, const drive_config_t *c, const base_values_t *b,
                          float Ts_slow_s)
{
    const drive_motor_t *m = &c->motor;
    float target_rpm = (c->ident.target_speed_rpm > 0.0f) ? c->ident.target_speed_rpm
                                                          : m->rated_speed_rpm;

    t->target = _IQ(target_rpm / b->n_base_rpm);
    t->least = _IQ(drive_target_least_rpm(c) / b->n_base_rpm);
    t->k_lpf = _IQ(1.0f - expf(-Ts_slow_s / DRIVE_TARGET_TAU_S));
    t->u_f = _IQ(0.0);
    return (int16_t)(!(target_rpm > 0.0f) || !(m->Ls_H > 0.0f));
}
