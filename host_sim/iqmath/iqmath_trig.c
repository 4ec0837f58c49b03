/**
 * @file iqmath_trig.c
 * Host IQmath trigonometry: _IQsin/_IQcos (radians), _IQsinPU/_IQcosPU
 * (per-unit revolutions), _IQatan2/_IQatan2PU/_IQatan.  Integer only.
 *
 * sin/cos: the angle is first made a fraction of a revolution, u in Q40
 * (exact for the PU forms, to 2^-40 rev from radians), reduced modulo one
 * revolution by masking, then
 *   sin(x0 + d) = sin(x0) cos(d) + cos(x0) sin(d)
 * with x0 the nearest of 256 points per revolution (65-entry quarter-wave
 * table, Q31) and |d| <= pi/256 rad, where cos(d) = 1 - d^2/2 + d^4/24 and
 * sin(d) = d - d^3/6 are exact to < 3e-12 (the next terms, d^6/720 and
 * d^5/120, are below 2.3e-12).  Error budget at Q30: table rounding
 * 0.25 LSB plus output rounding 0.5 LSB; at Q24 the rounding dominates.
 *
 * atan2: octant reduction to r = min/max in [0, 1] (Q32), then
 *   atan(r) = atan(r0) + atan(t),  t = (r - r0) / (1 + r r0)
 * with r0 the nearest of k/64 (65-entry table of atan(k/64)/(2 pi), Q34
 * revolutions) and |t| <= 1/128, atan(t) = t - t^3/3 + t^5/5 (next term
 * < 2e-17).  The angle is built in revolutions, Q40, and converted once.
 *
 * Tables and constants: tools/gen_trig_tables.py (mpmath, 50 digits).
 */
#include "IQmathLib.h"

#if MATH_TYPE == IQ_MATH   /* FLOAT_MATH: the header maps to libm */

/* ---- tables ------------------------------------------------------------- */

/* sin(k pi/128) in Q31 (unsigned), k = 0..64: one quarter wave of 256
 * points per revolution; signs come from the quadrant. */
static const uint32_t SIN_Q31[65] = {
    0u, 52701887u, 105372028u, 157978697u, 210490206u, 262874923u,
    315101295u, 367137861u, 418953276u, 470516330u, 521795963u, 572761285u,
    623381598u, 673626408u, 723465451u, 772868706u, 821806413u, 870249095u,
    918167572u, 965532978u, 1012316784u, 1058490808u, 1104027237u, 1148898640u,
    1193077991u, 1236538675u, 1279254516u, 1321199781u, 1362349204u, 1402678000u,
    1442161874u, 1480777044u, 1518500250u, 1555308768u, 1591180426u, 1626093616u,
    1660027308u, 1692961062u, 1724875040u, 1755750017u, 1785567396u, 1814309216u,
    1841958164u, 1868497586u, 1893911494u, 1918184581u, 1941302225u, 1963250501u,
    1984016189u, 2003586779u, 2021950484u, 2039096241u, 2055013723u, 2069693342u,
    2083126254u, 2095304370u, 2106220352u, 2115867626u, 2124240380u, 2131333572u,
    2137142927u, 2141664948u, 2144896910u, 2146836866u, 2147483648u,
};
static const uint32_t ATAN_REV_Q34[65] = {
    0u, 42719353u, 85417861u, 128074739u, 170669324u, 213181134u,
    255589927u, 297875755u, 340019024u, 382000541u, 423801562u, 465403846u,
    506789690u, 547941971u, 588844181u, 629480462u, 669835629u, 709895197u,
    749645397u, 789073198u, 828166314u, 866913213u, 905303124u, 943326033u,
    980972688u, 1018234587u, 1055103973u, 1091573821u, 1127637829u, 1163290394u,
    1198526605u, 1233342215u, 1267733622u, 1301697852u, 1335232527u, 1368335849u,
    1401006571u, 1433243970u, 1465047826u, 1496418395u, 1527356380u, 1557862909u,
    1587939507u, 1617588076u, 1646810863u, 1675610441u, 1703989687u, 1731951753u,
    1759500051u, 1786638228u, 1813370146u, 1839699863u, 1865631615u, 1891169797u,
    1916318946u, 1941083724u, 1965468907u, 1989479364u, 2013120049u, 2036395985u,
    2059312252u, 2081873977u, 2104086323u, 2125954478u, 2147483648u,
};

/* 2 pi in Q28 and Q29 (Q29 needs 32 bits unsigned), 1/(2 pi) in Q34. */
#define TWO_PI_Q28   ((int64_t)1686629713)
#define TWO_PI_Q29   ((uint32_t)3373259426u)
#define INV_2PI_Q34  ((int64_t)2734261102u)
/* 2^65 / (2 pi) = K_HI * 2^32 + K_LO: radians -> revolutions in 64 bits. */
#define K_HI         ((int64_t)1367130551)
#define K_LO         ((int64_t)656542357u)

#define REV_Q40_MASK    (((uint64_t)1 << 40) - 1u)   /* one revolution */
#define REV_Q40_QUARTER ((int64_t)1 << 38)   /* pi/2 as revolutions, Q40 */
#define REV_Q40_HALF    ((int64_t)1 << 39)   /* pi                       */

/* ---- helpers ------------------------------------------------------------ */

/** sin(k * 2 pi / 256) in Q31 for any k (only k mod 256 matters). */
static int64_t sin_tab(uint32_t k)
{
    uint32_t m = k & 63u;
    switch ((k >> 6) & 3u) {
    case 0u: return (int64_t)SIN_Q31[m];
    case 1u: return (int64_t)SIN_Q31[64u - m];
    case 2u: return -(int64_t)SIN_Q31[m];
    default: return -(int64_t)SIN_Q31[64u - m];
    }
}

/** sin(2 pi u / 2^40) in Qq (1 <= q <= 30), rounded to nearest; only
 *  u mod 2^40 matters (one revolution = 2^40).
 *  Scaling: d (Q40 rev) -> radians Q36; the sum is formed in Q35
 *  (|v| <= 2^35) then rounded to Qq.  Every intermediate is bounded in the
 *  comments; |sin| <= 1.0 fits Q30, so nothing saturates or wraps. */
static int32_t sin_rev40(uint64_t u, int q)
{
    uint64_t um = u & REV_Q40_MASK;
    uint32_t k = (uint32_t)(((um + ((uint64_t)1 << 31)) >> 32) & 255u);
    /* d = u - x0 in Q40 rev, in [-2^31, 2^31) (mod 2^40 arithmetic) */
    int64_t d = (int64_t)((um - ((uint64_t)k << 32) + ((uint64_t)1 << 31))
                          & REV_Q40_MASK) - ((int64_t)1 << 31);
    int64_t s0 = sin_tab(k);                             /* Q31 */
    int64_t c0 = sin_tab(k + 64u);                       /* Q31 */
    /* radians Q36: Q40 rev * Q28 (2 pi) = Q68 -> Q36; |d 2pi| < 2^61.7,
     * |dr| <= pi/256 2^36 < 2^29.7 */
    int64_t dr = iqm_asr64(d * TWO_PI_Q28 + ((int64_t)1 << 31), 32);
    int64_t d2 = iqm_asr64(dr * dr, 36);                 /* Q36, < 2^23.4 */
    int64_t cm1 = -(d2 / 2) + iqm_asr64(d2 * d2, 36) / 24; /* cos d - 1, Q36 */
    int64_t sd = dr - iqm_asr64(dr * d2, 36) / 6;         /* sin d, Q36 */
    /* Q31*Q36 = Q67 -> Q35; |s0 cm1| < 2^54.4, |c0 sd| < 2^60.7 */
    int64_t v = s0 * 16 + iqm_asr64(s0 * cm1, 32) + iqm_asr64(c0 * sd, 32);
    return (int32_t)iqm_asr64(v + ((int64_t)1 << (34 - q)), 35 - q);
}

/** Per-unit angle A (Qq revolutions) as Q40 revolutions (exact). */
static uint64_t pu_to_rev40(int32_t a, int q)
{
    return (uint64_t)(uint32_t)a << (40 - q);    /* mod 2^40 taken later */
}

/** A (radians, Qq) as revolutions Q40, modulo one revolution, to within
 *  2^-40 rev (q >= 7) or 2^(-33-q) rev (q < 7).
 *  A 2^(40-q) / (2 pi) = A K / 2^(25+q) with K = 2^65/(2 pi) split in
 *  halves: |A K_HI| < 2^61.5 and |A K_LO| < 2^63 both fit int64, and
 *  floor((X 2^32 + Y) / 2^(32+m)) == floor((X + floor(Y / 2^32)) / 2^m). */
static uint64_t rad_to_rev40(int32_t a, int q)
{
    int64_t hi = (int64_t)a * K_HI;
    int64_t lo = iqm_asr64((int64_t)a * K_LO, 32);
    int64_t w = hi + lo;                        /* floor(A K / 2^32) */
    if (q >= 7) {
        return (uint64_t)iqm_asr64(w, q - 7);
    }
    return (uint64_t)w << (7 - q);              /* unsigned: wraps, mod 2^40 */
}

/** |a| as uint32_t (|INT32_MIN| = 2^31 is representable). */
static uint32_t abs_u32(int32_t a)
{
    return (a < 0) ? (uint32_t)0u - (uint32_t)a : (uint32_t)a;
}

/** atan2(y, x) in revolutions Q40, in (-2^39, 2^39]; (0, 0) -> 0. */
static int64_t atan2_rev40(int32_t y, int32_t x)
{
    uint32_t ax = abs_u32(x);
    uint32_t ay = abs_u32(y);
    int swap = (ay > ax);
    uint32_t num = swap ? ax : ay;
    uint32_t den = swap ? ay : ax;
    uint64_t r;
    uint32_t k;
    int64_t delta, t, t2, t3, t5, at, a;

    if (den == 0u) {
        return 0;                        /* atan2(0, 0): 0, as TI */
    }
    /* Q32, [0, 2^32], rounded (error <= 2^-33); num 2^32 + den/2 < 2^64 */
    r = (((uint64_t)num << 32) + (den >> 1)) / den;
    k = (uint32_t)((r + ((uint64_t)1 << 25)) >> 26);     /* r0 = k/64 */
    delta = (int64_t)r - ((int64_t)k << 26);     /* Q32, |delta| <= 2^25 */
    /* t = delta / (1 + r r0): Q32 / Q32 -> Q37 (|delta| 2^37 <= 2^62);
     * 1 + r r0 = 2^32 + r k / 64 in Q32, in [2^32, 2^33]. */
    t = (delta * ((int64_t)1 << 37))
        / (int64_t)(((uint64_t)1 << 32) + ((r * k) >> 6));
    t2 = iqm_asr64(t * t, 37);                   /* Q37, |t| <= 2^30 */
    t3 = iqm_asr64(t2 * t, 37);
    t5 = iqm_asr64(t3 * t2, 37);
    at = t - t3 / 3 + t5 / 5;                    /* atan(t), rad Q37 */
    /* rad Q37 * (1/(2 pi)) Q34 = Q71 -> rev Q40; |at*INV| < 2^61.4 */
    a = (int64_t)ATAN_REV_Q34[k] * 64 + iqm_asr64(at * INV_2PI_Q34, 31);
    if (swap) {
        a = REV_Q40_QUARTER - a;         /* atan(y/x) = pi/2 - atan(x/y) */
    }
    if (x < 0) {
        a = REV_Q40_HALF - a;            /* second quadrant */
    }
    return (y < 0) ? -a : a;             /* y == 0, x < 0: +pi, as TI */
}

/** round(a * m / 2^s) for |a| < 2^43, 21 <= s <= 63, in 64-bit pieces:
 *  a = ah 2^20 + al (0 <= al < 2^20), |ah m| < 2^55, al m < 2^52. */
static int64_t mul_u32_round(int64_t a, uint32_t m, int s)
{
    int64_t ah = iqm_asr64(a, 20);
    int64_t al = a - ah * ((int64_t)1 << 20);
    int64_t v = iqm_asr64(ah * (int64_t)m + iqm_asr64(al * (int64_t)m, 20),
                          s - 21);              /* floor(a m / 2^(s-1)) */
    return iqm_asr64(v + 1, 1);
}

/* ---- API ---------------------------------------------------------------- */

int32_t iqm_sinpu(int32_t a, int q)
{
    return sin_rev40(pu_to_rev40(a, q), q);
}

int32_t iqm_cospu(int32_t a, int q)
{
    return sin_rev40(pu_to_rev40(a, q) + (uint64_t)REV_Q40_QUARTER, q);
}

int32_t iqm_sin(int32_t a, int q)
{
    return sin_rev40(rad_to_rev40(a, q), q);
}

int32_t iqm_cos(int32_t a, int q)
{
    return sin_rev40(rad_to_rev40(a, q) + (uint64_t)REV_Q40_QUARTER, q);
}

int32_t iqm_atan2(int32_t a, int32_t b, int q)
{
    /* rev Q40 * 2 pi Q29 = Q69 -> Qq; |result| <= pi 2^q < 2^31 for q <= 29 */
    return (int32_t)mul_u32_round(atan2_rev40(a, b), TWO_PI_Q29, 69 - q);
}

int32_t iqm_atan2pu(int32_t a, int32_t b, int q)
{
    int64_t rev = atan2_rev40(a, b);
    int64_t one = (int64_t)1 << q;
    int64_t v;
    if (rev < 0) {
        rev += (int64_t)1 << 40;          /* (-0.5, 0) -> (0.5, 1) */
    }
    v = (rev + ((int64_t)1 << (39 - q))) >> (40 - q);   /* rev >= 0 */
    return (int32_t)((v >= one) ? one - 1 : v);   /* keep [0, 1) */
}

#else
/* ISO C wants at least one declaration per translation unit. */
typedef int iqm_trig_unused_t;
#endif /* MATH_TYPE == IQ_MATH */
