/* The identification's target speed within the voltage
 * the bus gives (drive_target.c).
 *
 * A drive on its motor's own mains has about the motor's rated voltage as
 * the linear modulation's vdc / sqrt(3) (a 400 V motor on 400 V mains: a
 * 565 V bus gives 326 V peak per phase, the motor takes 327 V at rated
 * speed and no load), less the bridge's dead time and drops, less 15 % when
 * the mains are low.  The identification runs in linear modulation with
 * the flux constant (the regression's model, method §1), so its target is
 * the speed the voltage allows, not the rated one:
 *
 *  - at the start (background, drive_target_at_start): the configured
 *    target (ident.target_speed_rpm; 0: the rated speed), unless the
 *    measured bus cannot carry the believed motor's no-load voltage
 *    |Rs + j w Ls| i_M plus the bridge's loss at the least speed the
 *    identification can use within DRIVE_TARGET_NOLOAD_OF_VLIN of
 *    vdc / sqrt(3): the start is then refused (DRIVE_PUB_BUS_LOW).  The
 *    believed motor does not cap the target itself: its Ls is the
 *    nameplate's, up to 30 % off (believed Lm +30 % lowered the 1.1 kW
 *    motor's target to 0.82 of rated, and its set was refused);
 *  - during the acceleration (slow ISR, drive_target_headroom_out): the
 *    ramp ends at the present speed when the voltage the current loops ask
 *    of the modulator (their output and the dead-time feed-forward, low-
 *    passed over DRIVE_TARGET_TAU_S) reaches DRIVE_TARGET_HEAD_OF_VLIN of
 *    vdc / sqrt(3) on the bus it measures: the true motor's voltage, its
 *    load, the bus's sag, whatever the nameplate says;
 *  - the table of limits (drive_limits.c, DRIVE_LD_BUS) refuses only what
 *    cannot work: a configured target (or, by default, the least target)
 *    beyond the start's limit at the nominal bus.
 */
#ifndef DRIVE_TARGET_H
#define DRIVE_TARGET_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"
#include "drive_config.h"

/* The no-load voltage the start asks room for at the least target, and the
 * commanded voltage that ends the acceleration, as fractions of
 * vdc / sqrt(3) (the linear modulation's largest phase voltage); the
 * latter's low-pass (its lag 3 ms: the ramp moves 0.3 % of the rated speed
 * in it at a rated-speed-a-second ramp).  Measured before this limit
 * (paper, 1.1 kW, 15 kW, 37 kW motors on their buses, loads as given): the
 * applied voltage plus the loss reached 0.912 at most in ACCELERATE and
 * 0.946 in SETTLE (the speed loop's overshoot at the ramp's end); the head
 * limit leaves them their target and 5 % for the current loops beyond it. */
#define DRIVE_TARGET_NOLOAD_OF_VLIN 0.92f
#define DRIVE_TARGET_HEAD_OF_VLIN 0.95f
#define DRIVE_TARGET_TAU_S 0.003f

typedef struct {
    /* parameters (drive_target_init; pu of the drive's bases) */
    float rs_im;          /* Rs i_M of the believed motor, pu voltage */
    float ls_im;          /* Ls i_M, pu flux: the no-load voltage per pu speed */
    float loss_drop;      /* 2 device drops, pu voltage */
    float loss_per_vdc;   /* dead time td f_pwm: the loss per pu of bus */
    float target_pu;      /* the configured target (the rated speed when 0), pu */
    float least_pu;       /* the least target the identification can use, pu */
    _iq k_head2;          /* Q24: (DRIVE_TARGET_HEAD_OF_VLIN / sqrt(3))^2 */
    _iq k_lpf;            /* Q24: 1 - exp(-Ts_slow / DRIVE_TARGET_TAU_S) */
    /* state */
    _iq u2_f;             /* Q24 pu^2: the low-passed |u|^2 of the commanded voltage
                             (0 outside ACCELERATE: drive_target_headroom_reset) */
} drive_target_t;

/** The least target the identification can use (r/min): the largest of 20 %
 *  of the rated speed, enough encoder counts a filter time constant and,
 *  with the observer frame, its RLS gate (drive_limits.c says why each). */
float drive_target_least_rpm(const drive_config_t *c);

/** The largest speed (pu) at which the believed motor's no-load voltage plus
 *  the bridge's loss is @p k_vlin of vdc / sqrt(3), on a bus of @p vdc_pu
 *  (pu of V_base; sqrt(3) at the nominal bus); 0 when even standstill does
 *  not fit.  Float: configuration and background only. */
float drive_target_noload_max_pu(const drive_target_t *t, float vdc_pu, float k_vlin);

/** The bus (pu of V_base) on which the believed motor's no-load voltage at
 *  @p w_pu plus the loss is @p k_vlin of vdc / sqrt(3): the inverse of
 *  drive_target_noload_max_pu; FLT_MAX when the dead time alone takes
 *  that much.  Float. */
float drive_target_bus_for_pu(const drive_target_t *t, float w_pu, float k_vlin);

/** The constants from the configuration (float, once); @p Ts_slow_s: the
 *  period drive_target_headroom_out is called at.  Returns 0, or 1 if the
 *  configured target or the motor leave the target undefined. */
int16_t drive_target_init(drive_target_t *t, const drive_config_t *c, const base_values_t *b,
                          float Ts_slow_s);

/** Background, at a start: the target (pu, > 0) for the measured bus
 *  @p vdc_pu, or 0 when the bus cannot carry the least target at no load
 *  (the start is refused). */
float drive_target_at_start(const drive_target_t *t, float vdc_pu);

/** Slow ISR, in ACCELERATE: 1 when the commanded voltage (@p u_alpha,
 *  @p u_beta: the modulator's input, Q24 pu, each saturated to +-4) has
 *  reached DRIVE_TARGET_HEAD_OF_VLIN of vdc / sqrt(3) on the bus @p vdc
 *  (Q24 pu), its square low-passed (mean square: at least the square of
 *  the mean, so the test errs early).  Scaling: |u|^2 < 32, the limit's
 *  square < 64 for vdc < 13 pu: Q24, no overflow. */
uint16_t drive_target_headroom_out(drive_target_t *t, _iq u_alpha, _iq u_beta, _iq vdc);

/** Outside ACCELERATE: the low-pass restarts from 0 (one store). */
static inline void drive_target_headroom_reset(drive_target_t *t) { t->u2_f = _IQ(0.0); }

#endif /* DRIVE_TARGET_H */
