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
    inv->ripple_at_s = (double)NAN;
    return INV_OK;
}

/* s(i): -1..1, linear over |i| < i_band (dead-time transition) */
static double inv_sgn(const inverter_t *inv, double i_A)
{
    /* outside the band without the division: the same values (i >= b
     * gives i/b >= 1 after rounding, i < b gives i/b <= 1) */
    const double b = inv->p.i_band_A;
    if (i_A >= b) {
        return 1.0;
    }
    if (i_A <= -b) {
        return -1.0;
    }
    return inv_clamp(i_A / b, -1.0, 1.0);
}

double inverter_bus_voltage_V(const inverter_t *inv, double t_s, double i_dc_A)
{
    /* no ripple: no sin (vdc + 0 is vdc exactly) */
    const double ripple =
        (inv->ripple_V != 0.0) ? inv->ripple_V * sin(INV_TWO_PI * inv->p.ripple_Hz * t_s) : 0.0;
    return inv->p.vdc_V + ripple - inv->r_source_ohm * i_dc_A;
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
    /* i_dc does not depend on Vdc, so the bus equation is explicit
     * (inverter_bus_voltage_V, the ripple's sin kept for the same instant) */
    {
        const double tm = t_s + 0.5 * inv->Ts_s;
        if (inv->ripple_V == 0.0) {
            inv->vdc_V = inverter_bus_voltage_V(inv, tm, i_dc);
        } else {
            if (!(inv->ripple_at_s == tm)) {
                inv->ripple_at_s = tm;
                inv->ripple_now_V = inv->ripple_V * sin(INV_TWO_PI * inv->p.ripple_Hz * tm);
            }
            inv->vdc_V = inv->p.vdc_V + inv->ripple_now_V - inv->r_source_ohm * i_dc;
        }
    }
    for (x = 0; x < 3; x++) {
        inv->v_pole_V[x] = inv->d_eff[x] * inv->vdc_V - inv->v_drop_V * sgn[x] -
                           inv->r_on_ohm * i_mid_A[x];
    }
    /* by the constants' reciprocals (a division's latency, twice a period,
     * for the last bit) */
    vn = (inv->v_pole_V[0] + inv->v_pole_V[1] + inv->v_pole_V[2]) * (1.0 / 3.0);
    for (x = 0; x < 3; x++) {
        inv->v_phase_V[x] = inv->v_pole_V[x] - vn;
    }
    inv->v_alpha_V = inv->v_phase_V[0];
    inv->v_beta_V = (inv->v_phase_V[1] - inv->v_phase_V[2]) * (1.0 / INV_SQRT3);
}

/* One pole's period-average voltage loss against the ideal d vdc, and its
 * derivative by the current's change over the period di (the part the
 * implicit solve needs; the bus held at @p vdc). */
static double inv_pole_loss(const inverter_t *inv, double vdc, double d, double i0, double di,
                            double *dloss)
{
    const double b = inv->p.i_band_A;
    const double i_mid = i0 + 0.5 * di;
    double loss = inv->v_drop_V * inv_sgn(inv, i_mid) + inv->r_on_ohm * i_mid;
    double dl = 0.5 * inv->r_on_ohm + ((fabs(i_mid) < b) ? 0.5 * inv->v_drop_V / b : 0.0);
    if ((d > 0.0) && (d < 1.0)) {
        const double f_on = 0.5 * (1.0 - d), f_off = 0.5 * (1.0 + d);
        const double i_on = i0 + f_on * di, i_off = i0 + f_off * di;
        const double s_edges = 0.5 * (inv_sgn(inv, i_on) + inv_sgn(inv, i_off));
        const double d_eff = d - inv->td_frac * s_edges;
        if ((d_eff > 0.0) && (d_eff < 1.0)) {
            loss += inv->td_frac * s_edges * vdc;
            dl += 0.5 * inv->td_frac * vdc *
                  (((fabs(i_on) < b) ? f_on / b : 0.0) + ((fabs(i_off) < b) ? f_off / b : 0.0));
        } else {
            loss += (d - inv_clamp(d_eff, 0.0, 1.0)) * vdc;   /* clamped: flat */
        }
    }
    *dloss = dl;
    return loss;
}

/* The residual di - di1 + g P (e(di) - e1) of the implicit period, its norm
 * (max |.|, A) and the poles' loss derivatives. */
static double inv_residual(const inverter_t *inv, double vdc, const double d[3],
                           const double i0[3], const double di[3], const double di1[3],
                           const double e1[3], double g, double r[3], double de[3])
{
    double e[3], m, n = 0.0;
    int x;
    for (x = 0; x < 3; x++) {
        e[x] = inv_pole_loss(inv, vdc, d[x], i0[x], di[x], &de[x]) - e1[x];
    }
    m = (e[0] + e[1] + e[2]) / 3.0;
    for (x = 0; x < 3; x++) {
        r[x] = di[x] - di1[x] + g * (e[x] - m);
        n = fmax(n, fabs(r[x]));
    }
    return n;
}

/* Solves the 3x3 system a z = r (Gaussian elimination with partial
 * pivoting; a is overwritten).  Returns 0, or 1 if a pivot vanishes. */
static int inv_solve3(double a[3][3], double r[3], double z[3])
{
    int c, row, k;
    for (c = 0; c < 3; c++) {
        int piv = c;
        for (row = c + 1; row < 3; row++) {
            if (fabs(a[row][c]) > fabs(a[piv][c])) {
                piv = row;
            }
        }
        if (!(fabs(a[piv][c]) > 1e-300)) {
            return 1;
        }
        if (piv != c) {
            for (k = 0; k < 3; k++) {
                const double t = a[c][k];
                a[c][k] = a[piv][k];
                a[piv][k] = t;
            }
            {
                const double t = r[c];
                r[c] = r[piv];
                r[piv] = t;
            }
        }
        for (row = c + 1; row < 3; row++) {
            const double f = a[row][c] / a[c][c];
            for (k = c; k < 3; k++) {
                a[row][k] -= f * a[c][k];
            }
            r[row] -= f * r[c];
        }
    }
    for (c = 2; c >= 0; c--) {
        double s = r[c];
        for (k = c + 1; k < 3; k++) {
            s -= a[c][k] * z[k];
        }
        z[c] = s / a[c][c];
    }
    return 0;
}

#define INV_NEWTON_MAX 40
#define INV_NEWTON_TOL_A 1e-9

/* 1 when the current i0 + f di is outside the transition band on one and
 * the same side at both changes @p da and @p db (its s(.) the same +-1) */
static int inv_same_side(double i0, double f, double da, double db, double band)
{
    const double qa = i0 + f * da, qb = i0 + f * db;
    return ((qa >= band) && (qb >= band)) || ((qa <= -band) && (qb <= -band));
}

/* The implicit period in closed form where every pole stays in one affine
 * piece from the first pass's slope @p di_1st to the solution: its
 * mid-period and edge currents outside the transition band on the same
 * side at both, and the dead time leaving its duty unclamped.  There the
 * pole's loss is v_drop s + r_on i_mid + td/Ts s_edges vdc with the signs
 * fixed, e(di) - e1 = (r_on/2)(di - di_1st), and the residual
 * di - di1 + g P (e(di) - e1) = 0 is (I + k P) di = di1 + k P di_1st,
 * k = g r_on / 2, whose inverse is I - k/(1+k) P (P^2 = P).  Returns 1 with
 * the solution in @p di, 0 where a pole leaves its piece (Newton's case). */
static int inv_implicit_affine(const inverter_t *inv, const double d[3], const double i0[3],
                               const double di_1st[3], const double di1[3], double g,
                               double di[3])
{
    const double k = 0.5 * g * inv->r_on_ohm;
    const double band = inv->p.i_band_A;
    double y[3], m;
    int x;
    m = (di_1st[0] + di_1st[1] + di_1st[2]) / 3.0;
    for (x = 0; x < 3; x++) {
        y[x] = di1[x] + k * (di_1st[x] - m);
    }
    m = (y[0] + y[1] + y[2]) / 3.0;
    for (x = 0; x < 3; x++) {
        di[x] = y[x] - (k / (1.0 + k)) * (y[x] - m);
    }
    for (x = 0; x < 3; x++) {
        const double dx = d[x], a = di_1st[x], b = di[x];
        if (!inv_same_side(i0[x], 0.5, a, b, band)) {
            return 0;
        }
        if ((dx > 0.0) && (dx < 1.0)) {
            const double f_on = 0.5 * (1.0 - dx), f_off = 0.5 * (1.0 + dx);
            double d_eff;
            if (!inv_same_side(i0[x], f_on, a, b, band) ||
                !inv_same_side(i0[x], f_off, a, b, band)) {
                return 0;
            }
            d_eff = dx - inv->td_frac * 0.5 * (((i0[x] + f_on * a) > 0.0 ? 1.0 : -1.0) +
                                               ((i0[x] + f_off * a) > 0.0 ? 1.0 : -1.0));
            if (!((d_eff > 0.0) && (d_eff < 1.0))) {
                return 0;
            }
        }
    }
    return 1;
}

uint16_t inverter_step_implicit(inverter_t *inv, double t_s, const double duty[3],
                                const double i_abc_A[3], const double di1_A[3],
                                double g_A_per_V)
{
    const double vdc = inv->vdc_V;
    const double g = (isfinite(g_A_per_V) && g_A_per_V > 0.0) ? g_A_per_V : 0.0;
    double d[3], i0[3], di[3], di1[3], di_1st[3], e1[3], de[3], r[3], norm;
    uint16_t it = 0u;
    int x, y;

    for (x = 0; x < 3; x++) {
        /* the first pass's slope: inverter_step's extrapolation */
        di_1st[x] = (inv->started != 0u) ? (i_abc_A[x] - inv->i_A[x]) : 0.0;
        d[x] = isfinite(duty[x]) ? inv_clamp(duty[x], 0.0, 1.0) : 0.0;
        i0[x] = i_abc_A[x];
        di1[x] = isfinite(di1_A[x]) ? di1_A[x] : 0.0;
    }
    if (inv_implicit_affine(inv, d, i0, di_1st, di1, g, di)) {
        /* every pole in one affine piece: the solution itself (Newton would
         * stop within INV_NEWTON_TOL_A of it, after one step) */
        inverter_step_slope(inv, t_s, duty, i_abc_A, di);
        return 1u;
    }
    for (x = 0; x < 3; x++) {
        di[x] = di1[x];
        e1[x] = inv_pole_loss(inv, vdc, d[x], i0[x], di_1st[x], &de[x]);
    }
    norm = inv_residual(inv, vdc, d, i0, di, di1, e1, g, r, de);
    while ((norm > INV_NEWTON_TOL_A) && (it < INV_NEWTON_MAX)) {
        double a[3][3], z[3], lam = 1.0;
        it++;
        /* J = I + g P diag(de), P = I - 1 1^T / 3 */
        for (x = 0; x < 3; x++) {
            for (y = 0; y < 3; y++) {
                a[x][y] = ((x == y) ? 1.0 : 0.0) + g * (((x == y) ? 1.0 : 0.0) - 1.0 / 3.0) * de[y];
            }
        }
        if (inv_solve3(a, r, z) != 0) {
            break;
        }
        for (;;) {
            double dn[3], rn[3], den[3], nn;
            for (x = 0; x < 3; x++) {
                dn[x] = di[x] - lam * z[x];
            }
            nn = inv_residual(inv, vdc, d, i0, dn, di1, e1, g, rn, den);
            if ((nn < norm) || (lam < 1e-3)) {
                for (x = 0; x < 3; x++) {
                    di[x] = dn[x];
                    r[x] = rn[x];
                    de[x] = den[x];
                }
                norm = nn;
                break;
            }
            lam *= 0.5;
        }
    }
    inverter_step_slope(inv, t_s, duty, i_abc_A, di);
    return it;
}

double inverter_current_gain(double Ts_s, double Rs_ohm, double Rr_ohm, double Lm_H,
                             double Lls_H, double Llr_H)
{
    const double Lr = Lm_H + Llr_H;
    /* sigma Ls = Ls - Lm^2/Lr without the cancellation */
    const double sls = Lls_H + Lm_H * Llr_H / Lr;
    const double k = Lm_H / Lr;
    const double R = Rs_ohm + Rr_ohm * k * k;
    const double x = Ts_s * R / sls;
    /* (1 - e^-x)/R = (Ts/sigma Ls)(1 - e^-x)/x; the series below 1e-6 */
    return (x < 1e-6) ? (Ts_s / sls) * (1.0 - 0.5 * x) : -expm1(-x) / R;
}

double inverter_duty_from_cmpr(uint16_t cmpr, uint16_t t1pr)
{
    if ((t1pr == 0u) || (cmpr >= t1pr)) {
        return 0.0;
    }
    return (double)(t1pr - cmpr) / (double)t1pr;
}
