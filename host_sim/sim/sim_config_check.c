/* The checks of a parsed configuration.  See sim_config_check.h. */
#include "sim_config_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "drive_limits.h"
#include "drive_types.h"
#include "motor_model.h"
#include "sim_limits.h"

/* rated_voltage_V and rated_power_W are informative (the drive reads
 * neither): when both are given, the output power cannot exceed the
 * apparent power at rated current, which catches a wrong one of the three. */
static int check_ratings(const sim_nameplate_t *n, char *err, size_t len)
{
    double s = sqrt(3.0) * n->rated_voltage_V * n->rated_current_A;
    if (n->rated_voltage_V > 0.0 && n->rated_power_W > 0.0 && n->rated_power_W > s) {
        sim_config_set_err(err, len, "key 'nameplate.rated_power_W' = %g W is above the apparent "
                           "power sqrt(3) nameplate.rated_voltage_V nameplate.rated_current_A = "
                           "%g VA", n->rated_power_W, s);
        return 1;
    }
    return 0;
}

/* The drive side, as the firmware will judge it: the table of limits names
 * what fails; drive_init runs too, so that a limit of a module the table
 * does not hold cannot slip through (the fuzz target looks for that). */
static int check_drive(const sim_config_t *c, char *err, size_t len)
{
    drive_config_t dc;
    drive_limit_fail_t f;
    drive_t *d;
    int16_t st;

    sim_config_to_drive(c, &dc);
    if (drive_config_check(&dc, &f) != DRIVE_CFG_OK) {
        sim_limit_message(err, len, &f);
        return 1;
    }
    d = (drive_t *)malloc(sizeof *d);
    if (d == NULL) {   /* (drive_t is large: not on the stack) */
        sim_config_set_err(err, len, "out of memory");
        return 1;
    }
    st = drive_init(d, &dc);
    free(d);
    if (st != DRIVE_CFG_OK) {
        sim_config_set_err(err, len, "drive_init rejected the configuration: %s (a limit "
                           "include/drive_limits.h does not hold)", drive_cfg_status_str(st));
        return SIM_CONFIG_ERR_UNLISTED;
    }
    return 0;
}

/* The speed the drive lets the motor reach: its encoder check trips above
 * 4 pu of electrical speed (DRIVE_ENC_SPEED_MAX_PU, src/app/drive_design.h). */
#define SIM_SPEED_BOUND_PU 4.0

/* What the plant can integrate.
 *  - RK4 substep h = 1 / (board.pwm_freq_Hz simulation.substeps): every
 *    time constant the motor model integrates at least h.  RK4 is stable on
 *    a decaying mode while h/tau < 2.785 and accurate to about 2 % a step at
 *    h/tau = 1; beyond, the state grows without bound and becomes NaN.  The
 *    electrical one is the fast root of the stator-rotor network; the
 *    mechanical one J over the torque's slope against speed, the rotor flux's
 *    1.5 p^2 psi_r^2 / Rr (psi_r: plant.Lm_H controller.magnetizing_current_A,
 *    the largest the drive sets up) plus plant.B_Nm_s.
 *  - The load torque is held over each PWM period (plant_period), an
 *    explicit step of Ts: stable while Ts times its slope over J stays below
 *    2; asked to be at most 1, with the slope at the largest speed the drive
 *    allows (4 pu: the fan load's slope grows with speed).
 * A paper motor of 1e-7 kg m^2: tau_m = 3.2 us against h = 16.7 us. */
static int check_integration(const sim_config_t *c, char *err, size_t len)
{
    const sim_plant_t *p = &c->plant;
    motor_params_t mp;
    double Ts = 1.0 / c->board.pwm_freq_Hz;
    double h = Ts / c->simulation.substeps;
    double w_rated = c->nameplate.rated_speed_rpm * 2.0 * M_PI / 60.0;
    double w_max = SIM_SPEED_BOUND_PU * 2.0 * M_PI * c->nameplate.rated_freq_Hz /
                   c->nameplate.pole_pairs;
    double psi = p->Lm_H * c->controller.magnetizing_current_A;
    double load_slope = c->load.prop_Nm_s + 2.0 * c->load.fan_Nm * w_max / (w_rated * w_rated);
    double tau_e, tau_m, tau_load;

    memset(&mp, 0, sizeof mp);
    mp.Rs_ohm = p->Rs_ohm;
    mp.Rr_ohm = p->Rr_ohm;
    mp.Lm_H = p->Lm_H;
    mp.Lls_H = p->Lls_H;
    mp.Llr_H = p->Llr_H;
    mp.pole_pairs = (uint16_t)c->nameplate.pole_pairs;
    mp.J_kgm2 = p->J_kgm2;
    mp.B_Nm_s = p->B_Nm_s;
    motor_time_constants(&mp, psi, 0.0, &tau_e, &tau_m);
    tau_load = (load_slope > 0.0) ? p->J_kgm2 / load_slope : HUGE_VAL;
    if (!(tau_m >= h)) {
        sim_config_set_err(err, len, "key 'plant.J_kgm2' = %g kg m^2 is too small to integrate: "
                           "the simulated motor's mechanical time constant J / (1.5 p^2 psi_r^2 "
                           "/ plant.Rr_ohm + plant.B_Nm_s) = %.3g s is shorter than the "
                           "integration substep 1 / (board.pwm_freq_Hz simulation.substeps) = "
                           "%.3g s (RK4 diverges beyond 2.8 substeps a time constant); at least "
                           "%.3g kg m^2 with %g substeps", p->J_kgm2, tau_m, h,
                           p->J_kgm2 * h / tau_m, c->simulation.substeps);
        return 1;
    }
    if (!(tau_load >= Ts)) {
        sim_config_set_err(err, len, "key 'plant.J_kgm2' = %g kg m^2 is too small to integrate: "
                           "J over the load's slope at 4 pu of speed (load.prop_Nm_s, "
                           "load.fan_Nm) = %.3g s is shorter than the PWM period %.3g s over "
                           "which the plant holds the load torque (that explicit step diverges "
                           "beyond 2 periods a time constant); at least %.3g kg m^2",
                           p->J_kgm2, tau_load, Ts, load_slope * Ts);
        return 1;
    }
    if (!(tau_e >= h)) {
        sim_config_set_err(err, len, "the simulated motor's electrical time constant (the fast "
                           "root of its stator-rotor network: plant.Rs_ohm, plant.Rr_ohm, "
                           "plant.Lm_H, plant.Lls_H, plant.Llr_H) = %.3g s is shorter than the "
                           "integration substep 1 / (board.pwm_freq_Hz simulation.substeps) = "
                           "%.3g s (RK4 diverges beyond 2.8 substeps a time constant): raise the "
                           "leakage inductances or simulation.substeps", tau_e, h);
        return 1;
    }
    return 0;
}

/* The simulated world against the drive: the bus the bridge runs on and the
 * motor the drive magnetises.  Only what cannot work: the world's bus
 * outside the drive's trip levels (it would trip at once), a comparator
 * below the firmware's trip, a motor the plant cannot integrate, a
 * magnetisation shorter than the true motor's flux needs.  A bus that
 * cannot carry the rated point in linear modulation is the world of real
 * drives (a 400 V motor on 400 V mains): the drive identifies within the
 * voltage it has (drive_target.h) and is judged on it.  (A believed Lm
 * above the true Ls is a wrong nameplate, not an unphysical model, and
 * accepted: the believed Ls keeps the leakage; the wrong-nameplate sweeps
 * go to Lm +50 %.) */
static int check_world(const sim_config_t *c, char *err, size_t len)
{
    const sim_inverter_t *inv = &c->inverter;
    const sim_plant_t *p = &c->plant;
    double tr = (p->Lm_H + p->Llr_H) / p->Rr_ohm;

    if (!(c->controller.vdc_min_V < inv->vdc_V && inv->vdc_V < c->controller.vdc_max_V)) {
        sim_config_set_err(err, len, "key 'inverter.vdc_V' = %g V (default board.vdc_nominal_V) "
                           "is outside the drive's trip levels (controller.vdc_min_V, "
                           "controller.vdc_max_V) = (%g, %g) V", inv->vdc_V,
                           c->controller.vdc_min_V, c->controller.vdc_max_V);
        return 1;
    }
    if (!(c->controller.vdc_min_V < inv->vdc_V - inv->ripple_V &&
          inv->vdc_V + inv->ripple_V < c->controller.vdc_max_V)) {
        sim_config_set_err(err, len, "key 'inverter.ripple_V' = %g V takes the bus (%g V) "
                           "outside the drive's trip levels (controller.vdc_min_V, "
                           "controller.vdc_max_V) = (%g, %g) V at its troughs or peaks",
                           inv->ripple_V, inv->vdc_V, c->controller.vdc_min_V,
                           c->controller.vdc_max_V);
        return 1;
    }
    if (inv->overcurrent_hw_A > 0.0 && !(inv->overcurrent_hw_A > c->controller.overcurrent_A)) {
        sim_config_set_err(err, len, "key 'inverter.overcurrent_hw_A' = %g A is not above the "
                           "firmware's trip controller.overcurrent_A = %g A (the comparator "
                           "backs the firmware's protection up; 0: no comparator)",
                           inv->overcurrent_hw_A, c->controller.overcurrent_A);
        return 1;
    }
    if (check_integration(c, err, len) != 0) {
        return 1;
    }
    if (c->ident.magnetize_s < 5.0 * tr) {
        sim_config_set_err(err, len, "key 'ident.magnetize_s' = %g s is shorter than 5 Tr of the "
                           "simulated motor (plant) = %g s", c->ident.magnetize_s, 5.0 * tr);
        return 1;
    }
    return 0;
}

int sim_config_drive_check(const sim_config_t *c, char *err, size_t len)
{
    int rc = check_ratings(&c->nameplate, err, len);
    return (rc != 0) ? rc : check_drive(c, err, len);
}

int sim_config_cross_check(const sim_config_t *c, char *err, size_t len)
{
    int rc = sim_config_drive_check(c, err, len);
    return (rc != 0) ? rc : check_world(c, err, len);
}
