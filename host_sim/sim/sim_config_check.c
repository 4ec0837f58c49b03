/* The checks of a parsed configuration.  See sim_config_check.h. */
#include "sim_config_check.h"

#include <math.h>
#include <stdlib.h>

#include "drive_limits.h"
#include "drive_types.h"
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

/* Peak phase voltage the simulated motor needs at rated speed with the
 * magnetising current and the rest of the rated current as torque current
 * (steady state in the rotor-flux frame: u_d = Rs i_d - w sigma Ls i_q,
 * u_q = Rs i_q + w Ls i_d). */
static double rated_voltage_need_V(const sim_config_t *c)
{
    const sim_plant_t *p = &c->plant;
    double Ls = p->Lm_H + p->Lls_H, Lr = p->Lm_H + p->Llr_H;
    double sigma = 1.0 - p->Lm_H * p->Lm_H / (Ls * Lr);
    double w = 2.0 * M_PI * c->nameplate.rated_speed_rpm / 60.0 * c->nameplate.pole_pairs;
    double ipk = sqrt(2.0) * c->nameplate.rated_current_A;
    double id = c->controller.magnetizing_current_A;
    double iq = (ipk > id) ? sqrt(ipk * ipk - id * id) : 0.0;
    double ud = p->Rs_ohm * id - w * sigma * Ls * iq;
    double uq = p->Rs_ohm * iq + w * Ls * id;
    return sqrt(ud * ud + uq * uq);
}

/* The simulated world against the drive: the bus the bridge runs on and the
 * motor the drive magnetises.  (A believed Lm above the true Ls is a wrong
 * nameplate, not an unphysical model, and accepted: the believed Ls keeps
 * the leakage; the wrong-nameplate sweeps go to Lm +50 %.) */
static int check_world(const sim_config_t *c, char *err, size_t len)
{
    const sim_inverter_t *inv = &c->inverter;
    const sim_plant_t *p = &c->plant;
    double vmax_phase = inv->vdc_V / sqrt(3.0);
    double need = rated_voltage_need_V(c);
    /* what the real bridge loses (its dead time and drops: the compensation
     * asks for it on top), the drive's table's formula */
    double loss = (double)drive_limits_bridge_loss_V((float)inv->vdc_V, (float)inv->dead_time_s,
                                                     (float)c->board.pwm_freq_Hz,
                                                     (float)inv->device_drop_V);
    double tr = (p->Lm_H + p->Llr_H) / p->Rr_ohm;

    if (!(c->controller.vdc_min_V < inv->vdc_V && inv->vdc_V < c->controller.vdc_max_V)) {
        sim_config_set_err(err, len, "key 'inverter.vdc_V' = %g V (default board.vdc_nominal_V) "
                           "is outside the drive's trip levels (controller.vdc_min_V, "
                           "controller.vdc_max_V) = (%g, %g) V", inv->vdc_V,
                           c->controller.vdc_min_V, c->controller.vdc_max_V);
        return 1;
    }
    if (need + loss > 0.95 * vmax_phase) {
        sim_config_set_err(err, len, "key 'inverter.vdc_V' = %g V (default board.vdc_nominal_V) "
                           "is too low for rated speed: the simulated motor needs %.1f V peak "
                           "per phase and the bridge loses %.1f V (2 inverter.device_drop_V + "
                           "vdc inverter.dead_time_s board.pwm_freq_Hz), the bus gives %.1f V "
                           "(with 5 %% margin)", inv->vdc_V, need, loss, 0.95 * vmax_phase);
        return 1;
    }
    if (c->ident.magnetize_s < 5.0 * tr) {
        sim_config_set_err(err, len, "key 'ident.magnetize_s' = %g s is shorter than 5 Tr of the "
                           "simulated motor (plant) = %g s", c->ident.magnetize_s, 5.0 * tr);
        return 1;
    }
    return 0;
}

int sim_config_cross_check(const sim_config_t *c, char *err, size_t len)
{
    int rc = check_ratings(&c->nameplate, err, len);
    if (rc == 0) {
        rc = check_drive(c, err, len);
    }
    return (rc != 0) ? rc : check_world(c, err, len);
}
