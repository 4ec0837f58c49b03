/**
 * @file inverter_model.c
 * Averaged two-level bridge; see inverter_model.h.
 */
#include "inverter_model.h"

#include <math.h>
#include <string.h>

#define INV_TWO_PI 6.283185307179586476925
#define INV_SQRT3 1.732050807568877293527

static int inv_nonneg(double v) { return isfinite(v) && (v >= 0.0); }

static double inv_clamp(double v, double lo, double hi)
{
    return (v < lo) ? lo : ((v > hi) ? hi : v);
}

void inverter_params_default(inverter_params_t *p)
{
    p->vdc_V = 54.0;
    p->r_source_ohm = 0.05;
    p->ripple_V = 0.0;
    p->ripple_Hz = 100.0;
    p->f_pwm_Hz = 15000.0;
    p->dead_time_s = 1.0e-6;
    p->v_drop_V = 0.3;
    p->r_on_ohm = 0.01;
    p->i_band_A = 0.1;
    p->ideal = 0u;
}

inverter_status_t inverter_init(inverter_t *inv, const inverter_params_t *p)
{
    inverter_status_t st = INV_OK;

    if ((inv == NULL) || (p == NULL)) {
        return INV_ERR_NULL;
    }
    memset(inv, 0, sizeof(*inv));
    if (!isfinite(p->vdc_V) || !(p->vdc_V > 0.0)) {
        st = INV_ERR_VDC;
    } else if (!inv_nonneg(p->r_source_ohm)) {
        st = INV_ERR_RSOURCE;
    } else if (!inv_nonneg(p->ripple_V) || !inv_nonneg(p->ripple_Hz)) {
        st = INV_ERR_RIPPLE;
    } else if (!isfinite(p->f_pwm_Hz) || !(p->f_pwm_Hz > 0.0)) {
        st = INV_ERR_FPWM;
    } else if (!inv_nonneg(p->dead_time_s) ||
               !(p->dead_time_s < 0.5 / p->f_pwm_Hz)) {
        st = INV_ERR_DEADTIME;
    } else if (!inv_nonneg(p->v_drop_V)) {
        st = INV_ERR_DROP;
    } else if (!inv_nonneg(p->r_on_ohm)) {
        st = INV_ERR_RON;
    } else if (!isfinite(p->i_band_A) || !(p->i_band_A > 0.0)) {
        st = INV_ERR_BAND;
    } else {
        /* all valid */
    }
    if (st != INV_OK) {
        return st;
    }
    inv->p = *p;
    inv->Ts_s = 1.0 / p->f_pwm_Hz;
    if (p->ideal != 0u) {
        inv->td_frac = 0.0;
        inv->v_drop_V = 0.0;
        inv->r_on_ohm = 0.0;
        inv->r_source_ohm = 0.0;
        inv->ripple_V = 0.0;
    } else {
        inv->td_frac = p->dead_time_s * p->f_pwm_Hz;
        inv->v_drop_V = p->v_drop_V;
        inv->r_on_ohm = p->r_on_ohm;
        inv->r_source_ohm = p->r_source_ohm;
        inv->ripple_V = p->ripple_V;
    }
    inv->vdc_V = p->vdc_V;
    return INV_OK;
}

/* s(i): -1..1, linear over |i| < i_band (dead-time transition) */
static double inv_sgn(const inverter_t *inv, double i_A)
{
    return inv_clamp(i_A / inv->p.i_band_A, -1.0, 1.0);
}

double inverter_bus_voltage_V(const inverter_t *inv, double t_s, double i_dc_A)
{
    return inv->p.vdc_V + inv->ripple_V * sin(INV_TWO_PI * inv->p.ripple_Hz * t_s) -
           inv->r_source_ohm * i_dc_A;
}

void inverter_step(inverter_t *inv, double t_s, const double duty[3],
                   const double i_abc_A[3])
{
    double di[3];
    int x;
    for (x = 0; x < 3; x++) {
        /* change over this period, extrapolated from the last one */
        di[x] = (inv->started != 0u) ? (i_abc_A[x] - inv->i_A[x]) : 0.0;
    }
    inverter_step_slope(inv, t_s, duty, i_abc_A, di);
}

void inverter_step_slope(inverter_t *inv, double t_s, const double duty[3],
                         const double i_abc_A[3], const double di_A[3])
{
    double sgn[3];
    double i_mid_A[3];
    double i_dc = 0.0;
    double vn;
    int x;

    inv->t_s = t_s;
    for (x = 0; x < 3; x++) {
        const double d = isfinite(duty[x]) ? inv_clamp(duty[x], 0.0, 1.0) : 0.0;
        const double i0 = i_abc_A[x];
        const double di = isfinite(di_A[x]) ? di_A[x] : 0.0;
        const double i_mid = i0 + 0.5 * di;
        inv->duty[x] = d;
        inv->i_A[x] = i0;
        /* the conduction drops follow the period-mean current */
        sgn[x] = inv_sgn(inv, i_mid);
        i_mid_A[x] = i_mid;
        if ((d > 0.0) && (d < 1.0)) {
            /* the upper switch is on around the middle of the period, from
             * (1 - d)/2 to (1 + d)/2 Ts: each of the two edges loses or gains
             * td/2 by the sign of the current at that edge */
            const double s_edges = 0.5 * (inv_sgn(inv, i0 + 0.5 * (1.0 - d) * di) +
                                          inv_sgn(inv, i0 + 0.5 * (1.0 + d) * di));
            inv->d_eff[x] = inv_clamp(d - inv->td_frac * s_edges, 0.0, 1.0);
        } else {
            inv->d_eff[x] = d; /* no switching edge, no dead time */
        }
        i_dc += inv->d_eff[x] * i_mid;
    }
    inv->started = 1u;
    inv->i_dc_A = i_dc;
    /* i_dc does not depend on Vdc, so the bus equation is explicit */
    inv->vdc_V = inverter_bus_voltage_V(inv, t_s + 0.5 * inv->Ts_s, i_dc);
    for (x = 0; x < 3; x++) {
        inv->v_pole_V[x] = inv->d_eff[x] * inv->vdc_V - inv->v_drop_V * sgn[x] -
                           inv->r_on_ohm * i_mid_A[x];
    }
    vn = (inv->v_pole_V[0] + inv->v_pole_V[1] + inv->v_pole_V[2]) / 3.0;
    for (x = 0; x < 3; x++) {
        inv->v_phase_V[x] = inv->v_pole_V[x] - vn;
    }
    inv->v_alpha_V = inv->v_phase_V[0];
    inv->v_beta_V = (inv->v_phase_V[1] - inv->v_phase_V[2]) / INV_SQRT3;
}

double inverter_duty_from_cmpr(uint16_t cmpr, uint16_t t1pr)
{
    if ((t1pr == 0u) || (cmpr >= t1pr)) {
        return 0.0;
    }
    return (double)(t1pr - cmpr) / (double)t1pr;
}
