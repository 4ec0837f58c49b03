/* The simulated power stage.  See plant.h. */
#include "plant.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int plant_init(plant_t *p, const sim_config_t *c, uint16_t t1pr, char *err, unsigned err_len)
{
    motor_params_t mp;
    inverter_params_t ip;
    hall_params_t hp;
    adc_f2812_params_t ap;
    encoder_params_t ep;
    uint64_t seed = (uint64_t)c->sensors.seed;

    memset(p, 0, sizeof *p);
    p->Ts_s = 1.0 / c->board.pwm_freq_Hz;
    p->t1pr = t1pr;
    p->substeps = (uint16_t)c->simulation.substeps;
    p->load_const_Nm = c->load.const_Nm;
    p->load_prop_Nm_s = c->load.prop_Nm_s;
    p->load_fan_Nm = c->load.fan_Nm;
    p->locked = (uint16_t)(c->load.locked != 0.0);
    p->w_rated_m_rad_s = c->nameplate.rated_speed_rpm * 2.0 * M_PI / 60.0;
    p->hall_a_gain_fault = 1.0;
    p->vdc_scale = 1.0;
    p->t_visible_s = -1.0;
    p->i_trip_A = c->controller.overcurrent_A;
    p->i_fs_A = c->board.current_full_scale_A;
    p->hw_trip_until_s = -1.0;
    p->hw_oc_A = c->inverter.overcurrent_hw_A;
    p->hw_delay_s = c->inverter.overcurrent_hw_delay_s;
    p->hw_pending_s = -1.0;
    p->t_hw_first_s = -1.0;

    memset(&mp, 0, sizeof mp);
    mp.Rs_ohm = c->plant.Rs_ohm;
    mp.Rr_ohm = c->plant.Rr_ohm;
    mp.Lm_H = c->plant.Lm_H;
    mp.Lls_H = c->plant.Lls_H;
    mp.Llr_H = c->plant.Llr_H;
    mp.pole_pairs = (uint16_t)c->nameplate.pole_pairs;
    mp.J_kgm2 = c->plant.J_kgm2;
    p->J_kgm2 = c->plant.J_kgm2;
    mp.B_Nm_s = c->plant.B_Nm_s;
    if (motor_init(&p->motor, &mp) != MOTOR_OK) {
        snprintf(err, err_len, "motor model rejected the [plant] parameters");
        return 1;
    }
    p->theta_m0_rad = p->motor.theta_m_rad;

    {
        /* the exact electrical step takes the torque's slope against speed
         * explicitly over a period: a mechanical time constant (at the
         * largest rotor flux the drive sets up, as sim_config_check) of at
         * least a period; a shorter one falls back to RK4 in substeps */
        double tau_e, tau_m;
        motor_time_constants(&mp, mp.Lm_H * c->controller.magnetizing_current_A, 0.0, &tau_e,
                             &tau_m);
        p->exact = (uint16_t)(tau_m >= p->Ts_s);
    }
    p->i_per_V = inverter_current_gain(p->Ts_s, mp.Rs_ohm, mp.Rr_ohm, mp.Lm_H, mp.Lls_H,
                                       mp.Llr_H);

    inverter_params_default(&ip);
    ip.vdc_V = c->inverter.vdc_V;
    ip.r_source_ohm = c->inverter.source_resistance_ohm;
    ip.ripple_V = c->inverter.ripple_V;
    ip.ripple_Hz = c->inverter.ripple_Hz;
    ip.f_pwm_Hz = c->board.pwm_freq_Hz;
    ip.dead_time_s = c->inverter.dead_time_s;
    ip.v_drop_V = c->inverter.device_drop_V;
    ip.r_on_ohm = c->inverter.r_on_ohm;
    ip.i_band_A = c->inverter.dead_time_band_A;
    ip.ideal = 0u;
    if (inverter_init(&p->inv, &ip) != 0) {
        snprintf(err, err_len, "inverter model rejected the [inverter] parameters");
        return 2;
    }

    hall_params_default(&hp);
    hp.gain_error = c->sensors.hall_gain_error_pct / 100.0;
    hp.noise_rms_A = c->sensors.hall_noise_A_rms;
    hp.offset_A = c->sensors.hall_offset_a_A;
    hp.seed = seed * 7919u + 1u;
    if (hall_init(&p->hall_a, &hp) != HALL_OK) {
        snprintf(err, err_len, "Hall sensor model rejected the [sensors] parameters");
        return 3;
    }
    hp.offset_A = c->sensors.hall_offset_b_A;
    hp.gain_error = -0.6 * c->sensors.hall_gain_error_pct / 100.0;   /* the two sensors differ */
    hp.seed = seed * 7919u + 2u;
    (void)hall_init(&p->hall_b, &hp);
    if (sig_cond_init_current(&p->cond_i, c->board.current_full_scale_A) != SIG_COND_OK ||
        sig_cond_init_vdc(&p->cond_v, c->board.vdc_full_scale_V) != SIG_COND_OK) {
        snprintf(err, err_len, "signal conditioning rejected the full-scale values");
        return 4;
    }
    adc_f2812_params_default(&ap);
    ap.noise_lsb_rms = c->sensors.adc_noise_lsb;
    ap.seed = seed * 7919u + 3u;
    (void)adc_f2812_init(&p->adc_a, &ap);
    ap.seed = seed * 7919u + 4u;
    (void)adc_f2812_init(&p->adc_b, &ap);
    ap.seed = seed * 7919u + 5u;
    if (adc_f2812_init(&p->adc_v, &ap) != ADC_F2812_OK) {
        snprintf(err, err_len, "ADC model rejected its parameters");
        return 5;
    }
    encoder_params_default(&ep);
    ep.lines = (uint16_t)c->board.encoder_lines;
    ep.seed = seed * 7919u + 6u;
    ep.theta_offset = c->sensors.encoder_offset;
    if (encoder_init(&p->enc, &ep, 0.0) != 0) {
        snprintf(err, err_len, "encoder model rejected board.encoder_lines");
        return 6;
    }
    return 0;
}

double plant_load_Nm(const plant_t *p, double w_m)
{
    double sgn = (w_m > 0.0) ? 1.0 : ((w_m < 0.0) ? -1.0 : 0.0);
    double r = w_m / p->w_rated_m_rad_s;
    return sgn * p->load_const_Nm + p->load_prop_Nm_s * w_m + sgn * p->load_fan_Nm * r * r +
           p->extra_load_Nm;
}

/* The load over the next period, held constant over it.  [load] const_Nm is
 * Coulomb friction with stiction (a conveyor, a gearbox, a pump's seals):
 * it opposes the motion and, at rest, holds the rotor while the motor's
 * torque net of the other loads stays within it.  Never a torque source: as
 * sgn(w) const_Nm held over a period it overshot through zero on every
 * period (const_Nm / J Ts of speed a period) and a large one turned the
 * rotor backwards (const_Nm 10000 on the paper motor).  So the rotor
 * sticks (its speed held at 0 for the period) when it would cross zero
 * within a period anyway, |w| <= const_Nm Ts / J, and the torque cannot
 * break it free; it breaks free in the direction of the net torque. */
static double plant_period_load_Nm(plant_t *p)
{
    motor_t *m = &p->motor;
    const double w = m->w_m_rad_s;
    const double tc = p->load_const_Nm;
    const double other = plant_load_Nm(p, w) - ((w > 0.0) ? tc : ((w < 0.0) ? -tc : 0.0));
    const double net = m->Te_Nm - other;
    p->turn_peak_rad = fmax(p->turn_peak_rad, fabs(m->theta_m_rad - p->theta_m0_rad));
    if (p->locked != 0u) {
        /* a load that cannot turn: whatever the motor's torque, it holds */
        motor_set_speed(m, 0.0);
        motor_lock_speed(m, 1u);
        p->te_hold_peak_Nm = fmax(p->te_hold_peak_Nm, fabs(m->Te_Nm));
        return m->Te_Nm;
    }
    if (tc > 0.0 && fabs(w) <= tc * p->Ts_s / p->J_kgm2 && fabs(net) <= tc) {
        motor_set_speed(m, 0.0);
        motor_lock_speed(m, 1u);
        return other + net;   /* what holds it: the torque, balanced */
    }
    motor_lock_speed(m, 0u);
    if (w == 0.0) {
        return other + ((net > 0.0) ? tc : -tc);   /* breaking free */
    }
    return plant_load_Nm(p, w);
}

void plant_inject(plant_t *p, plant_fault_t kind, double value)
{
    switch (kind) {
    case PLANT_FAULT_HALL_GAIN: p->hall_a_gain_fault = 1.0 + value; break;
    case PLANT_FAULT_HALL_LOST: p->hall_b_lost = 1u; break;
    case PLANT_FAULT_BUS_SAG: p->vdc_scale = 1.0 - value; break;
    case PLANT_FAULT_OVERVOLTAGE: p->vdc_scale = 1.0 + value; break;
    case PLANT_FAULT_ENCODER_LOST: p->encoder_frozen = 1u; break;
    case PLANT_FAULT_SHORT: p->short_L_H = value * 1e-6; break;
    case PLANT_FAULT_ADC_RAIL: p->vdc_rail = 1u; break;
    case PLANT_FAULT_CURRENT_OFFSET: p->offset_a_A = value * p->i_fs_A; break;
    case PLANT_FAULT_ENCODER_JUMP:
        /* a whole number of counts, either way (motor_sim: [-32768, 32767]):
         * through int32_t, as a negative double has no uint16_t value */
        p->qep_jump = (uint16_t)(p->qep_jump + (uint16_t)(int32_t)value);
        break;
    case PLANT_FAULT_HW_TRIP: p->hw_trip_until_s = p->t_s + value; break;
    case PLANT_FAULT_CLEAR:
        p->hall_a_gain_fault = 1.0;
        p->hall_b_lost = 0u;
        p->vdc_scale = 1.0;
        p->encoder_frozen = 0u;
        p->short_L_H = 0.0;
        p->i_short_A = 0.0;
        p->vdc_rail = 0u;
        p->offset_a_A = 0.0;
        p->hw_trip_until_s = -1.0;   /* a count jump, once taken, stays (T2 is relative) */
        break;
    case PLANT_FAULT_NONE:
    default: break;
    }
}

int plant_finite(const plant_t *p)
{
    const motor_t *m = &p->motor;
    return isfinite(m->w_m_rad_s) && isfinite(m->theta_m_rad) && isfinite(m->i_alpha_A) &&
           isfinite(m->i_beta_A) && isfinite(m->psi_r_alpha_Wb) && isfinite(m->psi_r_beta_Wb) &&
           isfinite(p->i_short_A);
}

uint16_t plant_trip_line(const plant_t *p) { return (uint16_t)(p->t_s < p->hw_trip_until_s); }

void plant_sample(plant_t *p, hal_host_port_t *port)
{
    const motor_t *m = &p->motor;
    double ia = hall_measure(&p->hall_a, m->ia_A + p->i_short_A, p->Ts_s) * p->hall_a_gain_fault +
                p->offset_a_A;
    double ib = hall_measure(&p->hall_b, m->ib_A - p->i_short_A, p->Ts_s);
    double vdc = inverter_bus_voltage_V(&p->inv, p->t_s, p->i_dc_A) * p->vdc_scale;
    double vdc_pin = sig_cond_apply(&p->cond_v, vdc);
    uint16_t visible;
    uint16_t count;

    if (p->hall_b_lost != 0u) {
        ib = 0.0;
    }
    if (p->vdc_rail != 0u) {
        vdc_pin = 3.3;   /* divider's low side open: the pin at the 3.3 V clamp */
    }
    port->adc.ia_raw = adc_f2812_convert(&p->adc_a, sig_cond_apply(&p->cond_i, ia));
    port->adc.ib_raw = adc_f2812_convert(&p->adc_b, sig_cond_apply(&p->cond_i, ib));
    port->adc.vdc_raw = adc_f2812_convert(&p->adc_v, vdc_pin);
    count = encoder_sample(&p->enc, m->theta_m_rad);
    if (p->encoder_frozen == 0u) {
        p->frozen_count = (uint16_t)(count + p->qep_jump);
    }
    port->qep_count = p->frozen_count;
    /* the first sample in which an injected fault reaches the ADC or QEP
     * (a short: once a phase current beyond the trip level reaches them) */
    visible = (uint16_t)(p->hall_a_gain_fault != 1.0 || p->hall_b_lost != 0u ||
                         p->vdc_scale != 1.0 || p->encoder_frozen != 0u ||
                         fmax(fabs(m->ia_A + p->i_short_A), fabs(m->ib_A - p->i_short_A)) >
                             p->i_trip_A ||
                         p->vdc_rail != 0u || p->offset_a_A != 0.0 ||
                         p->qep_jump != 0u || plant_trip_line(p) != 0u ||
                         p->hw_trips != 0u);
    if (visible != 0u && p->t_visible_s < 0.0) {
        p->t_visible_s = p->t_s;
    }
}

/* The motor over @p dt with the stator voltage (ua, ub) held / with the
 * stator open: the exact step, or RK4 in @p n steps (plant_t.exact). */
static void plant_motor_step(plant_t *p, double ua, double ub, double dt, uint16_t n)
{
    if (p->exact != 0u) {
        motor_step_exact(&p->motor, ua, ub, dt);
    } else {
        motor_step(&p->motor, ua, ub, dt, n);
    }
}

static void plant_motor_open(plant_t *p, double dt)
{
    if (p->exact != 0u) {
        motor_step_open_exact(&p->motor, dt);
    } else {
        motor_step_open(&p->motor, dt, p->substeps);
    }
}

/* |current| of each leg at the state @p m with the short's current @p i_sh
 * (out of leg a, into leg b). */
static void leg_currents(const motor_t *m, double i_sh, double out[3])
{
    out[0] = fabs(m->ia_A + i_sh);
    out[1] = fabs(m->ib_A - i_sh);
    out[2] = fabs(m->ic_A);
}

static void note_peaks(plant_t *p, const motor_t *m, double i_sh)
{
    double leg[3];
    double ph = fmax(fabs(m->ia_A), fmax(fabs(m->ib_A), fabs(m->ic_A)));
    leg_currents(m, i_sh, leg);
    p->i_phase_peak_A = fmax(p->i_phase_peak_A, ph);
    p->i_leg_peak_A = fmax(p->i_leg_peak_A, fmax(leg[0], fmax(leg[1], leg[2])));
}

/* The mean a-b voltage of the period that drives the short (no resistance,
 * dead time or drops: a fault current is not a precision quantity). */
static double short_vab(const plant_t *p, const double duty[3])
{
    return (duty[0] - duty[1]) * inverter_bus_voltage_V(&p->inv, p->t_s, 0.0) * p->vdc_scale;
}

/* The bridge on for @p t_on of the period (the voltage of the period's
 * second pass), then open for the rest: the comparator's trip. */
static void period_cut(plant_t *p, const motor_state_t *m0, const double duty[3],
                       double t_on)
{
    motor_t *m = &p->motor;
    double i_sh;
    uint16_t n_on = (uint16_t)ceil((double)p->substeps * t_on / p->Ts_s);
    motor_restore(m, m0);
    if (t_on > 0.0) {
        plant_motor_step(p, p->inv.v_alpha_V * p->vdc_scale, p->inv.v_beta_V * p->vdc_scale,
                         t_on, (n_on == 0u) ? 1u : n_on);
    }
    i_sh = (p->short_L_H > 0.0) ? p->i_short_A + short_vab(p, duty) * t_on / p->short_L_H : 0.0;
    note_peaks(p, m, i_sh);   /* the currents when the outputs go off */
    plant_motor_open(p, p->Ts_s - t_on);
    p->i_short_A = 0.0;       /* the short's loop current freewheels out within us */
    p->i_dc_A = p->inv.i_dc_A * t_on / p->Ts_s;
    p->hw_fired = 1u;
    p->hw_trips++;
    if (p->t_hw_first_s < 0.0) {
        p->t_hw_first_s = p->t_s + t_on;
    }
}

/* The comparator over the period just stepped from the phase currents
 * @p i0 (and the short's current @p i_sh0) at its start: when a leg crossed
 * the level, the time into the period at which the outputs go off
 * (crossing + delay; may lie beyond the period), else -1. */
static double comparator_off_time(const plant_t *p, const double i0[3], double i_sh0)
{
    double l0[3], l1[3], t_cross = -1.0;
    int x;
    if (!(p->hw_oc_A > 0.0)) {
        return -1.0;
    }
    l0[0] = fabs(i0[0] + i_sh0);   /* as leg_currents */
    l0[1] = fabs(i0[1] - i_sh0);
    l0[2] = fabs(i0[2]);
    leg_currents(&p->motor, p->i_short_A, l1);
    for (x = 0; x < 3; x++) {
        if (l1[x] > p->hw_oc_A) {
            /* linear between the ends (the start is below: the bridge would
             * already be off otherwise) */
            double f = (l0[x] >= p->hw_oc_A) ? 0.0 : (p->hw_oc_A - l0[x]) / (l1[x] - l0[x]);
            double t = f * p->Ts_s;
            if (t_cross < 0.0 || t < t_cross) {
                t_cross = t;
            }
        }
    }
    return (t_cross < 0.0) ? -1.0 : t_cross + p->hw_delay_s;
}

void plant_period(plant_t *p, const hal_pwm_compare_t *active, uint16_t outputs_enabled)
{
    motor_t *m = &p->motor;

    p->hw_fired = 0u;
    motor_set_load_constant(m, plant_period_load_Nm(p));
    if (outputs_enabled != 0u) {
        double duty[3], i_abc[3];
        motor_state_t m0;
        const double i_sh0 = p->i_short_A;
        double t_off;
        uint16_t x;
        for (x = 0u; x < 3u; x++) {
            duty[x] = inverter_duty_from_cmpr(active->cmpr[x], p->t1pr);
        }
        motor_save(m, &m0);
        i_abc[0] = m->ia_A;
        i_abc[1] = m->ib_A;
        i_abc[2] = m->ic_A;
        {
            /* two passes: the dead time of each switching edge follows the
             * current at that edge, which depends on the voltage of this
             * very period.  Pass 1 extrapolates the current's change from
             * the last period; pass 2 redoes the period with the change
             * consistent with its own voltage (inverter_step_implicit: the
             * motor is linear in the voltage over a period, so pass 1's
             * change and the motor's current gain give the change under any
             * other error; solved, not iterated, so a transition steeper
             * than the motor's sigma Ls / Ts settles instead of cycling). */
            const inverter_t inv0 = p->inv;
            double di[3];
            inverter_step(&p->inv, p->t_s, duty, i_abc);
            if (p->exact != 0u) {
                /* the exact step is affine in the voltage: pass 1's end
                 * current without stepping (pass 2 reuses its transition) */
                double i_al, i_be, i_b;
                motor_predict_current(m, p->inv.v_alpha_V * p->vdc_scale,
                                      p->inv.v_beta_V * p->vdc_scale, p->Ts_s, &i_al, &i_be);
                /* the inverse Clarke as the motor's outputs */
                i_b = -0.5 * i_al + 0.5 * 1.732050807568877293527 * i_be;
                di[0] = i_al - i_abc[0];
                di[1] = i_b - i_abc[1];
                di[2] = (-i_al - i_b) - i_abc[2];
            } else {
                motor_step(m, p->inv.v_alpha_V * p->vdc_scale, p->inv.v_beta_V * p->vdc_scale,
                           p->Ts_s, p->substeps);
                di[0] = m->ia_A - i_abc[0];
                di[1] = m->ib_A - i_abc[1];
                di[2] = m->ic_A - i_abc[2];
                motor_restore(m, &m0);
            }
            {
                /* as before pass 1, but for the ripple it evaluated (the
                 * same instant in pass 2) */
                const double r_at = p->inv.ripple_at_s, r_now = p->inv.ripple_now_V;
                p->inv = inv0;
                p->inv.ripple_at_s = r_at;
                p->inv.ripple_now_V = r_now;
            }
            (void)inverter_step_implicit(&p->inv, p->t_s, duty, i_abc, di,
                                         p->i_per_V * p->vdc_scale);
            if (p->hw_pending_s >= 0.0) {
                /* the comparator crossed near the end of the last period */
                const double t_on = fmin(p->hw_pending_s, p->Ts_s);
                p->hw_pending_s = -1.0;
                period_cut(p, &m0, duty, t_on);
                p->t_s += p->Ts_s;
                return;
            }
            plant_motor_step(p, p->inv.v_alpha_V * p->vdc_scale,
                             p->inv.v_beta_V * p->vdc_scale, p->Ts_s, p->substeps);
        }
        p->i_dc_A = p->inv.i_dc_A;
        if (p->short_L_H > 0.0) {
            /* legs a and b drive the short: its current integrates the mean
             * a-b voltage of the period */
            p->i_short_A += short_vab(p, duty) * p->Ts_s / p->short_L_H;
        }
        t_off = comparator_off_time(p, i_abc, i_sh0);
        if (t_off >= p->Ts_s) {
            p->hw_pending_s = t_off - p->Ts_s;   /* off early in the next period */
        } else if (t_off >= 0.0) {
            p->i_short_A = i_sh0;
            period_cut(p, &m0, duty, t_off);
        } else {
            /* no crossing */
        }
    } else {
        p->i_short_A = 0.0;   /* bridge off: the loop current freewheels out within us */
        p->hw_pending_s = -1.0;
        plant_motor_open(p, p->Ts_s);
        p->i_dc_A = 0.0;
    }
    note_peaks(p, m, p->i_short_A);
    p->t_s += p->Ts_s;
}
