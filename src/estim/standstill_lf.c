/* The standstill sequence's low-frequency impedance test.  See standstill_lf.h. */
#include "standstill_lf.h"

#include "estim_bfp.h"
#include "iq_rmpy.h"

#include <math.h>
#include <string.h>

#define SUM_GAIN 16.0f
#define PER_MAX 1048576.0f   /* 2^20 samples per period */

static inline _iq sat_in(_iq x)
{
    return _IQsat(x, _IQ(STANDSTILL_LF_IN_MAX), -_IQ(STANDSTILL_LF_IN_MAX));
}

/* The test's shape from the SI set-up: samples per period, periods per
 * half, lead samples (floats: init only). */
static standstill_lf_status_t shape(float Ts_s, float tr_s, float ampl_pu, float im_pu,
                                    float min_window_s, float *per, float *periods,
                                    float *lead)
{
    if (!(Ts_s > 0.0f) || !(tr_s > 0.0f)) {
        return STANDSTILL_LF_ERR_TIME;
    }
    /* the fundamental's period: 2 pi Tr / (w1 Tr) */
    *per = floorf(6.2831853f * tr_s / (STANDSTILL_LF_W1_TR * Ts_s) + 0.5f);
    if (!(*per >= (float)STANDSTILL_LF_PER_MIN && *per <= PER_MAX)) {
        return STANDSTILL_LF_ERR_TIME;
    }
    *periods = ceilf(0.5f * min_window_s / (*per * Ts_s));
    if (!(*periods >= 1.0f)) {
        *periods = 1.0f;
    }
    *lead = ceilf(STANDSTILL_LF_LEAD_TR * tr_s / Ts_s);
    if (*periods * *per > (float)STANDSTILL_LF_HALF_MAX ||
        *lead + 2.0f * *periods * *per > 2147483647.0f) {
        return STANDSTILL_LF_ERR_WINDOW;
    }
    if (!(im_pu > 0.0f && im_pu <= 2.0f) || !(ampl_pu > 0.0f) ||
        ampl_pu > STANDSTILL_LF_AMPL_MAX_OF_IM * im_pu) {
        return STANDSTILL_LF_ERR_AMPL;
    }
    return STANDSTILL_LF_OK;
}

standstill_lf_status_t standstill_lf_check(float Ts_s, float tr_s, float ampl_pu, float im_pu,
                                           float min_window_s)
{
    float per, periods, lead;
    return shape(Ts_s, tr_s, ampl_pu, im_pu, min_window_s, &per, &periods, &lead);
}

standstill_lf_status_t standstill_lf_init(standstill_lf_t *z, float Ts_s, float tr_s,
                                          float ampl_pu, float im_pu, float min_window_s,
                                          uint16_t hold_log2)
{
    float per = 0.0f, periods = 0.0f, lead = 0.0f;
    standstill_lf_status_t st;

    memset(z, 0, sizeof *z);
    st = shape(Ts_s, tr_s, ampl_pu, im_pu, min_window_s, &per, &periods, &lead);
    if (st != STANDSTILL_LF_OK) {
        return st;
    }
    if (hold_log2 > STANDSTILL_LF_HOLD_LOG2_MAX) {
        return STANDSTILL_LF_ERR_HOLD;
    }
    z->hold_log2 = hold_log2;
    z->per = (uint32_t)per;
    z->half = (uint32_t)(periods * per);
    z->lead = (uint32_t)lead;
    z->ampl = _IQ(ampl_pu);
    z->gain = _IQ(SUM_GAIN / (periods * per));
    z->ang_step = _IQ(1.0f / per);
    /* 2^32 / per rounded, in integers (a 32-bit double, the C28x's and the
     * AVR's, would round it); per >= 64 keeps it below 2^26 */
    z->inv_per_q32 = (uint32_t)((((uint64_t)1 << 32) + (uint64_t)(z->per / 2u)) /
                                (uint64_t)z->per);
    return STANDSTILL_LF_OK;
}

uint32_t standstill_lf_samples(const standstill_lf_t *z)
{
    return z->lead + 2u * z->half;
}

float standstill_lf_w1_rad_s(const standstill_lf_t *z, float Ts_s)
{
    return (z->per > 0u) ? 6.2831853f / ((float)z->per * Ts_s) : 0.0f;
}

void standstill_lf_start(standstill_lf_t *z)
{
    memset(z->sum, 0, sizeof z->sum);
    z->k = 0u;
    z->ph = 0u;
    z->done = 0u;
    z->i_add = _IQ(0.0);
    z->i_step = _IQ(0.0);   /* the step first: an ISR between the two adds nothing */
    z->i_ref = _IQ(0.0);
    z->running = (uint16_t)(z->per > 0u);
}

/* The sample's angle in the fundamental's period, Q24 pu of a revolution:
 * ph * round(2^32 / per) / 2^8 (ph < per: the product below 2^32 + per/2,
 * so uint32 holds it but for the last sample's rounding: taken in 64 bits). */
static inline _iq lf_angle(const standstill_lf_t *z)
{
#if MATH_TYPE == IQ_MATH
    return (_iq)(((uint64_t)z->ph * (uint64_t)z->inv_per_q32) >> (32 - GLOBAL_Q));
#else
    return (float)z->ph / (float)z->per;
#endif
}

/* One harmonic's four sums: the weights rounded (a truncated weight is
 * biased by -1/2 LSB and lets the inputs' DC into the phasors), the
 * products truncated (_IQmpy: each -1/2 LSB on average, which the reader
 * gives back: standstill_lf_sum, in the background).  |s|, |c| <= 1, g <= 0.25: each
 * weight below 0.25, each product below 1 pu (|u| <= 4). */
static inline void accumulate(_iq sum[STANDSTILL_LF_NSUM], _iq s, _iq c, _iq u, _iq i, _iq g)
{
    const _iq ws = iq_rmpy(s, g);
    const _iq wc = iq_rmpy(c, g);
    sum[SSLF_US] += _IQmpy(u, ws);
    sum[SSLF_UC] += _IQmpy(u, wc);
    sum[SSLF_IS] += _IQmpy(i, ws);
    sum[SSLF_IC] += _IQmpy(i, wc);
}

float standstill_lf_sum(const standstill_lf_t *z, uint16_t half, uint16_t h, uint16_t k)
{
#if MATH_TYPE == IQ_MATH
    /* the truncated products' mean bias, -1/2 LSB each, given back: n/2 LSB
     * on a half of n samples (n <= 2^20: at most 0.03 pu); what stays is the
     * fractions' spread, about sqrt(n / 12) LSB */
    return _IQtoF(z->sum[half][h][k]) + ldexpf(0.5f * (float)z->half, -GLOBAL_Q);
#else
    return _IQtoF(z->sum[half][h][k]);   /* FLOAT rounds to nearest: no bias */
#endif
}

void standstill_lf_step(standstill_lf_t *z)
{
    const _iq a = lf_angle(z);
    _iq s1, c1, s2, c2, s4, c4, p;

    if (z->running == 0u) {
        return;
    }
    /* the fundamental's sine and cosine, the harmonics' by the double angle
     * (sin 2x = 2 s c, cos 2x = 1 - 2 s^2): two library calls instead of
     * six; each product's truncation (1 LSB) makes the harmonics' weights a
     * few LSB off a true sine, the same every period (orthogonal over whole
     * periods as the injection is the same function of the phase) */
    s1 = _IQsinPU(a);
    c1 = _IQcosPU(a);
    p = _IQmpy(s1, c1);
    s2 = p + p;
    p = _IQmpy(s1, s1);
    c2 = _IQ(1.0) - (p + p);
    p = _IQmpy(s2, c2);
    s4 = p + p;
    p = _IQmpy(s2, s2);
    c4 = _IQ(1.0) - (p + p);
    if (z->k >= z->lead) {
        const uint32_t j = z->k - z->lead;
        const uint16_t second = (uint16_t)(j >= z->half);
        _iq (*sum)[STANDSTILL_LF_NSUM] = z->sum[second];
        const _iq u = sat_in(z->u_m);
        const _iq i = sat_in(z->i_m);
        accumulate(sum[0], s1, c1, u, i, z->gain);
        accumulate(sum[1], s2, c2, u, i, z->gain);
        accumulate(sum[2], s4, c4, u, i, z->gain);
    }
    /* the injection for the next samples: 3 ampl < 0.9 i_M <= 1.8 pu,
     * reached by a ramp from where the last one ended (standstill_lf_fast:
     * a held value would fold its images onto the tones, standstill_lf.h) */
    z->i_add = _IQmpy(z->ampl, s1 + s2 + s4);
    z->i_step = estim_div_pow2_round(z->i_add - z->i_ref, z->hold_log2);
    if (++z->ph >= z->per) {
        z->ph = 0u;
    }
    if (++z->k >= z->lead + 2u * z->half) {
        z->done = 1u;
        z->running = 0u;
        z->i_add = _IQ(0.0);
        z->i_step = _IQ(0.0);   /* the step first (standstill_lf_start) */
        z->i_ref = _IQ(0.0);
    }
}
