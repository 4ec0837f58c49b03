/* Standstill lock-in measurement of sigma Ls.  See standstill_z.h. */
#include "standstill_z.h"

#include "iq_rmpy.h"

#include <math.h>

#define TWO_PI_F 6.28318530717958647692f
/* The sums carry 16 / N per sample instead of 1 / N: the phasors then use
 * 4 more bits of Q24 (|I|^2 was ~1e4 LSB at 15 % injection; now ~2.6e6)
 * and stay below 4 * 16 = 64 for inputs saturated at +-4 pu. */
#define SUM_GAIN 16.0f
/* Largest phasor sum accepted (an AC amplitude of ~1 pu: far beyond this
 * test's); keeps each product of the final step below 64 and their sums
 * below 128. */
#define SUM_MAX 7.9f

/* The recurrence's rounding constants: half an LSB of Q24 in Q30 (the
 * weights' Q30 -> Q24 rounding), one LSB of Q30 (two truncated products'
 * bias, at most 2 LSB); nothing in the FLOAT build, which rounds to nearest. */
#if MATH_TYPE == IQ_MATH
#define SSZ_HALF_Q24_IN_Q30 ((int32_t)1 << (30 - GLOBAL_Q - 1))
#define SSZ_ONE_Q30 ((int32_t)1)
#else
#define SSZ_HALF_Q24_IN_Q30 0.0f
#endif

static inline _iq sat_in(_iq x)
{
    return _IQsat(x, _IQ(STANDSTILL_Z_IN_MAX), -_IQ(STANDSTILL_Z_IN_MAX));
}

standstill_z_status_t standstill_z_init(standstill_z_t *z, float Ts_s, float f_base_Hz,
                                        float f_Hz, uint16_t cycles, float ampl_pu,
                                        float corr_pu)
{
    float per;
    float f;
    float w_pu;
    uint32_t window;

    z->ampl = z->inv_n = z->inv_w = z->w = z->corr = _IQ(0.0);
    z->rot_c = z->rot_s = z->s = z->c = _IQ30(0.0);
    z->rev_step = _IQ(0.0);
    z->per_period = z->lead = z->window = 0u;
    z->running = 0u;
    standstill_z_start(z);
    z->running = 0u;
    if (!(Ts_s > 0.0f) || !(f_base_Hz > 0.0f) || !(f_Hz > 0.0f)) {
        return STANDSTILL_Z_ERR_FREQ;
    }
    per = floorf(1.0f / (f_Hz * Ts_s) + 0.5f);
    if (!(per >= 8.0f && per <= 4096.0f)) {
        return STANDSTILL_Z_ERR_FREQ;
    }
    window = (uint32_t)cycles * (uint32_t)per;
    if (cycles < 4u || cycles > 200u || window + (uint32_t)per > 65535u) {
        return STANDSTILL_Z_ERR_CYCLES;
    }
    if (!(ampl_pu > 0.0f && ampl_pu <= 0.5f)) {
        return STANDSTILL_Z_ERR_AMPL;
    }
    if (!(corr_pu >= 0.0f && corr_pu <= 1.0f)) {
        return STANDSTILL_Z_ERR_CORR;
    }
    f = 1.0f / (per * Ts_s);
    w_pu = f / f_base_Hz;
    if (!(w_pu >= 0.01f && w_pu <= 30.0f)) {
        return STANDSTILL_Z_ERR_FREQ;
    }
    z->per_period = (uint16_t)per;
    z->lead = (uint16_t)per;                /* one period for the current loop to follow */
    z->window = (uint16_t)window;
    z->ampl = _IQ(ampl_pu);
    z->inv_n = _IQ(SUM_GAIN / (float)window);
    /* the weights' rotation by 2 pi / per a sample: cos as 1 - 2 sin^2(half),
     * so that the float's relative rounding falls on the small 2 sin^2 (0.4
     * LSB of Q30) and not on a number near 1 (64 LSB) */
    {
        const float h = sinf(TWO_PI_F * 0.5f / per);
        z->rot_c = _IQ30(1.0) - _IQ30(2.0f * h * h);
        z->rot_s = _IQ30(sinf(TWO_PI_F / per));
    }
    z->rev_step = _IQ(1.0f / per);

    z->inv_w = _IQ(1.0f / w_pu);
    z->w = _IQ(w_pu);
    z->corr = _IQ(corr_pu);
    return STANDSTILL_Z_OK;
}

float standstill_z_freq_Hz(const standstill_z_t *z, float Ts_s)
{
    return (z->per_period > 0u) ? 1.0f / ((float)z->per_period * Ts_s) : 0.0f;
}

float standstill_z_corr(float f_Hz, float Lm_H, float Lr_H, float Rr_ohm, float L_base_H)
{
    float wtr = TWO_PI_F * f_Hz * Lr_H / Rr_ohm;
    return (Lm_H * Lm_H / Lr_H) / (1.0f + wtr * wtr) / L_base_H;
}

uint16_t standstill_z_samples(const standstill_z_t *z)
{
    return (uint16_t)(z->lead + z->window);
}

void standstill_z_start(standstill_z_t *z)
{
    z->us = z->uc = z->is = z->ic = _IQ(0.0);
    z->i_prev = _IQ(0.0);
    z->i_add = z->x = z->r = z->sigma_ls = _IQ(0.0);
    z->k = z->ph = 0u;
    z->done = z->valid = 0u;
    z->running = (uint16_t)(z->window > 0u);
}

/* The impedance from the four sums (see the header). */
void standstill_z_finish(standstill_z_t *z)
{
    _iq den;
    _iq num_x;
    _iq num_r;
    /* the current phasor (SUM_GAIN / 2 times the amplitude) from a current
     * of at least a quarter of the commanded amplitude:
     * |I|^2 >= (SUM_GAIN ampl / 8)^2 = 4 ampl^2 */
    _iq den_min = _IQmpy(_IQ(4.0), _IQmpy(z->ampl, z->ampl));

    z->valid = 0u;
    if (z->done == 0u) {
        return;
    }
    if (_IQabs(z->us) > _IQ(SUM_MAX) || _IQabs(z->uc) > _IQ(SUM_MAX) ||
        _IQabs(z->is) > _IQ(SUM_MAX) || _IQabs(z->ic) > _IQ(SUM_MAX)) {
        return;   /* invalid: an AC amplitude beyond any plausible response */
    }
    /* each product < 62.5, each sum < 125; |num| / 100 < den rather than
     * |num| < 100 den, which leaves Q24 for den > 1.28 */
    den = _IQmpy(z->is, z->is) + _IQmpy(z->ic, z->ic);
    num_x = _IQmpy(z->uc, z->is) - _IQmpy(z->us, z->ic);
    num_r = _IQmpy(z->us, z->is) + _IQmpy(z->uc, z->ic);
    if (!(den > den_min) || !(_IQmpy(_IQabs(num_x), _IQ(0.01)) < den) ||
        !(_IQmpy(_IQabs(num_r), _IQ(0.01)) < den)) {
        return;   /* invalid: no current, or an impedance beyond 100 pu */
    }
    z->x = _IQdiv(num_x, den);
    z->r = _IQdiv(num_r, den);
    /* sigma Ls = x / w <= 4 pu  <=>  x <= 4 w (w <= 30: 4 w < 128), so
     * the product x inv_w stays below 4 */
    if (!(z->x > _IQ(0.0)) || !(z->x <= _IQmpy(_IQ(4.0), z->w))) {
        return;
    }
    z->sigma_ls = _IQmpy(z->x, z->inv_w) - z->corr;
    z->valid = (uint16_t)(z->sigma_ls > _IQ(0.0) && z->sigma_ls <= _IQ(4.0));
}

void standstill_z_step(standstill_z_t *z)
{
    _iq sn;
    _iq cn;
    _iq im;
    _iq30 sv;
    _iq30 cv;

    if (z->running == 0u) {
        z->i_add = _IQ(0.0);
        return;
    }
    /* sin, cos of phase ph / per_period revolutions by a rotation
     * recurrence (header), re-seeded exactly at the start of every period:
     * the pattern repeats exactly each period, as a table would, and the
     * drift is bounded by one period's steps */
#if MATH_TYPE == IQ_MATH
    if (z->ph == 0u) {
        z->s = _IQ30(0.0);
        z->c = _IQ30(1.0);
    }
    sv = z->s;
    cv = z->c;
#else
    /* FLOAT (the host's reference model, no cycle budget): the sine and
     * cosine themselves, as before the recurrence (a float recurrence
     * drifts by 6e-8 a step, enough to move a marginal closed-loop run) */
    sv = _IQsinPU(z->rev_step * (float)z->ph);
    cv = _IQcosPU(z->rev_step * (float)z->ph);
#endif
    /* the weights 16/N sin, 16/N cos: Q30 * Q24 -> Q30, then rounded to Q24
     * (a truncated weight is biased by -1/2 LSB and lets the DC of u and i
     * leak into the phasors: measured sigma Ls +8e-4); |.| <= 0.5 */
    sn = _IQ30toIQ(_IQ30mpyIQX(sv, 30, z->inv_n, GLOBAL_Q) + SSZ_HALF_Q24_IN_Q30);
    cn = _IQ30toIQ(_IQ30mpyIQX(cv, 30, z->inv_n, GLOBAL_Q) + SSZ_HALF_Q24_IN_Q30);
    im = sat_in(z->i_m);
    if (z->k >= z->lead) {
        _iq u = sat_in(z->u_m);
        /* mean of i(k-1), i(k): the instant of u (header); |.| <= 4 */
        _iq i_mid = _IQdiv2(im + z->i_prev);   /* an arithmetic shift: _IQmpy by 0.5 bit for bit */
        /* rounded products (iq_rmpy.h: _IQrmpy bit for bit, |.| <= 4 * 0.5) */
        z->us += iq_rmpy(u, sn);
        z->uc += iq_rmpy(u, cn);
        z->is += iq_rmpy(i_mid, sn);
        z->ic += iq_rmpy(i_mid, cn);
    }
    z->i_prev = im;
    z->i_add = _IQmpyIQX(sv, 30, z->ampl, GLOBAL_Q);   /* Q30 * Q24 -> Q24, |.| <= ampl */
    /* the next phase: (sin, cos) turned by 2 pi / per_period.  Each Q30
     * product truncates (in (-1, 0] LSB): the sum of two gets one LSB back,
     * the difference is centred as it is; |.| <= 1 + the drift: no
     * overflow */
#if MATH_TYPE == IQ_MATH
    z->s = _IQ30mpy(sv, z->rot_c) + _IQ30mpy(cv, z->rot_s) + SSZ_ONE_Q30;
    z->c = _IQ30mpy(cv, z->rot_c) - _IQ30mpy(sv, z->rot_s);
#endif
    if (++z->ph >= z->per_period) {
        z->ph = 0u;
    }
    if (++z->k >= (uint16_t)(z->lead + z->window)) {
        /* the window is complete: the sums hold for standstill_z_finish */
        z->running = 0u;
        z->done = 1u;
        z->i_add = _IQ(0.0);
    }
}
