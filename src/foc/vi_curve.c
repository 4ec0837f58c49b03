/* The bridge's voltage error against the current at standstill.  See
 * vi_curve.h. */
#include "vi_curve.h"

#include <math.h>
#include <string.h>

/* One level: a current (k times i1, PI on i_alpha) or a voltage (k times
 * the polarity's (4/3) E estimate, held); the last entry is the rest. */
typedef struct {
    uint16_t current;
    float k;
} vi_level_t;

static const vi_level_t levels[VI_CURVE_LEVELS + 1u] = {
    {1u, 2.0f}, {1u, 1.0f}, {0u, 0.9f}, {0u, 0.6f}, {0u, 0.3f},
    {1u, -2.0f}, {1u, -1.0f}, {0u, 0.9f}, {0u, 0.6f}, {0u, 0.3f},
    {0u, 0.0f},
};

#define VI_AVG_MIN_SHIFT 7u    /* at least 128 samples per window: the noise of a
                                  few current LSB averaged to a tenth of one */

/* The level l's commands for the ISR: the window restarts (n last: the ISR
 * takes no sample while n is full, whatever it reads of the rest). */
static void start_level(vi_curve_t *v, uint16_t l, float u_now)
{
    const vi_level_t *L = &levels[l];
    v->level = l;
    v->pi.ui = _IQ(u_now);   /* bumpless into a current level */
    v->i_ref = _IQ(L->k * v->i1);
    v->u_ref = _IQ(L->k * v->ea_hat);
    v->settle = (L->current != 0u) ? v->settle_i_n : v->settle_n;
    v->current = L->current;
    v->su = _IQ(0.0);
    v->si = _IQ(0.0);
    v->sv = _IQ(0.0);
    v->t = 0u;
    v->n = 0u;
}

vi_curve_status_t vi_curve_check(float Ts_s, float i1_pu, float Tr_s, float kp, float ki,
                                 float u_max)
{
    if (!(Ts_s > 0.0f) || !(Tr_s > 0.0f)) {
        return VI_CURVE_ERR_PERIOD;
    }
    if (!(i1_pu > 0.0f) || !(2.0f * i1_pu <= VI_CURVE_I_MAX_PU)) {
        return VI_CURVE_ERR_CURRENT;
    }
    /* the float vi_curve_init rounds up to settle_i_n: it must fit 16 bits */
    if (!(6.0f * (Tr_s / Ts_s) <= 65535.0f)) {
        return VI_CURVE_ERR_TIME;
    }
    if (pi_check(kp, ki, -u_max, u_max) != PI_OK) {
        return VI_CURVE_ERR_GAINS;
    }
    return VI_CURVE_OK;
}

vi_curve_status_t vi_curve_init(vi_curve_t *v, float Ts_s, float i1_pu, float Tr_s, float kp,
                                float ki, float u_max)
{
    float tr_n;
    uint16_t k = VI_AVG_MIN_SHIFT;
    vi_curve_status_t st;

    memset(v, 0, sizeof *v);
    st = vi_curve_check(Ts_s, i1_pu, Tr_s, kp, ki, u_max);
    if (st != VI_CURVE_OK) {
        return st;
    }
    tr_n = Tr_s / Ts_s;
    (void)pi_init(&v->pi, kp, ki, -u_max, u_max);   /* pi_check passed above */
    v->i1 = i1_pu;
    v->settle_n = (uint16_t)ceilf(3.0f * tr_n);
    v->settle_i_n = (uint16_t)ceilf(6.0f * tr_n);
    while (k < VI_CURVE_AVG_MAX_SHIFT && (float)((uint32_t)1u << k) < tr_n) {
        k++;
    }
    v->avg_shift = k;
    vi_curve_restart(v);
    return VI_CURVE_OK;
}

void vi_curve_restart(vi_curve_t *v)
{
    pi_reset(&v->pi);
    v->u_cmd = _IQ(0.0);
    v->fail = 0u;
    v->fail_level = 0u;
    v->ea_hat = 0.0f;
    v->mean_vdc = 0.0f;
    start_level(v, 0u, 0.0f);
    v->done = 0u;   /* last (volatile): a finished test's ISR steps nothing until now */
}

vi_curve_status_t vi_curve_retry(vi_curve_t *v, float i1_pu)
{
    if (!(i1_pu > 0.0f) || !(2.0f * i1_pu <= VI_CURVE_I_MAX_PU)) {
        return VI_CURVE_ERR_CURRENT;
    }
    v->i1 = i1_pu;
    vi_curve_restart(v);
    return VI_CURVE_OK;
}

uint32_t vi_curve_samples(const vi_curve_t *v)
{
    /* four current levels, six voltage levels and the rest */
    return 4u * (uint32_t)v->settle_i_n + 7u * (uint32_t)v->settle_n +
           (uint32_t)(VI_CURVE_LEVELS + 1u) * ((uint32_t)1u << v->avg_shift);
}

float vi_curve_duration_s(float Ts_s, float Tr_s)
{
    vi_curve_t v;
    if (vi_curve_init(&v, Ts_s, 0.1f, Tr_s, 0.0f, 0.0f, 1.0f) != VI_CURVE_OK) {
        return 0.0f;
    }
    return (float)vi_curve_samples(&v) * Ts_s;
}

/* One sample into a window's sum: limited to +-VI_CURVE_IN_MAX_PU, IQ_MATH
 * as Q16 (Q24 >> 8, an arithmetic shift: truncated towards -inf, a bias of
 * half a Q16 LSB, 8e-6 pu, in the mean; the fit removes it) */
static inline _iq window_add(_iq s, _iq x)
{
    const _iq y = _IQsat(x, _IQ(VI_CURVE_IN_MAX_PU), _IQ(-VI_CURVE_IN_MAX_PU));
#if MATH_TYPE == IQ_MATH
    return s + (y >> 8);
#else
    return s + y;
#endif
}

void vi_curve_step(vi_curve_t *v)
{
    if (v->run == 0u || v->done != 0u) {
        v->u_cmd = _IQ(0.0);
        return;
    }
    if (v->current != 0u) {
        v->pi.ref = v->i_ref;
        v->pi.fbk = v->i_alpha;
        v->pi.ff = _IQ(0.0);
        pi_step(&v->pi);
        v->u_cmd = v->pi.out;
    } else {
        /* held: inside the transition the current follows the voltage */
        v->u_cmd = v->u_ref;
    }
    if (v->t < v->settle) {
        v->t++;
    } else if (v->n < ((uint16_t)1u << v->avg_shift)) {
        v->su = window_add(v->su, v->u_alpha);
        v->si = window_add(v->si, v->i_alpha);
        v->sv = window_add(v->sv, v->vdc);
        v->n++;
    } else {
        /* full: the background takes it (vi_curve_next) */
    }
}

/* A window's mean, pu (float: the fit, off the ISR path; not drive_slow.c's window_mean) */
static float level_mean_pu(const vi_curve_t *v, _iq s)
{
#if MATH_TYPE == IQ_MATH
    /* a Q16 sum; + half a Q16 LSB: the truncation's mean bias */
    return ((float)s / (float)((uint32_t)1u << v->avg_shift) + 0.5f) / 65536.0f;
#else
    return s / (float)((uint32_t)1u << v->avg_shift);
#endif
}

uint16_t vi_curve_next(vi_curve_t *v)
{
    const uint16_t l = v->level;
    float u, i;

    if (v->done != 0u || v->n < ((uint16_t)1u << v->avg_shift)) {
        return 0u;
    }
    u = level_mean_pu(v, v->su);
    i = level_mean_pu(v, v->si);
    if (l >= VI_CURVE_LEVELS) {
        v->done = 1u;   /* the rest is over */
        return 1u;
    }
    v->mean_u[l] = u;
    v->mean_i[l] = i;
    v->mean_vdc += level_mean_pu(v, v->sv) / (float)VI_CURVE_LEVELS;
    if (levels[l].current != 0u) {
        const float ref = levels[l].k * v->i1;
        if (!(fabsf(i - ref) <= 0.125f * fabsf(ref))) {
            v->fail = 1u;
            v->fail_level = l;
            v->done = 1u;
            return 1u;
        }
        if (l == 1u || l == 6u) {
            /* the polarity's line through its two levels, at I = 0 */
            v->ea_hat = 2.0f * v->mean_u[l] - v->mean_u[l - 1u];
        }
    }
    start_level(v, (uint16_t)(l + 1u), u);
    return 1u;
}

float vi_curve_model_V(float e_pole_V, float band_A, float i_A)
{
    const float s1 = fmaxf(-1.0f, fminf(1.0f, i_A / band_A));
    const float s2 = fmaxf(-1.0f, fminf(1.0f, 0.5f * i_A / band_A));
    return (2.0f / 3.0f) * e_pole_V * (s1 + s2);
}

/* The half-width b that puts the error u' (> 0) at current i (> 0) on (1):
 * u' = E i / b inside b, (2/3) E + E i / (3 b) between b and 2 b; 0 when
 * u' is at or beyond the saturated (4/3) E (no information on b). */
static float band_of_point(float e_pole, float i, float u_err)
{
    if (!(i > 0.0f) || !(u_err > 0.0f)) {
        return 0.0f;
    }
    if (u_err < e_pole) {
        return e_pole * i / u_err;
    }
    if (u_err < (4.0f / 3.0f) * e_pole * 0.98f) {
        return e_pole * i / (3.0f * u_err - 2.0f * e_pole);
    }
    return 0.0f;
}

void vi_curve_fit(const vi_curve_t *v, float I_base_A, float V_base_V, vi_fit_t *f)
{
    float rs[2], ea[2], b_sum = 0.0f;
    uint16_t p, l, nb = 0u;

    memset(f, 0, sizeof *f);
    if (v->done == 0u) {
        f->status = VI_FIT_NOT_DONE;
        return;
    }
    if (v->fail != 0u) {
        f->status = VI_FIT_NO_CURRENT;
        return;
    }
    for (l = 0u; l < VI_CURVE_LEVELS; l++) {
        f->i_A[l] = v->mean_i[l] * I_base_A;
    }
    f->vdc_V = v->mean_vdc * V_base_V;
    /* each polarity's line through its two current levels (0, 1 and 5, 6),
     * signs folded so that both are Rs I + (4/3) E with I > 0 */
    for (p = 0u; p < 2u; p++) {
        const uint16_t a = (uint16_t)(5u * p);
        const float sg = (p == 0u) ? 1.0f : -1.0f;
        const float i2 = sg * f->i_A[a], i1 = sg * f->i_A[a + 1u];
        const float u2 = sg * v->mean_u[a] * V_base_V;
        const float u1 = sg * v->mean_u[a + 1u] * V_base_V;
        rs[p] = (u2 - u1) / (i2 - i1);
        ea[p] = u1 - rs[p] * i1;
    }
    f->rs_ohm = 0.5f * (rs[0] + rs[1]);
    f->e_pole_V = 0.75f * 0.5f * (ea[0] + ea[1]);
    f->e_split = fabsf(ea[0] - ea[1]) / fmaxf(fabsf(0.5f * (ea[0] + ea[1])), 1e-30f);
    for (l = 0u; l < VI_CURVE_LEVELS; l++) {
        f->u_err_V[l] = v->mean_u[l] * V_base_V - f->rs_ohm * f->i_A[l];
    }
    if (!(f->rs_ohm > 0.0f) || !isfinite(f->rs_ohm)) {
        f->status = VI_FIT_RS;
        return;
    }
    if (!(ea[0] > 0.0f) || !(ea[1] > 0.0f) || !(fabsf(ea[0] - ea[1]) <= 0.25f * fmaxf(ea[0], ea[1]))) {
        f->status = VI_FIT_ERROR;
        return;
    }
    /* b from the voltage levels (2-4, 7-9) by (1), folded to I > 0 */
    for (l = 2u; l < VI_CURVE_LEVELS; l++) {
        if (levels[l].current == 0u) {
            const float sg = (l < 5u) ? 1.0f : -1.0f;
            const float b = band_of_point(f->e_pole_V, sg * f->i_A[l], sg * f->u_err_V[l]);
            if (b > 0.0f) {
                b_sum += b;
                nb++;
            }
        }
    }
    f->n_band = nb;
    f->band_A = (nb > 0u) ? b_sum / (float)nb : 0.0f;
    if (nb == 0u || !(f->band_A > 0.0f) || !isfinite(f->band_A) ||
        !(2.0f * f->band_A < v->i1 * I_base_A)) {
        f->status = VI_FIT_BAND;
        return;
    }
    f->status = VI_FIT_OK;
}

const char *vi_fit_str(vi_fit_status_t s)
{
    switch (s) {
    case VI_FIT_OK: return "ok";
    case VI_FIT_NOT_DONE: return "not_done";
    case VI_FIT_NO_CURRENT: return "no_current";
    case VI_FIT_RS: return "rs_not_positive";
    case VI_FIT_ERROR: return "error_implausible";
    case VI_FIT_BAND: return "band_implausible";
    default: return "unknown";
    }
}
