/* Recursive least squares with a block-floating-point covariance (method §3,
 * eq. 1).  The scaling plan is in rls.h. */
#include "rls.h"

#include <math.h>
#include <string.h>

#include "c28x_intrinsics.h"
#include "estim_bfp.h"

#if RLS_N != 4
#error "rls.c writes the 4-column sums out"
#endif
#if MATH_TYPE == IQ_MATH && GLOBAL_Q != 24
#error "rls.c: the scaling plan (rls.h) is written for GLOBAL_Q = 24"
#endif

/* Pn_ij, i <= j, in r->Pn[] (the upper triangle, row by row) */
#define P00 0
#define P01 1
#define P02 2
#define P03 3
#define P11 4
#define P12 5
#define P13 6
#define P22 7
#define P23 8
#define P33 9

/* the same index for any (i, j): init and the rare paths */
static const int16_t rls_ix[RLS_N][RLS_N] = {
    {P00, P01, P02, P03}, {P01, P11, P12, P13}, {P02, P12, P22, P23}, {P03, P13, P23, P33}};

/* ---- the raw operations of the block floating point --------------------
 * IQ_MATH: the int32 mantissa itself (shifted, normalised by the C28x's
 * CSB, range-tested as unsigned); FLOAT_MATH: the same scaling by powers of
 * two, exactly, by ldexpf, and the same tests by comparison, so both builds
 * run the same steps.  dq = qin - qout: how the Q format of the result
 * differs from the argument's. */
#if MATH_TYPE == IQ_MATH

/** Raw x 2^s, 0 <= s <= 30: exact; the caller's range bound (stated at the
 *  call) keeps |x| 2^s < 2^31, so it cannot overflow. */
static inline _iq rls_shl(_iq x, int16_t s, int16_t dq)
{
    (void)dq;
    return x * (int32_t)((uint32_t)1 << s);
}

/** Raw floor(x 2^-s) of a NON-NEGATIVE x, 0 <= s <= 31 (no negative value
 *  is ever shifted). */
static inline _iq rls_shr(_iq x, int16_t s, int16_t dq)
{
    (void)dq;
    return x >> s;
}

/** The normalising shift of x >= 0 in Q(q): the largest n with x 2^n still
 *  an int32, 30 for x = 0 (x | 1: the same for x >= 2, and 0 2^30 = 0):
 *  one CSB. */
static inline int16_t rls_norm(_iq x, int16_t q)
{
    (void)q;
    return iq_norm32(x | 1);
}

/** Nonzero iff one of a, b, c, d is outside [-m, m), m = 2^k (raw; hi =
 *  ~(2m - 1), the bits at and above 2m): each x + m is in [0, 2m) as an
 *  unsigned iff x is in range, and an OR of such values is below 2m iff
 *  all are.  Two operations per value, no branch, no absolute value. */
static inline uint32_t rls_out4(_iq a, _iq b, _iq c, _iq d, _iq m, uint32_t hi)
{
    uint32_t x = ((uint32_t)a + (uint32_t)m) | ((uint32_t)b + (uint32_t)m);
    return (x | ((uint32_t)c + (uint32_t)m) | ((uint32_t)d + (uint32_t)m)) & hi;
}

/* hi of rls_out4 for m (a power of two) */
static inline uint32_t rls_hi(_iq m)
{
    return ~((uint32_t)m + (uint32_t)m - 1u);
}

/** Nonzero iff one of a, b, c, d is outside the open (-m, m): rls_out4 and
 *  the same with x + m - 1, which is negative (huge) only for x = -m. */
static inline uint32_t rls_out4_open(_iq a, _iq b, _iq c, _iq d, _iq m, uint32_t hi)
{
    uint32_t m1 = (uint32_t)m - 1u;
    uint32_t x = ((uint32_t)a + m1) | ((uint32_t)b + m1) | ((uint32_t)c + m1) | ((uint32_t)d + m1);
    return (x & hi) | rls_out4(a, b, c, d, m, hi);
}

/* hi of rls_out4 for |phi| < RLS_PHI_MAX = 4 (2^26 raw) */
#define RLS_PHI_HI (~(uint32_t)0x7FFFFFF)

/** Nonzero iff, after an update, an |Pn_ij| (i != j) is at 1 or a |theta_i|
 *  (Q26) at 16: raw + 2^30 outside [0, 2^31), the sign bit of the OR of
 *  the 10 values as unsigned.  They bound the next row's downdate and
 *  prediction (rls.h), so they are tested after every row. */
static inline uint32_t rls_out_of_range(const _iq30 p[RLS_NP], const _iq tx[RLS_N])
{
    const uint32_t o = (uint32_t)1 << 30;
    uint32_t x = ((uint32_t)p[P01] + o) | ((uint32_t)p[P02] + o) | ((uint32_t)p[P03] + o);
    x |= ((uint32_t)p[P12] + o) | ((uint32_t)p[P13] + o) | ((uint32_t)p[P23] + o);
    x |= ((uint32_t)tx[0] + o) | ((uint32_t)tx[1] + o);
    x |= ((uint32_t)tx[2] + o) | ((uint32_t)tx[3] + o);
    return x & ((uint32_t)1 << 31);
}

/** Nonzero iff a Pn_ii is below 0.25 (raw - 2^28 negative): tested once
 *  per completed sample (the band is for precision, and a non-positive
 *  diagonal is harmless for one row: q <= 0 or the clamp of h). */
static inline uint32_t rls_below_band(const _iq30 p[RLS_NP])
{
    const uint32_t q = (uint32_t)1 << 28;
    return (((uint32_t)p[P00] - q) | ((uint32_t)p[P11] - q) | ((uint32_t)p[P22] - q)
            | ((uint32_t)p[P33] - q)) & ((uint32_t)1 << 31);
}

/** y = floor(2x) (one bit finer) -> x rounded half up, for either sign:
 *  floor((y + 1) / 2), the one-bit arithmetic shift of TI's _IQ25toIQ
 *  (Q25 -> Q24, GLOBAL_Q = 24; floor in the host IQmath too): _IQNrmpy's
 *  result bit for bit, in two operations. */
static inline _iq rls_round(_iq y)
{
    return _IQ25toIQ(y + 1);
}

/* the mean error of four truncated products: 4 * 1/2 LSB */
#define RLS_FLOOR4 ((int32_t)2)
#define RLS_LSB ((int32_t)1)          /* one LSB of any Q */
#define RLS_ONE_RAW ((int32_t)1)      /* 2^s as a raw multiplier: rls_shl(RLS_ONE_RAW, s, .) */

/* theta's state: Q26 (|theta| < 16: 2^30 raw; a sum with an increment below
 * 16 pu stays in int32); the published theta_i is its Q24 rounding */
static inline _iq *rls_theta_state(rls_t *r)
{
    return r->theta_x;
}

/**
 * theta_i += h e 2^-dl (Q26): h (Q27, |h| < 1) times e (raw, < 2^31)
 * shifted by dl, taken one bit finer (twice the increment, < 2^31) and
 * rounded to Q26 (|increment| < 2^30 raw = 16 pu).  An increment below
 * 1/2 LSB26 (1/8 LSB24) is lost: the dead zone of a rounded integrator,
 * a quarter of a Q24 one's (rls.h).
 */
static inline void rls_theta_add(_iq th[RLS_N], _iq tx[RLS_N], int16_t i, _iq27 h, _iq30 e,
                                 int16_t dl)
{
    (void)th;
    tx[i] += rls_round(_IQ27mpy(h, e >> dl));
}

/* theta[] (Q24) = the state rounded half up, once per completed sample */
static inline void rls_publish(rls_t *r)
{
    r->theta[0] = _IQ26toIQ(r->theta_x[0] + (int32_t)2);
    r->theta[1] = _IQ26toIQ(r->theta_x[1] + (int32_t)2);
    r->theta[2] = _IQ26toIQ(r->theta_x[2] + (int32_t)2);
    r->theta[3] = _IQ26toIQ(r->theta_x[3] + (int32_t)2);
}

#else /* FLOAT_MATH */

static inline _iq rls_shl(_iq x, int16_t s, int16_t dq)
{
    return ldexpf(x, (int)s + (int)dq);
}

static inline _iq rls_shr(_iq x, int16_t s, int16_t dq)
{
    return ldexpf(x, (int)dq - (int)s);
}

/* the n of the IQ build for the value x >= 0 of a Q(q) number: x = f 2^e,
 * f in [0.5, 1), raw x 2^q has its top bit at q + e - 1 */
static inline int16_t rls_norm(_iq x, int16_t q)
{
    int e = 0;
    if (!(x > 0.0f)) {
        return 30;
    }
    (void)frexpf(x, &e);
    return (int16_t)(31 - (int)q - e);
}

static inline uint32_t rls_out4(_iq a, _iq b, _iq c, _iq d, _iq m, uint32_t hi)
{
    (void)hi;
    return (uint32_t)((a < -m) | (a >= m) | (b < -m) | (b >= m) | (c < -m) | (c >= m)
                      | (d < -m) | (d >= m));
}

static inline uint32_t rls_hi(_iq m)
{
    (void)m;
    return 0u;
}

static inline uint32_t rls_out4_open(_iq a, _iq b, _iq c, _iq d, _iq m, uint32_t hi)
{
    (void)hi;
    return (uint32_t)((a <= -m) | (a >= m) | (b <= -m) | (b >= m) | (c <= -m) | (c >= m)
                      | (d <= -m) | (d >= m));
}

#define RLS_PHI_HI 0u

static inline _iq rls_round(_iq y)
{
    return y;
}

static inline uint32_t rls_out_of_range(const _iq30 p[RLS_NP], const _iq tx[RLS_N])
{
    /* (each test as a 0/1 integer, OR-ed without a branch) */
    return (uint32_t)(rls_out4(p[P01], p[P02], p[P03], p[P12], 1.0f, 0u) != 0u) |
           (uint32_t)(rls_out4(p[P13], p[P23], 0.0f, 0.0f, 1.0f, 0u) != 0u) |
           (uint32_t)(rls_out4(tx[0], tx[1], tx[2], tx[3], 16.0f, 0u) != 0u);
}

static inline uint32_t rls_below_band(const _iq30 p[RLS_NP])
{
    return (uint32_t)((p[P00] < 0.25f) | (p[P11] < 0.25f) | (p[P22] < 0.25f) | (p[P33] < 0.25f));
}

#define RLS_FLOOR4 0.0f
#define RLS_LSB 0.0f
#define RLS_ONE_RAW 1.0f

/* theta's state: theta[] itself (theta_x is its Kahan term) */
static inline _iq *rls_theta_state(rls_t *r)
{
    return r->theta;
}

/** theta_i += h e 2^-dl by Kahan summation (tx_i the compensation term),
 *  the float build's finer resolution: a float theta ~ 1 has a 1.2e-7
 *  ulp. */
static inline void rls_theta_add(_iq th[RLS_N], _iq tx[RLS_N], int16_t i, _iq27 h, _iq30 e,
                                 int16_t dl)
{
    float y = h * ldexpf(e, -(int)dl) + tx[i];
    float t = th[i] + y;
    tx[i] = y - (t - th[i]);
    th[i] = t;
}

/* theta[] is the state itself */
static inline void rls_publish(rls_t *r)
{
    (void)r;
}

#endif /* MATH_TYPE */

/* |a|..|d|: a bound with the top bit of the largest magnitude (IQ: the OR
 * of the magnitudes; FLOAT: the largest) */
static inline _iq rls_mag4(_iq a, _iq b, _iq c, _iq d)
{
#if MATH_TYPE == IQ_MATH
    return _IQabs(a) | _IQabs(b) | _IQabs(c) | _IQabs(d);
#else
    return fmaxf(fmaxf(fabsf(a), fabsf(b)), fmaxf(fabsf(c), fabsf(d)));
#endif
}

/* x with the sign of e (e = 0: +x) */
static inline _iq rls_sign(_iq x, _iq e)
{
#if MATH_TYPE == IQ_MATH
    return x * (1 - 2 * (int32_t)(e < 0));
#else
    return (e < 0.0f) ? -x : x;
#endif
}

/* lo <= x <= hi (IQ: _IQsat, the C28x MINL/MAXL pair on an int32) */
static inline int16_t rls_clamp(int16_t x, int16_t lo, int16_t hi)
{
#if MATH_TYPE == IQ_MATH
    return (int16_t)_IQsat((int32_t)x, (int32_t)hi, (int32_t)lo);
#else
    return (int16_t)((x < lo) ? lo : ((x > hi) ? hi : x));
#endif
}

/* float -> Q30, rounded to nearest (init only). */
static _iq30 rls_to_q30(float v)
{
#if MATH_TYPE == IQ_MATH
    return _IQ30(roundf(v * 1073741824.0f) / 1073741824.0f);
#else
    return v;
#endif
}

/* theta_i = v (init, and the saturation) */
static void rls_theta_set(rls_t *r, int16_t i, float v)
{
#if MATH_TYPE == IQ_MATH
    r->theta_x[i] = _IQ26(roundf(v * 67108864.0f) / 67108864.0f);
    r->theta[i] = _IQ26toIQ(r->theta_x[i] + (int32_t)2);
#else
    r->theta[i] = v;
    r->theta_x[i] = 0.0f;
#endif
}

/* Per parameter: dl_i = min(pe_ref - Pe_i, 31), d_i = 2^-dl_i in Q30 (0
 * below 2^-30: a P_ii below 4^-30 of the largest one, 1e-18, would freeze
 * that parameter; the measured spread is 4^7). */
static void rls_ref1(rls_t *r, int16_t i)
{
    int16_t dl = (int16_t)(r->pe_ref - r->Pe[i]);
    r->dl[i] = (int16_t)((dl > 31) ? 31 : dl);
    r->d[i] = (dl > 30) ? _IQ30(0.0) : rls_shr(_IQ30(1.0), dl, 0);
}

/* pe_ref = max Pe_i and the dl_i, d_i of every parameter (rare paths). */
static void rls_refs(rls_t *r)
{
    int16_t m = r->Pe[0], i;
    for (i = 1; i < RLS_N; i++) {
        m = (int16_t)((r->Pe[i] > m) ? r->Pe[i] : m);
    }
    r->pe_ref = m;
    for (i = 0; i < RLS_N; i++) {
        rls_ref1(r, i);
    }
}

rls_status_t rls_init(rls_t *r, rls_form_t form, float p0, float lambda,
                      float trace_max, const float theta0[RLS_N])
{
    int x = 0;
    float f;
    int16_t i;

    memset(r, 0, sizeof *r);
    if (form != RLS_FORM_CONST && form != RLS_FORM_PAPER && form != RLS_FORM_FLUX) {
        return RLS_ERR_FORM;
    }
    if (!(p0 >= 1e-9f) || !(p0 <= 1e12f)) { return RLS_ERR_P0; }
    if (!(lambda >= 0.9f) || !(lambda <= 1.0f)) { return RLS_ERR_LAMBDA; }
    if (trace_max == 0.0f) {
        trace_max = 4.0f * p0;
    }
    if (!(trace_max >= 4.0f * p0 * 0.999999f) || !(trace_max <= 1e30f)) { return RLS_ERR_TRACE; }
    if (theta0 != NULL) {
        for (i = 0; i < RLS_N; i++) {
            if (!(fabsf(theta0[i]) < RLS_THETA_MAX)) { return RLS_ERR_THETA0; }
        }
    }

    r->form = (uint16_t)form;
    r->forget = (lambda < 1.0f) ? 1u : 0u;
    r->lambda = rls_to_q30(lambda);
    f = frexpf(trace_max, &x);               /* trace_max = f 2^x, f in [0.5, 1) */
    r->trace_max_m = rls_to_q30(f);
    r->trace_max_e = (int16_t)x;
    /* trace(P) / lambda < 4 * 4^pe_ref / (w lambda) <= 17.8 * 4^pe_ref
     * (Pn_ii < 1, w >= 1/4, lambda >= 0.9) <= 2^(x-1) <= trace_max when
     * 2 pe_ref <= x - 6 */
    r->pe_fast = estim_floor_half((int16_t)(x - 6));
    r->w = _IQ30(1.0);

    /* P(0) = p0 I = 4^Pe Pn with Pn_ii in [0.25, 1) */
    f = frexpf(p0, &x);
    if ((x % 2) != 0) {
        f = 0.5f * f;                        /* [0.25, 0.5) */
        x = x + 1;
    }
    for (i = 0; i < RLS_N; i++) {
        r->Pn[rls_ix[i][i]] = rls_to_q30(f);
        r->Pe[i] = (int16_t)(x / 2);
        rls_theta_set(r, i, (theta0 != NULL) ? theta0[i] : 0.0f);
    }
    rls_refs(r);
    return RLS_OK;
}

/* ---- rare paths (out of line) ------------------------------------------ */

/* A regressor at or beyond +-RLS_PHI_MAX: the four saturated to
 * +-RLS_PHI_SAT (< RLS_PHI_MAX) into phi. */
static void rls_phi_sat(_iq phi[RLS_N], const _iq phi_in[RLS_N])
{
    int16_t j;
    for (j = 0; j < RLS_N; j++) {
        phi[j] = _IQsat(phi_in[j], _IQ(RLS_PHI_SAT), _IQ(-RLS_PHI_SAT));
    }
}

/* pe_ref down to max Pe_j after a rescaling: by c = the CSB of OR d_j
 * (max d_j = 2^(30 - c) raw: every d_j a power of two or 0), the d_j times
 * 2^c and the dl_j minus c; 0 when the largest Pe_j is still pe_ref.  (A d_j
 * of 0, dl_j 31, stays until its row comes within 2^30 again.) */
static inline void rls_ref_down(rls_t *r)
{
    _iq30 *d = r->d;
    int16_t c = rls_norm(rls_mag4(d[0], d[1], d[2], d[3]), 30);
    _iq sc = rls_shl(RLS_ONE_RAW, c, 0);
    r->pe_ref = (int16_t)(r->pe_ref - c);
    d[0] *= sc;                              /* max d_j 2^c = 2^30: in range */
    d[1] *= sc;
    d[2] *= sc;
    d[3] *= sc;
    r->dl[0] = (int16_t)(r->dl[0] - c);
    r->dl[1] = (int16_t)(r->dl[1] - c);
    r->dl[2] = (int16_t)(r->dl[2] - c);
    r->dl[3] = (int16_t)(r->dl[3] - c);
}

/* Row and column i of Pn times 2^s, Pe_i minus s (P unchanged), so that Pn_ii
 * (d, raw in (0, 2^28)) is back in [0.25, 1): its CSB n >= 3, s = (n - 1) / 2
 * >= 1, d 4^s in [2^28, 2^30).  While P is PD |Pn_ij| <= sqrt(Pn_ii Pn_jj)
 * < 2^-s, so every |Pn_ij| 2^s < 1 (exact shifts).  Pn_ii <= 0, or an
 * |Pn_ij| >= 2^-s (positive definiteness lost by rounding): row and column
 * reset (Pn_ii = 0.5, no correlation, Pe_i kept), counted in pd_count.
 * dl_i, d_i follow; pe_ref comes down with the largest Pe_j (rls_ref_down).  Pe_i stays above
 * -RLS_PE_LIM: P_ii >= 1 / (1/p0 + sum phi_i^2) > 4^-20 after 2^32 updates
 * of |phi| < 4. */
static void rls_rescale(rls_t *r, int16_t i)
{
    _iq30 *p = r->Pn;
    const int16_t *ix = rls_ix[i];
    _iq30 d = p[ix[i]], m;
    int16_t s;
    p[ix[i]] = _IQ30(0.0);                   /* out of the range test below */
    if (d > _IQ30(0.0)) {
        /* >= 1 for d < 2^28 (the caller's case); the clamp keeps every
         * shift below defined for any d (rare path) */
        s = rls_clamp((int16_t)((rls_norm(d, 30) - 1) >> 1), 0, 15);
        m = rls_shr(_IQ30(1.0), s, 0);
        if (rls_out4(p[ix[0]], p[ix[1]], p[ix[2]], p[ix[3]], m, rls_hi(m)) == 0u) {
            p[ix[0]] = rls_shl(p[ix[0]], s, 0);
            p[ix[1]] = rls_shl(p[ix[1]], s, 0);
            p[ix[2]] = rls_shl(p[ix[2]], s, 0);
            p[ix[3]] = rls_shl(p[ix[3]], s, 0);
            p[ix[i]] = rls_shl(d, (int16_t)(2 * s), 0);
            r->Pe[i] = (int16_t)(r->Pe[i] - s);
            r->dl[i] = rls_clamp((int16_t)(r->dl[i] + s), 0, 31);
            r->d[i] = rls_shr(r->d[i], s, 0);
            rls_ref_down(r);
            return;
        }
    }
    estim_count(&r->pd_count);
    p[ix[0]] = _IQ30(0.0);
    p[ix[1]] = _IQ30(0.0);
    p[ix[2]] = _IQ30(0.0);
    p[ix[3]] = _IQ30(0.0);
    p[ix[i]] = _IQ30(0.5);
}

/* theta_i = +-RLS_THETA_MAX (the saturation, in the ISR): constants only,
 * no float at run time (rls_theta_set's rounding is for init). */
static void rls_theta_saturate(rls_t *r, int16_t i, uint16_t negative)
{
#if MATH_TYPE == IQ_MATH
    static const _iq26 lim = _IQ26(RLS_THETA_MAX);   /* folded at compile time */
    r->theta_x[i] = (negative != 0u) ? -lim : lim;
    r->theta[i] = _IQ26toIQ(r->theta_x[i] + (int32_t)2);
#else
    r->theta[i] = (negative != 0u) ? -RLS_THETA_MAX : RLS_THETA_MAX;
    r->theta_x[i] = 0.0f;
#endif
}

/* The rare paths after a row: an off-diagonal at 1 (only if P is not PD:
 * clamped to 1 - 2^-30), a theta at 16 (saturated to RLS_THETA_MAX).
 * Returns 1 (a value was clamped). */
static uint16_t rls_clamp_all(rls_t *r)
{
    static const int16_t off[6] = {P01, P02, P03, P12, P13, P23};
    _iq30 *p = r->Pn;
    const _iq *tx = rls_theta_state(r);
    int16_t i;
    for (i = 0; i < 6; i++) {
        p[off[i]] = _IQsat(p[off[i]], _IQ30(1.0) - RLS_LSB, RLS_LSB - _IQ30(1.0));
    }
    for (i = 0; i < RLS_N; i++) {
        if (_IQabs(tx[i]) >= _IQ26(16.0)) {
            rls_theta_saturate(r, i, (uint16_t)(tx[i] < _IQ26(0.0)));
        }
    }
    return 1u;
}

/* At the end of a sample: every Pn_ii back in [0.25, 1) (P shrank along
 * that parameter by 4 since its last rescaling: a few times per decade of
 * P), or repaired. */
static inline void rls_renorm(rls_t *r)
{
    const _iq30 *p = r->Pn;
    if (p[P00] < _IQ30(0.25)) { rls_rescale(r, 0); }
    if (p[P11] < _IQ30(0.25)) { rls_rescale(r, 1); }
    if (p[P22] < _IQ30(0.25)) { rls_rescale(r, 2); }
    if (p[P33] < _IQ30(0.25)) { rls_rescale(r, 3); }
}

/* The exact wind-up test: trace(P) / lambda = sum_i 4^Pe_i Pn_ii / wl
 * (wl = w lambda, the w after this forgetting step) > trace_max, i.e.
 * tr = sum_i Pn_ii 4^-dl_i (Q28, < 4) > trace_max wl 4^-pe_ref.  Only when
 * P is within 4^3 of its bound (pe_ref > pe_fast).  Pn_ii > 0 (in band). */
static uint16_t rls_trace_exceeds(const rls_t *r, _iq30 wl)
{
    const _iq30 *p = r->Pn;
    const int16_t *dl = r->dl;
    _iq28 tr, rhs;
    int16_t sh;
    /* Pn_ii Q30 -> Q28 (>> 2), times 4^-dl_i (floor; 0 for dl_i >= 15) */
    tr = rls_shr(p[P00], rls_clamp((int16_t)(2 + 2 * dl[0]), 0, 31), 2)
       + rls_shr(p[P11], rls_clamp((int16_t)(2 + 2 * dl[1]), 0, 31), 2);
    tr += rls_shr(p[P22], rls_clamp((int16_t)(2 + 2 * dl[2]), 0, 31), 2)
       + rls_shr(p[P33], rls_clamp((int16_t)(2 + 2 * dl[3]), 0, 31), 2);
    rhs = _IQ30mpy(r->trace_max_m, wl);                  /* Q30, in (0.2, 1) */
    sh = (int16_t)(r->trace_max_e - 2 * r->pe_ref - 2);   /* Q30 -> Q28, times 2^(e - 2 pe_ref) */
    if (sh >= 2) {
        return 0u;                   /* rhs >= 4 > tr: within the bound */
    }
    rhs = (sh >= 0) ? rls_shl(rhs, sh, 2) : rls_shr(rhs, rls_clamp((int16_t)-sh, 0, 31), 2);
    return (uint16_t)(tr > rhs);
}

/* ---- forgetting -------------------------------------------------------- */

/* P / lambda = D Pn D / (w lambda): only the scalar w moves (one product),
 * Pn is not touched; w is brought back above 1/4 by 4 w and Pe_i + 1 (P
 * unchanged) every ln 4 / ln(1/lambda) samples.  Rounding: w lambda is
 * truncated (relative 2^-28 per sample: an extra forgetting of < 4e-9).
 * The exact trace test only when P is within 4^3 of its bound. */
static void rls_forget_w(rls_t *r)
{
    _iq30 wl = _IQ30mpy(r->w, r->lambda);                /* Q30, >= 0.225 */
    if (r->pe_ref > r->pe_fast && rls_trace_exceeds(r, wl) != 0u) {
        r->windup_hold = 1u;
        return;
    }
    r->windup_hold = 0u;
    if (wl < _IQ30(0.25)) {
        wl = rls_shl(wl, 2, 0);      /* < 1: no overflow */
        r->Pe[0] = (int16_t)(r->Pe[0] + 1);   /* <= log4(4 trace_max) < 52 */
        r->Pe[1] = (int16_t)(r->Pe[1] + 1);
        r->Pe[2] = (int16_t)(r->Pe[2] + 1);
        r->Pe[3] = (int16_t)(r->Pe[3] + 1);
        r->pe_ref = (int16_t)(r->pe_ref + 1);
    }
    r->w = wl;
}

void rls_forget(rls_t *r)
{
    if (r->forget != 0u) {
        rls_forget_w(r);
    }
}

/* ---- one scalar update ------------------------------------------------- */

/* The end of an update: the flag counted once, the innovation in Q24. */
static inline _iq rls_finish(rls_t *r, uint16_t ov, _iq22 es)
{
    if (ov != 0u) {
        estim_count(&r->sat_count);
    }
    return _IQ22toIQ(es);
}

/*
 * One scalar update (eq. 1) by the row phi and the measurement y (Q24).
 * Returns the a-priori innovation (Q24).  Scaling of every step: rls.h
 * ("scaling plan"); the bound that keeps each step in range is beside it.
 * Products truncate (_IQNmpy, the 5-cycle intrinsic) except the P downdate
 * and the theta increments, rounded (rls_round); no rounding call, no
 * 64-bit operation.  A value that has to be saturated or clamped sets the
 * update's flag, counted once in sat_count.
 */
static _iq rls_row_update(rls_t *r, const _iq phi_in[RLS_N], _iq y)
{
    _iq30 *p = r->Pn;
    const _iq30 *dd = r->d;
    const int16_t *dl = r->dl;
    _iq *tx = rls_theta_state(r);
    const _iq *ph = phi_in;
    _iq phs[RLS_N];
    _iq22 e22, es, ae;
    _iq27 v0, v1, v2, v3;            /* 2^-dl_j phi_j (Q27), then psi_j (Q30) */
    _iq28 g0, g1, g2, g3;
    _iq27 h0, h1, h2, h3;
    _iq28 q, den;
    _iq29 rm, c;
    _iq30 el;
    _iq sc;
    uint16_t ov = 0u;
    int16_t s, a, f, n, k, up, t;

    /* |phi_j| < 4 (one test for the four) */
    if (rls_out4(ph[0], ph[1], ph[2], ph[3], _IQ(RLS_PHI_MAX), RLS_PHI_HI) != 0u) {
        rls_phi_sat(phs, phi_in);
        ph = phs;
        ov = 1u;
    }
    /* a-priori innovation in Q22 (phi Q24 * theta Q26 -> Q22): |y| < 128
     * (2^29 raw) and |phi_j theta_j| < 4 * 16 (2^28 raw each): |sum| <
     * 1.5 * 2^30, no overflow; clamped to +-RLS_E_MAX.  Products truncated
     * (rls.h "Truncation"). */
    e22 = _IQtoIQ22(y) - _IQ28mpy(ph[0], tx[0]) - _IQ28mpy(ph[1], tx[1]);
    e22 -= _IQ28mpy(ph[2], tx[2]) + _IQ28mpy(ph[3], tx[3]);
    es = _IQsat(e22, _IQ22(RLS_E_MAX), _IQ22(-RLS_E_MAX));
    ov |= (uint16_t)(es != e22);

    /* scaled regressor: v_j = 2^-dl_j phi_j (Q24 * Q30 -> Q27, |v| < 4),
     * psi = v 2^s read as Q30 (max |psi_j| in [0.25, 0.5)): 2^Pe_j phi_j =
     * 2^a psi_j, a = pe_ref + 3 - s */
    v0 = _IQ27mpy(ph[0], dd[0]);
    v1 = _IQ27mpy(ph[1], dd[1]);
    v2 = _IQ27mpy(ph[2], dd[2]);
    v3 = _IQ27mpy(ph[3], dd[3]);
    s = (int16_t)(rls_norm(rls_mag4(v0, v1, v2, v3), 27) - 2);   /* >= 0: OR < 2^29 */
    s = (int16_t)((s < 0) ? 0 : s);   /* (the bound above; one compare keeps the shift defined) */
    sc = rls_shl(RLS_ONE_RAW, s, -3);
    v0 *= sc;                        /* exact: max |v| 2^s < 2^29 */
    v1 *= sc;
    v2 *= sc;
    v3 *= sc;
    a = (int16_t)(r->pe_ref + 3 - s);

    /* g = Pn psi (Q30 * Q30 -> Q28, the high word of the product): |g_i| <
     * 2 since |Pn_ij| < 1, |psi_j| < 1/2; plus 2 LSB28, the mean of the four
     * floors, and the same for q below: when P is huge, q is ~1000 LSB28 and
     * the part of P that the update leaves along phi is ~1/(P |phi|^2) of
     * it, so a bias of q is a large relative error there (measured: without
     * these pads the P(0) = 1e12 test loses positive definiteness for
     * good) */
    g0 = _IQ28mpyIQX(p[P00], 30, v0, 30) + _IQ28mpyIQX(p[P01], 30, v1, 30) + RLS_FLOOR4;
    g0 += _IQ28mpyIQX(p[P02], 30, v2, 30) + _IQ28mpyIQX(p[P03], 30, v3, 30);
    g1 = _IQ28mpyIQX(p[P01], 30, v0, 30) + _IQ28mpyIQX(p[P11], 30, v1, 30) + RLS_FLOOR4;
    g1 += _IQ28mpyIQX(p[P12], 30, v2, 30) + _IQ28mpyIQX(p[P13], 30, v3, 30);
    g2 = _IQ28mpyIQX(p[P02], 30, v0, 30) + _IQ28mpyIQX(p[P12], 30, v1, 30) + RLS_FLOOR4;
    g2 += _IQ28mpyIQX(p[P22], 30, v2, 30) + _IQ28mpyIQX(p[P23], 30, v3, 30);
    g3 = _IQ28mpyIQX(p[P03], 30, v0, 30) + _IQ28mpyIQX(p[P13], 30, v1, 30) + RLS_FLOOR4;
    g3 += _IQ28mpyIQX(p[P23], 30, v2, 30) + _IQ28mpyIQX(p[P33], 30, v3, 30);
    /* q = psi' Pn psi (Q30 * Q28 -> Q28, |terms| < 1, q < 4).  q <= 0: Pn
     * not PD along psi, or phi = 0 (no information): nothing changes. */
    q = _IQ30mpy(v0, g0) + _IQ30mpy(v1, g1) + RLS_FLOOR4;
    q += _IQ30mpy(v2, g2) + _IQ30mpy(v3, g3);
    if (q <= RLS_FLOOR4) {
        if (rls_mag4(v0, v1, v2, v3) != _IQ27(0.0)) {
            estim_count(&r->pd_count);
        }
        return rls_finish(r, ov, es);
    }
    /* s / 4^f = den (Q28, in (0, 5)), f = max(a, 0): a >= 0: q + w 4^-a;
     * a < 0: q 4^a + w (the shifts capped at 30: the term is then below 1
     * LSB28 of the other) */
    f = rls_clamp(a, 0, 32767);
    den = rls_shr(r->w, rls_clamp((int16_t)(2 + 2 * f), 0, 30), 2);
    den += rls_shr(q, rls_clamp((int16_t)(2 * (f - a)), 0, 30), 0);
    /* den = dm 4^k, dm in [0.25, 1) (Q29): the CSB n of den (>= 1 raw,
     * < 2^31) puts it in [2^30, 2^31); k = 2 - (n + 1) / 2 in [-13, 1] */
    n = rls_norm(den, 28);
    k = (int16_t)(2 - ((n + 1) >> 1));
    rm = _IQ29isqrt(rls_shr(rls_shl(den, n, 0), (int16_t)(3 - (n & 1)), -1));  /* Q29, (1, 2] */

    /* h_i = g_i rm 2^up, up = a - f - k, with the sign of e (the downdate
     * sees h_i h_j only).  up <= 0: folded into c = rm 2^up (Q29); up > 0
     * (a huge P, den < 1/4: the first samples): h_i = (g_i rm) 2^up, up <=
     * 13.  While P is PD |h_i|^2 <= Pn_ii q / den < 1 (Cauchy-Schwarz);
     * |h_i| >= 1 (or a shift that would overflow) means it is not. */
    up = (int16_t)(a - f - k);
    c = rls_sign(rls_shr(rm, rls_clamp((int16_t)-up, 0, 31), 0), es);
    up = rls_clamp(up, 0, 13);
    h0 = _IQ30mpy(g0, c);                    /* Q28 * Q29 -> Q27 */
    h1 = _IQ30mpy(g1, c);
    h2 = _IQ30mpy(g2, c);
    h3 = _IQ30mpy(g3, c);
    sc = rls_shr(_IQ27(1.0), up, 0);         /* |h| 2^up < 1: h h' < 1 fits Q31 */
    if (rls_out4_open(h0, h1, h2, h3, sc, rls_hi(sc)) != 0u) {
        /* not PD: |h_i| clamped below 1 (the downdate then takes a diagonal
         * to <= 0, and rls_renorm resets that parameter) */
        sc -= RLS_LSB;
        h0 = _IQsat(h0, sc, -sc);
        h1 = _IQsat(h1, sc, -sc);
        h2 = _IQsat(h2, sc, -sc);
        h3 = _IQsat(h3, sc, -sc);
        ov = 1u;
    }
    sc = rls_shl(RLS_ONE_RAW, up, 0);
    h0 *= sc;                                /* |h| < 1: in range */
    h1 *= sc;
    h2 *= sc;
    h3 *= sc;

    /* P downdate, upper triangle: Pn_ij -= h_i h_j (Q27 * Q27 -> Q31,
     * |.| < 1, rounded to Q30 = _IQ24rmpy bit for bit: Pn_ij stays in
     * (-2, 2)).  Rounded, not truncated: P integrates these (rls.h
     * "Truncation"). */
    p[P00] -= rls_round(_IQ23mpy(h0, h0));
    p[P01] -= rls_round(_IQ23mpy(h0, h1));
    p[P02] -= rls_round(_IQ23mpy(h0, h2));
    p[P03] -= rls_round(_IQ23mpy(h0, h3));
    p[P11] -= rls_round(_IQ23mpy(h1, h1));
    p[P12] -= rls_round(_IQ23mpy(h1, h2));
    p[P13] -= rls_round(_IQ23mpy(h1, h3));
    p[P22] -= rls_round(_IQ23mpy(h2, h2));
    p[P23] -= rls_round(_IQ23mpy(h2, h3));
    p[P33] -= rls_round(_IQ23mpy(h3, h3));

    /* theta_i += K_i e = 2^(Pe_i - f - k) h_i rm e.  |e| = em 2^(9 - n)
     * with em in [0.5, 1) (the CSB of |e22|; e = 0: em = 0), eps = rm em
     * (Q30, < 2), K_i e = h_i eps 2^(t - dl_i), t = pe_ref - f - k + 9 - n:
     * the product keeps ~27 significant bits however small e is.  IQ: el =
     * eps 2^(t - 3) (raw, rls_theta_add); t > 3 (|increment| >= 16 pu:
     * theta saturates anyway) is taken as 3. */
    ae = _IQabs(es);
    n = rls_norm(ae, 22);
    el = _IQ30mpy(rm, rls_shl(ae, n, -9));           /* Q29 * [0.5, 1) -> Q30 */
    t = (int16_t)(r->pe_ref - f - k + 9 - n);
#if MATH_TYPE == IQ_MATH
    el = rls_shr(el, rls_clamp((int16_t)(3 - t), 0, 31), 0);
#else
    el = ldexpf(el, (int)t);
#endif
    rls_theta_add(r->theta, r->theta_x, 0, h0, el, dl[0]);
    rls_theta_add(r->theta, r->theta_x, 1, h1, el, dl[1]);
    rls_theta_add(r->theta, r->theta_x, 2, h2, el, dl[2]);
    rls_theta_add(r->theta, r->theta_x, 3, h3, el, dl[3]);

    /* the bounds of the next row: every |Pn_ij| < 1, every |theta_i| < 16
     * (one test for the 10); the diagonals' band: once per sample
     * (rls_end_sample) */
    if (rls_out_of_range(p, tx) != 0u) {
        ov |= rls_clamp_all(r);
    }
    estim_count(&r->n_updates);
    return rls_finish(r, ov, es);
}

/* The end of a sample (after row 2; after every rls_update_row): the
 * diagonals back in their band, theta[] published. */
static inline void rls_end_sample(rls_t *r)
{
    if (rls_below_band(r->Pn) != 0u) {
        rls_renorm(r);
    }
    rls_publish(r);
}

_iq rls_update_row(rls_t *r, const _iq phi[RLS_N], _iq y)
{
    _iq e = rls_row_update(r, phi, y);
    rls_end_sample(r);
    return e;
}

/* Row 1 (eq. 7 or eq. 9): [i_Mf, u_Mf, c, 0], c from theta2 as it is now;
 * the flux form: [i_Mf, u_Mf, m_Mf, -(wr m_T)f] */
static inline void rls_row1(rls_t *r)
{
    _iq row[RLS_N];
    row[0] = r->i_mf;
    row[1] = r->u_mf;
    row[2] = (r->form == (uint16_t)RLS_FORM_PAPER) ? r->theta[1] : _IQ(1.0);
    row[3] = _IQ(0.0);
    if (r->form == (uint16_t)RLS_FORM_FLUX) {
        row[2] = r->c1;
        row[3] = r->d1;
    }
    r->innov[0] = rls_row_update(r, row, r->y1);
}

/* Row 2: [i_Tf, u_Tf, 0, wr_f]; the flux form: [i_Tf, u_Tf, m_Tf, (wr m_M)f] */
static inline void rls_row2(rls_t *r)
{
    _iq row[RLS_N];
    row[0] = r->i_tf;
    row[1] = r->u_tf;
    row[2] = (r->form == (uint16_t)RLS_FORM_FLUX) ? r->c2 : _IQ(0.0);
    row[3] = r->wr_f;
    r->innov[1] = rls_row_update(r, row, r->y2);
}

/* the forgetting step as the rows take it: lambda = 1 costs one test */
static inline void rls_forget_step(rls_t *r)
{
    if (r->forget != 0u) {
        rls_forget_w(r);
    }
}

void rls_step(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    rls_forget_step(r);
    /* the third regressor comes from theta2 BEFORE this sample: row 1 first */
    rls_row1(r);
    rls_row2(r);
    rls_end_sample(r);
}

void rls_step_row1(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    rls_forget_step(r);
    rls_row1(r);
}

void rls_step_row2(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    rls_row2(r);
    rls_end_sample(r);
}

void rls_step_row(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    if (r->row_next == 0u) {
        rls_forget_step(r);
        rls_row1(r);
        r->row_next = 1u;
    } else {
        rls_row2(r);
        rls_end_sample(r);
        r->row_next = 0u;
    }
}
