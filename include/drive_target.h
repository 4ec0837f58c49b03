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
 *  - at each start the configured target (ident.target_speed_rpm; 0: the
 *    rated speed), not lowered from the believed motor: its Ls is the
 *    nameplate's, up to 30 % off (believed Lm +30 % lowered the 1.1 kW
 *    motor's target to 0.82 of rated, and its set was refused; and on a
 *    bus 15 % low it refused the start of a motor that runs there);
 *  - during the acceleration (slow ISR, drive_target_step): the ramp ends
 *    at the present speed once the voltage the current loops command of
 *    the modulator (their output and the dead-time feed-forward),
 *    low-passed over DRIVE_TARGET_TAU_S, reaches the current check's
 *    voltage limit, 0.95 of vdc / sqrt(3) on the bus it measures: the true
 *    motor's voltage, its load, the bus's sag, whatever the nameplate says;
 *    if that is
 *    below the least target the identification can use, the drive stops
 *    it there (DRIVE_PUB_BUS_LOW: the bus cannot carry the identification);
 *  - the table of limits (drive_limits.c, DRIVE_LD_BUS) refuses only what
 *    cannot work with the motor the user gives: a configured target whose
 *    no-load voltage is beyond DRIVE_TARGET_NOLOAD_OF_VLIN of vdc / sqrt(3)
 *    at the nominal bus; by default, the least target even with the
 *    believed Ls at its low end, Ls / (1 + DRIVE_TARGET_LS_TOL): the drive
 *    measures the true motor's voltage at each start (above), so a
 *    nameplate whose Lm is high must not refuse a motor that runs (the
 *    37 kW 690 V motor on its 976 V bus, nameplate Lm +30 %: refused, while
 *    the true motor reaches its least target at 0.65 of the bus's linear
 *    range).
 */
#ifndef DRIVE_TARGET_H
#define DRIVE_TARGET_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"
#include "drive_config.h"

/* The no-load voltage the configuration asks room for, as a fraction of
 * vdc / sqrt(3) (the linear modulation's largest phase voltage), and the
 * low-pass of the commanded voltage that ends the acceleration at the
 * current check's limit (drive_slow.c, 0.95 of it): its lag 3 ms, the ramp
 * moves 0.3 % of the rated speed in it at a rated-speed-a-second ramp (a
 * count of the samples at the limit instead, with the bus's 5 % ripple or
 * the dead-time feed-forward's steps making the limit come and go, either
 * ended the ramp too late, a set published 3.1 % off, or too early, below
 * the least target on 97 of 1 152 healthy runs).  Measured before this
 * limit (paper, 1.1 kW, 15 kW, 37 kW motors on their buses, loads as
 * given): the applied voltage plus the loss reached at most 0.912 in
 * ACCELERATE and 0.946 in SETTLE (the speed loop's overshoot at the ramp's
 * end): their target does not move. */
#define DRIVE_TARGET_NOLOAD_OF_VLIN 0.92f
#define DRIVE_TARGET_TAU_S 0.003f
/* How far the nameplate's Ls may be high when the default target is checked
 * (the nuisance sweep's nameplate errors, tools/nuisance_sweep.py: Lm -30 %
 * to +30 %). */
#define DRIVE_TARGET_LS_TOL 0.3f

/** The believed motor's no-load voltage (the configuration's check,
 *  drive_limits.c DRIVE_LD_BUS; pu of the drive's bases). */
typedef struct {
    float rs_im;          /* Rs i_M of the believed motor, pu voltage */
    float ls_im;          /* Ls i_M, pu flux: the no-load voltage per pu speed */
    float loss_drop;      /* 2 device drops, pu voltage */
    float loss_per_vdc;   /* dead time td f_pwm: the loss per pu of bus */
} drive_target_noload_t;

typedef struct {
    /* parameters (drive_target_init) */
    _iq target;           /* Q24 pu: the configured target (the rated speed when 0) */
    _iq least;            /* Q24 pu: the least target the identification can use */
    _iq k_lpf;            /* Q24: 1 - exp(-Ts_slow / DRIVE_TARGET_TAU_S) */
    /* state */
    _iq u_f;              /* Q24 pu: the commanded voltage's magnitude, low-passed */
    /* output */
    uint16_t at_limit;    /* u_f at the limit (drive_target_step): ACCELERATE ends */
} drive_target_t;

/** The least target the identification can use (r/min): the largest of 20 %
 *  of the rated speed, enough encoder counts a filter time constant and,
 *  with the observer frame, its RLS gate (drive_limits.c says why each). */
float drive_target_least_rpm(const drive_config_t *c);

/** The largest speed (pu) at which the believed motor's no-load voltage plus
 *  the bridge's loss is @p k_vlin of vdc / sqrt(3), on a bus of @p vdc_pu
 *  (pu of V_base; sqrt(3) at the nominal bus); 0 when even standstill does
 *  not fit.  Float: configuration and background only. */
float drive_target_noload_max_pu(const drive_target_noload_t *t, float vdc_pu, float k_vlin);

/** The bus (pu of V_base) on which the believed motor's no-load voltage at
 *  @p w_pu plus the loss is @p k_vlin of vdc / sqrt(3): the inverse of
 *  drive_target_noload_max_pu; FLT_MAX when the dead time alone takes
 *  that much.  Float. */
float drive_target_bus_for_pu(const drive_target_noload_t *t, float w_pu, float k_vlin);

/** The believed motor's no-load figures from the configuration (float). */
void drive_target_noload_init(drive_target_noload_t *t, const drive_config_t *c,
                              const base_values_t *b);

/** The constants from the configuration (float, once); @p Ts_slow_s: the
 *  period drive_target_headroom_out is called at.  Returns 0, or 1 if the
 *  configured target or the motor leave the target undefined. */
int16_t drive_target_init(drive_target_t *t, const drive_config_t *c, const base_values_t *b,
                          float Ts_slow_s);

/** Slow ISR, once a slow period: the commanded voltage's magnitude @p u
 *  into the low-pass; at_limit 1 when that is at the limit @p lim (Q24 pu,
 *  both below 64: |difference| < 64, the product < 64, no overflow). */
static inline void drive_target_step(drive_target_t *t, _iq u, _iq lim)
{
    t->u_f += _IQmpy(t->k_lpf, u - t->u_f);
    t->at_limit = (uint16_t)(t->u_f >= lim);
}

#endif /* DRIVE_TARGET_H */
