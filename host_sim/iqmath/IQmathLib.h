/**
 * @file IQmathLib.h
 * Host IQmath: a portable, integer-only re-implementation of the API of TI's
 * C28x IQmath library (IQmathLib.h, "C28x IQmath Library - A Virtual
 * Floating Point Engine", SPRC087), so that the control core builds and runs
 * unchanged on the host and, on the F2812, against TI's own header and
 * IQmath.lib.  Written from TI's documented semantics, not from TI's code.
 *
 * MATH_TYPE (TI): IQ_MATH (0, default) makes _iq a 32-bit fixed-point
 * number in Q GLOBAL_Q (default 24); FLOAT_MATH (1) makes _iq a float and
 * every macro the float expression TI's header gives (SPRC087 §7,
 * "Floating-Point Operating Mode"), which is the reference build.
 *
 * IQ_MATH implementation rules (why: the same sources are also compiled by
 * avr-gcc, 16-bit int, 32-bit double, and must give bit-identical results):
 *  - int32_t / int64_t / uint32_t / uint64_t only, never `long`, never
 *    relying on `int` being 32 bits;
 *  - integer arithmetic only, except the conversions _IQ(A) / _IQN(A)
 *    (float in) and _IQtoF / _IQNtoF (float out);
 *  - no signed overflow: every wrap goes through uint32_t/uint64_t, every
 *    right shift of a possibly negative value goes through iqm_asr64(),
 *    which floors (as the C28x arithmetic shift does) without relying on
 *    the implementation-defined `>>` of negative values.
 *
 * Accuracy of this implementation (TI states ~30 bits for sin/cos, ~28 bits
 * for atan2/sqrt/isqrt/div/mag, ~31 bits for the rest; SPRC087 §5).
 * Measured worst case over tests/iqmath (sweeps, edges and 2^17..2^18
 * seeded random inputs per function, against double libm), in LSB of the
 * output Q; the tests' bounds are in brackets:
 *    _IQmpy _IQrmpy _IQrsmpy _IQmpyI32* _IQmpyIQX _IQint _IQfrac
 *    _IQtoIQN _IQNtoIQ _IQtoQN _QNtoIQ _IQ _IQtoF      0 (bit-exact to spec)
 *    _IQdiv, every N        0.99999 (truncates)        [< 1]
 *    _IQsqrt _IQisqrt _IQmag                   0.500 (rounded) [0.5]
 *    Q24 _IQsinPU _IQcosPU _IQsin _IQcos       0.504           [0.52]
 *    Q24 _IQatan2 _IQatan2PU _IQatan           0.505           [0.52]
 *    Q30 _IQ30sinPU/_IQ30cosPU 0.783 [0.85];  Q29 _IQ29sin/cos 0.639 [0.70]
 *    Q29 _IQ29atan2 0.680 [0.80];  Q30 _IQ30atan2PU 0.548 [0.80]
 * Results are bit-identical on avr-gcc/simavr (16-bit int) and the host.
 *
 * _IQ(A) / _IQN(A) are TI's (int32_t)(A * 2^N): truncation toward zero, the
 * argument must be in range (out of range is undefined, as in TI's header).
 * They are constant expressions (usable in static initialisers).  Note for
 * the avr build: with a 32-bit double, a non-dyadic literal (0.1) is rounded
 * to 24 bits before scaling, so _IQ30(0.1) can differ by a few LSB from the
 * host; every function below is bit-identical given identical IQ inputs.
 *
 * Call counting (for the ISR cycle estimate): when IQMATH_COUNT_CALLS is
 * defined (CMake: -DIQMATH_COUNT_CALLS=ON, or link target iqmath_counted),
 * every IQ_MATH operation except the constant conversions _IQ(A)/_IQN(A)
 * increments iqmath_call_count[IQMATH_FN_xxx].  Otherwise there is no
 * counter and no global.
 */
#ifndef IQMATHLIB_H
#define IQMATHLIB_H

#include <stdint.h>

#define IQ_MATH    0
#define FLOAT_MATH 1

#ifndef MATH_TYPE
#define MATH_TYPE IQ_MATH
#endif

#ifndef GLOBAL_Q
#define GLOBAL_Q 24
#endif

#if (MATH_TYPE != IQ_MATH) && (MATH_TYPE != FLOAT_MATH)
#error "MATH_TYPE must be IQ_MATH (0) or FLOAT_MATH (1)"
#endif
#if (GLOBAL_Q < 1) || (GLOBAL_Q > 30)
#error "GLOBAL_Q must be in 1..30 (TI IQmath supports Q1..Q30)"
#endif

/* TI's predefined Q constants (SPRC087 §8), e.g. for _IQmpyIQX. */
#define QG  GLOBAL_Q
#define Q30 30
#define Q29 29
#define Q28 28
#define Q27 27
#define Q26 26
#define Q25 25
#define Q24 24
#define Q23 23
#define Q22 22
#define Q21 21
#define Q20 20
#define Q19 19
#define Q18 18
#define Q17 17
#define Q16 16
#define Q15 15
#define Q14 14
#define Q13 13
#define Q12 12
#define Q11 11
#define Q10 10
#define Q9  9
#define Q8  8
#define Q7  7
#define Q6  6
#define Q5  5
#define Q4  4
#define Q3  3
#define Q2  2
#define Q1  1

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Call counting                                                            */
/* ------------------------------------------------------------------------ */

/** Operation ids for iqmath_call_count[] (both MATH_TYPEs, so that code
 *  that prints the counters builds either way).  The _IQN variants count
 *  under the id of their GLOBAL_Q sibling. */
typedef enum {
    IQMATH_FN_MPY = 0,   /* _IQmpy, _IQNmpy                    */
    IQMATH_FN_RMPY,      /* _IQrmpy                            */
    IQMATH_FN_RSMPY,     /* _IQrsmpy                           */
    IQMATH_FN_MPYI32,    /* _IQmpyI32                          */
    IQMATH_FN_MPYI32INT, /* _IQmpyI32int                       */
    IQMATH_FN_MPYI32FRAC,/* _IQmpyI32frac                      */
    IQMATH_FN_MPYIQX,    /* _IQmpyIQX                          */
    IQMATH_FN_DIV,       /* _IQdiv                             */
    IQMATH_FN_SQRT,      /* _IQsqrt                            */
    IQMATH_FN_ISQRT,     /* _IQisqrt                           */
    IQMATH_FN_MAG,       /* _IQmag                             */
    IQMATH_FN_SIN,       /* _IQsin                             */
    IQMATH_FN_COS,       /* _IQcos                             */
    IQMATH_FN_SINPU,     /* _IQsinPU                           */
    IQMATH_FN_COSPU,     /* _IQcosPU                           */
    IQMATH_FN_ATAN2,     /* _IQatan2                           */
    IQMATH_FN_ATAN2PU,   /* _IQatan2PU                         */
    IQMATH_FN_ATAN,      /* _IQatan                            */
    IQMATH_FN_INT,       /* _IQint                             */
    IQMATH_FN_FRAC,      /* _IQfrac                            */
    IQMATH_FN_SAT,       /* _IQsat                             */
    IQMATH_FN_ABS,       /* _IQabs                             */
    IQMATH_FN_TOF,       /* _IQtoF, _IQNtoF                    */
    IQMATH_FN_TOIQN,     /* _IQtoIQN, _IQNtoIQ                 */
    IQMATH_FN_TOQN,      /* _IQtoQN, _QNtoIQ                   */
    IQMATH_FN_NORM32,    /* iq_norm32: the C28x's CSB (c28x_intrinsics.h), not IQmath */
    IQMATH_FN_COUNT
} iqmath_fn_t;

/** Name of operation @p id ("_IQmpy", ...), "?" if out of range. */
const char *iqmath_fn_name(int id);

#if defined(IQMATH_COUNT_CALLS) && (MATH_TYPE == IQ_MATH)
/** Calls per operation since the last iqmath_count_reset(). */
extern uint32_t iqmath_call_count[IQMATH_FN_COUNT];
/** Zero every counter. */
void iqmath_count_reset(void);
/* A function, not `count[id]++` inline: nested operations such as
 * _IQmpy(_IQmpy(a, b), _IQmpy(c, d)) would otherwise modify the same
 * counter twice between sequence points (undefined behaviour); function
 * calls are never interleaved. */
static inline void iqm_count_call(iqmath_fn_t id)
{
    iqmath_call_count[id]++;
}
#define IQM_CALL(id, expr) (iqm_count_call(id), (expr))
#else
#define IQM_CALL(id, expr) (expr)
#endif

#if MATH_TYPE == IQ_MATH
/* ======================================================================== */
/* IQ_MATH: fixed point                                                     */
/* ======================================================================== */

typedef int32_t _iq;   /* Q GLOBAL_Q */
typedef int32_t _iq30;
typedef int32_t _iq29;
typedef int32_t _iq28;
typedef int32_t _iq27;
typedef int32_t _iq26;
typedef int32_t _iq25;
typedef int32_t _iq24;
typedef int32_t _iq23;
typedef int32_t _iq22;
typedef int32_t _iq21;
typedef int32_t _iq20;
typedef int32_t _iq19;
typedef int32_t _iq18;
typedef int32_t _iq17;
typedef int32_t _iq16;
typedef int32_t _iq15;
typedef int32_t _iq14;
typedef int32_t _iq13;
typedef int32_t _iq12;
typedef int32_t _iq11;
typedef int32_t _iq10;
typedef int32_t _iq9;
typedef int32_t _iq8;
typedef int32_t _iq7;
typedef int32_t _iq6;
typedef int32_t _iq5;
typedef int32_t _iq4;
typedef int32_t _iq3;
typedef int32_t _iq2;
typedef int32_t _iq1;

#define MAX_IQ_POS INT32_MAX
#define MAX_IQ_NEG INT32_MIN
#define MIN_IQ_POS ((int32_t)1)
#define MIN_IQ_NEG ((int32_t)-1)

/* 2^n as a double constant, and 1.0 in Qn (n <= 30). */
#define IQM_TWO_POW_D(n) ((double)((int64_t)1 << (n)))
#define IQM_ONE(n)       ((int32_t)((int32_t)1 << (n)))
/* Float to Qn as TI: (long)(A * 2^n), truncating toward zero.  The cast to
 * double keeps -Wdouble-promotion quiet for float arguments and keeps the
 * macro a constant expression for literal arguments. */
#define IQM_FTOQ(A, n)   ((int32_t)((double)(A) * IQM_TWO_POW_D(n)))

/* ---- portable integer primitives (no UB, no implementation-defined) ---- */

/** floor(x / 2^s) for 0 <= s <= 63: the arithmetic right shift, written so
 *  that `>>` only ever sees a non-negative operand (~x = -x-1 >= 0). */
static inline int64_t iqm_asr64(int64_t x, int s)
{
    return (x < 0) ? ~((~x) >> s) : (x >> s);
}

/** The int32_t whose two's-complement bits are @p u (u mod 2^32). */
static inline int32_t iqm_s32(uint32_t u)
{
    return (u <= (uint32_t)INT32_MAX) ? (int32_t)u
                                      : (int32_t)(-(int32_t)(~u) - 1);
}

/** x modulo 2^32, as a signed 32-bit value: the C28x's 32-bit wrap. */
static inline int32_t iqm_wrap32(int64_t x)
{
    return iqm_s32((uint32_t)((uint64_t)x & 0xFFFFFFFFu));
}

/** x clamped to [INT32_MIN, INT32_MAX]. */
static inline int32_t iqm_sat32(int64_t x)
{
    return (x > (int64_t)INT32_MAX) ? INT32_MAX
         : (x < (int64_t)INT32_MIN) ? INT32_MIN : (int32_t)x;
}

/* ---- multiplies -------------------------------------------------------- */

/** A*B in Qq.  Scaling: 64-bit product (Qq*Qq -> Q2q, exact), floor-shifted
 *  right by q (truncation toward -inf, as the C28x IMPYL/QMPYL + shift).
 *  Overflow: wraps modulo 2^32, as TI's _IQmpy (no saturation). */
static inline int32_t iqm_mpy(int32_t a, int32_t b, int q)
{
    return iqm_wrap32(iqm_asr64((int64_t)a * b, q));   /* Q2q -> Qq */
}

/** A*B in Qq rounded: adds 2^(q-1) (half an LSB) before the floor shift,
 *  i.e. round half up.  Overflow: wraps modulo 2^32, as TI's _IQrmpy. */
static inline int32_t iqm_rmpy(int32_t a, int32_t b, int q)
{
    /* |a*b| <= 2^62, so adding 2^(q-1) <= 2^29 cannot overflow int64. */
    return iqm_wrap32(iqm_asr64((int64_t)a * b + ((int64_t)1 << (q - 1)), q));
}

/** A*B in Qq rounded as iqm_rmpy, then saturated to [INT32_MIN, INT32_MAX]
 *  (TI's _IQrsmpy: "round and then saturate to the maximum IQ range"). */
static inline int32_t iqm_rsmpy(int32_t a, int32_t b, int q)
{
    return iqm_sat32(iqm_asr64((int64_t)a * b + ((int64_t)1 << (q - 1)), q));
}

/** A (Qqa) * B (Qqb) -> Qqr.  Scaling: exact 64-bit product in Q(qa+qb),
 *  floor-shifted right by qa+qb-qr (or multiplied by 2^(qr-qa-qb) if that
 *  is negative).  Overflow: wraps modulo 2^32 (TI's __IQxmpy, no sat). */
static inline int32_t iqm_mpyiqx(int32_t a, int qa, int32_t b, int qb, int qr)
{
    int s = qa + qb - qr;
    int64_t p = (int64_t)a * b;                          /* Q(qa+qb) */
    if (s >= 0) {
        return iqm_wrap32(iqm_asr64(p, s));
    }
    /* left shift done on uint64_t: wraps, never UB */
    return iqm_s32((uint32_t)(((uint64_t)p << (-s)) & 0xFFFFFFFFu));
}

/** A (Qq) * B (integer) -> Qq.  Overflow: wraps modulo 2^32 (TI:
 *  `(A) * (B)` in long arithmetic). */
static inline int32_t iqm_mpyI32(int32_t a, int32_t b)
{
    return iqm_wrap32((int64_t)a * b);
}

/** Integer part of A (Qq) * B (integer), as TI's _IQmpyI32int: the exact
 *  64-bit product, its integer part truncated toward zero (sign-magnitude,
 *  so that int + frac == A*B), then wrapped to 32 bits ("no round or sat"). */
static inline int32_t iqm_mpyI32int(int32_t a, int32_t b, int q)
{
    int64_t p = (int64_t)a * b;                          /* Qq, |p| <= 2^62 */
    return iqm_wrap32((p >= 0) ? (p >> q) : -((-p) >> q));
}

/** Fractional part of A (Qq) * B (integer), in Qq, with the sign of the
 *  product (TI: frac(A*B); int + frac == A*B).  |result| < 1.0: no overflow. */
static inline int32_t iqm_mpyI32frac(int32_t a, int32_t b, int q)
{
    int64_t p = (int64_t)a * b;
    int64_t mask = ((int64_t)1 << q) - 1;
    return (int32_t)((p >= 0) ? (p & mask) : -((-p) & mask));
}

/* ---- integer / fraction, abs, sat, Q conversions ------------------------ */

/** Integer part of A (Qq), truncated toward zero as TI documents
 *  (_IQint(-2.3456) == -2).  No overflow possible. */
static inline int32_t iqm_int(int32_t a, int q)
{
    int64_t v = a;
    return (int32_t)((v >= 0) ? (v >> q) : -((-v) >> q));
}

/** Fractional part of A (Qq) with the sign of A, as TI documents
 *  (_IQfrac(-2.3456) == -0.3456).  No overflow possible. */
static inline int32_t iqm_frac(int32_t a, int q)
{
    int64_t v = a;
    int64_t mask = ((int64_t)1 << q) - 1;
    return (int32_t)((v >= 0) ? (v & mask) : -((-v) & mask));
}

/** |A|.  Saturates: |INT32_MIN| -> INT32_MAX (the C28x ABS with overflow
 *  mode set; plain labs() would be undefined behaviour in C). */
static inline int32_t iqm_abs(int32_t a)
{
    return (a >= 0) ? a : ((a == INT32_MIN) ? INT32_MAX : -a);
}

/** A limited to [Neg, Pos] (TI's _IQsat(A, Pos, Neg)). */
static inline int32_t iqm_sat(int32_t a, int32_t pos, int32_t neg)
{
    return (a > pos) ? pos : ((a < neg) ? neg : a);
}

/** Qfrom -> Qto: multiply by 2^(to-from) wrapping modulo 2^32 (TI's `<<`),
 *  or floor-shift right (TI's `>>`). */
static inline int32_t iqm_qtoq(int32_t a, int from, int to)
{
    return (to >= from) ? iqm_wrap32((int64_t)a * ((int64_t)1 << (to - from)))
                        : (int32_t)iqm_asr64(a, from - to);
}

/** Qq -> float: (float)A is rounded to 24 bits, the scaling by 2^-q exact. */
static inline float iqm_qtof(int32_t a, int q)
{
    return (float)a / (float)((int32_t)1 << q);
}

/* ---- out of line (iqmath_div_sqrt.c, iqmath_trig.c) --------------------- */

/** A/B in Qq.  Scaling: exact (A * 2^q) / B in 64 bits, truncated toward
 *  zero (error < 1 LSB).  Overflow: saturates to INT32_MAX / INT32_MIN by
 *  the sign of the quotient; B == 0 returns INT32_MAX whatever A is, as
 *  TI's C28x IQNdiv ("= 0x7FFFFFFF if Den == 0"). */
int32_t iqm_div(int32_t a, int32_t b, int q);
/** sqrt(A) in Qq, rounded to nearest (<= 0.5 LSB); A <= 0 returns 0 (TI's
 *  IQNsqrt: "ACC = 0 if input is -ve or 0").  Cannot overflow
 *  (sqrt(2^31 * 2^q) < 2^31; TI: "will never overflow"). */
int32_t iqm_sqrt(int32_t a, int q);
/** 1/sqrt(A) in Qq, rounded to nearest (<= 0.5 LSB).  Saturates to
 *  INT32_MAX when the result exceeds the Q range (A < 2^(3q-62) roughly),
 *  and returns INT32_MAX for A <= 0: the limit of 1/sqrt(x) as x -> 0+,
 *  the same clamp as _IQdiv by zero (TI documents no value here). */
int32_t iqm_isqrt(int32_t a, int q);
/** sqrt(A^2 + B^2), same Q in and out (Q cancels), rounded to nearest
 *  (<= 0.5 LSB); saturates to INT32_MAX (only |A| and |B| near 2^31). */
int32_t iqm_mag(int32_t a, int32_t b);
/** sin(A), A in radians Qq (any value; reduced exactly modulo 2 pi to
 *  2^-32 rev), result Qq rounded.  |result| <= 1.0: no overflow (q <= 30). */
int32_t iqm_sin(int32_t a, int q);
/** cos(A), A in radians Qq, as iqm_sin. */
int32_t iqm_cos(int32_t a, int q);
/** sin(2 pi A), A in per-unit revolutions Qq, any value (only the
 *  fractional part matters: the angle wraps, as TI's _IQsinPU). */
int32_t iqm_sinpu(int32_t a, int q);
/** cos(2 pi A), A in per-unit revolutions Qq, as iqm_sinpu. */
int32_t iqm_cospu(int32_t a, int q);
/** atan2(A, B) in radians Qq (q <= 29), in (-pi, pi]; (0, 0) -> 0. */
int32_t iqm_atan2(int32_t a, int32_t b, int q);
/** atan2(A, B) / (2 pi) in per-unit Qq, in [0, 1) as TI documents:
 *  A >= 0 -> [0, 0.5], A < 0 -> (0.5, 1); results that round up to 1.0
 *  are returned as 1.0 - 1 LSB.  (0, 0) -> 0. */
int32_t iqm_atan2pu(int32_t a, int32_t b, int q);

/* ---- the TI API, GLOBAL_Q -------------------------------------------------*/

#define _IQ(A)                 IQM_FTOQ((A), GLOBAL_Q)
#define _IQtoF(A)              IQM_CALL(IQMATH_FN_TOF, iqm_qtof((A), GLOBAL_Q))

#define _IQmpy(A, B)           IQM_CALL(IQMATH_FN_MPY, iqm_mpy((A), (B), GLOBAL_Q))
#define _IQrmpy(A, B)          IQM_CALL(IQMATH_FN_RMPY, iqm_rmpy((A), (B), GLOBAL_Q))
#define _IQrsmpy(A, B)         IQM_CALL(IQMATH_FN_RSMPY, iqm_rsmpy((A), (B), GLOBAL_Q))
#define _IQmpyIQX(A, IQA, B, IQB) \
    IQM_CALL(IQMATH_FN_MPYIQX, iqm_mpyiqx((A), (IQA), (B), (IQB), GLOBAL_Q))
#define _IQmpyI32(A, B)        IQM_CALL(IQMATH_FN_MPYI32, iqm_mpyI32((A), (B)))
#define _IQmpyI32int(A, B)     IQM_CALL(IQMATH_FN_MPYI32INT, iqm_mpyI32int((A), (B), GLOBAL_Q))
#define _IQmpyI32frac(A, B)    IQM_CALL(IQMATH_FN_MPYI32FRAC, iqm_mpyI32frac((A), (B), GLOBAL_Q))
#define _IQdiv(A, B)           IQM_CALL(IQMATH_FN_DIV, iqm_div((A), (B), GLOBAL_Q))

#define _IQsqrt(A)             IQM_CALL(IQMATH_FN_SQRT, iqm_sqrt((A), GLOBAL_Q))
#define _IQisqrt(A)            IQM_CALL(IQMATH_FN_ISQRT, iqm_isqrt((A), GLOBAL_Q))
#define _IQmag(A, B)           IQM_CALL(IQMATH_FN_MAG, iqm_mag((A), (B)))

#define _IQsin(A)              IQM_CALL(IQMATH_FN_SIN, iqm_sin((A), GLOBAL_Q))
#define _IQcos(A)              IQM_CALL(IQMATH_FN_COS, iqm_cos((A), GLOBAL_Q))
#define _IQsinPU(A)            IQM_CALL(IQMATH_FN_SINPU, iqm_sinpu((A), GLOBAL_Q))
#define _IQcosPU(A)            IQM_CALL(IQMATH_FN_COSPU, iqm_cospu((A), GLOBAL_Q))
#define _IQatan2(A, B)         IQM_CALL(IQMATH_FN_ATAN2, iqm_atan2((A), (B), GLOBAL_Q))
#define _IQatan2PU(A, B)       IQM_CALL(IQMATH_FN_ATAN2PU, iqm_atan2pu((A), (B), GLOBAL_Q))
#define _IQatan(A)             IQM_CALL(IQMATH_FN_ATAN, iqm_atan2((A), IQM_ONE(GLOBAL_Q), GLOBAL_Q))

#define _IQint(A)              IQM_CALL(IQMATH_FN_INT, iqm_int((A), GLOBAL_Q))
#define _IQfrac(A)             IQM_CALL(IQMATH_FN_FRAC, iqm_frac((A), GLOBAL_Q))
#define _IQsat(A, Pos, Neg)    IQM_CALL(IQMATH_FN_SAT, iqm_sat((A), (Pos), (Neg)))
#define _IQabs(A)              IQM_CALL(IQMATH_FN_ABS, iqm_abs(A))
/* A / 2 as TI's IQmathLib.h writes it: an arithmetic shift right, the
 * floor of A/2 (bit for bit _IQmpy(A, _IQ(0.5))); inline, no call */
#define _IQdiv2(A)             ((int32_t)(A) >> 1)

#include "iqmath_qn_fixed.h"

#if defined(IQMATH_TI_CALLS)
/* ---- tools/bench_size.py's compiles only: never linked, never run --------
 * What TI's IQmathLib.h makes a call into IQmath.lib (SPRC990: every
 * operation but _IQmpy, _IQsat, _IQabs, _IQNtoIQ and the conversions of
 * constants, which are intrinsics or macros) becomes here a call to TI's
 * entry of that Q, _IQ<q><op>, named ti_IQ<q><op> (the _IQ names are this
 * header's macros), declared and never defined: the size
 * compile then sizes the call sites as the target has them, and the call
 * graph names the functions of TI's library that the ISR reaches, each
 * sized from TI's own library (bench_size.py TI_IQMATH_WORDS).  _IQmag has
 * no Q of its own here (iqm_mag): it is named ti_IQ<GLOBAL_Q>mag, which has
 * the size of every _IQNmag. */
#define IQM_TI_(q, op) ti_IQ##q##op
#define IQM_TI(q, op) IQM_TI_(q, op)
#define IQM_TI_DECL(q) \
    int32_t IQM_TI(q, rmpy)(int32_t, int32_t);   int32_t IQM_TI(q, rsmpy)(int32_t, int32_t); \
    int32_t IQM_TI(q, mpyI32int)(int32_t, int32_t); \
    int32_t IQM_TI(q, mpyI32frac)(int32_t, int32_t); \
    int32_t IQM_TI(q, int)(int32_t);             int32_t IQM_TI(q, frac)(int32_t); \
    int32_t IQM_TI(q, div)(int32_t, int32_t);    int32_t IQM_TI(q, sqrt)(int32_t); \
    int32_t IQM_TI(q, isqrt)(int32_t);           int32_t IQM_TI(q, mag)(int32_t, int32_t); \
    int32_t IQM_TI(q, sin)(int32_t);             int32_t IQM_TI(q, cos)(int32_t); \
    int32_t IQM_TI(q, sinPU)(int32_t);           int32_t IQM_TI(q, cosPU)(int32_t); \
    int32_t IQM_TI(q, atan2)(int32_t, int32_t);  int32_t IQM_TI(q, atan2PU)(int32_t, int32_t); \
    float IQM_TI(q, toF)(int32_t);
IQM_TI_DECL(1)  IQM_TI_DECL(2)  IQM_TI_DECL(3)  IQM_TI_DECL(4)  IQM_TI_DECL(5)
IQM_TI_DECL(6)  IQM_TI_DECL(7)  IQM_TI_DECL(8)  IQM_TI_DECL(9)  IQM_TI_DECL(10)
IQM_TI_DECL(11) IQM_TI_DECL(12) IQM_TI_DECL(13) IQM_TI_DECL(14) IQM_TI_DECL(15)
IQM_TI_DECL(16) IQM_TI_DECL(17) IQM_TI_DECL(18) IQM_TI_DECL(19) IQM_TI_DECL(20)
IQM_TI_DECL(21) IQM_TI_DECL(22) IQM_TI_DECL(23) IQM_TI_DECL(24) IQM_TI_DECL(25)
IQM_TI_DECL(26) IQM_TI_DECL(27) IQM_TI_DECL(28) IQM_TI_DECL(29) IQM_TI_DECL(30)
#define iqm_rmpy(a, b, q)       IQM_TI(q, rmpy)((a), (b))
#define iqm_rsmpy(a, b, q)      IQM_TI(q, rsmpy)((a), (b))
#define iqm_mpyI32int(a, b, q)  IQM_TI(q, mpyI32int)((a), (b))
#define iqm_mpyI32frac(a, b, q) IQM_TI(q, mpyI32frac)((a), (b))
#define iqm_int(a, q)           IQM_TI(q, int)(a)
#define iqm_frac(a, q)          IQM_TI(q, frac)(a)
#define iqm_div(a, b, q)        IQM_TI(q, div)((a), (b))
#define iqm_sqrt(a, q)          IQM_TI(q, sqrt)(a)
#define iqm_isqrt(a, q)         IQM_TI(q, isqrt)(a)
#define iqm_mag(a, b)           IQM_TI(GLOBAL_Q, mag)((a), (b))
#define iqm_sin(a, q)           IQM_TI(q, sin)(a)
#define iqm_cos(a, q)           IQM_TI(q, cos)(a)
#define iqm_sinpu(a, q)         IQM_TI(q, sinPU)(a)
#define iqm_cospu(a, q)         IQM_TI(q, cosPU)(a)
#define iqm_atan2(a, b, q)      IQM_TI(q, atan2)((a), (b))
#define iqm_atan2pu(a, b, q)    IQM_TI(q, atan2PU)((a), (b))
#define iqm_qtof(a, q)          IQM_TI(q, toF)(a)
#endif /* IQMATH_TI_CALLS */

#else /* MATH_TYPE == FLOAT_MATH */
/* ======================================================================== */
/* FLOAT_MATH: every operation is the float expression (SPRC087 §7)          */
/* ======================================================================== */
#include <float.h>
#include <math.h>

typedef float _iq;
typedef float _iq30;
typedef float _iq29;
typedef float _iq28;
typedef float _iq27;
typedef float _iq26;
typedef float _iq25;
typedef float _iq24;
typedef float _iq23;
typedef float _iq22;
typedef float _iq21;
typedef float _iq20;
typedef float _iq19;
typedef float _iq18;
typedef float _iq17;
typedef float _iq16;
typedef float _iq15;
typedef float _iq14;
typedef float _iq13;
typedef float _iq12;
typedef float _iq11;
typedef float _iq10;
typedef float _iq9;
typedef float _iq8;
typedef float _iq7;
typedef float _iq6;
typedef float _iq5;
typedef float _iq4;
typedef float _iq3;
typedef float _iq2;
typedef float _iq1;

#define MAX_IQ_POS FLT_MAX
#define MAX_IQ_NEG (-FLT_MAX)
#define MIN_IQ_POS FLT_MIN
#define MIN_IQ_NEG (-FLT_MIN)

#define IQF_2PI 6.28318530717958647692f

/** atan2(A, B) in revolutions, [0, 1) (TI's float _IQatan2PU). */
static inline float iqf_atan2pu(float a, float b)
{
    float r = atan2f(a, b) * (1.0f / IQF_2PI);
    return (r >= 0.0f) ? r : (1.0f + r);
}
/** sqrt(A^2 + B^2) (TI's float _IQmag). */
static inline float iqf_mag(float a, float b)
{
    return sqrtf(a * a + b * b);
}
/** Fractional part with the sign of A, as TI's (A - (float)((long)A)). */
static inline float iqf_frac(float a)
{
    return a - (float)(int32_t)a;
}
/** A limited to [Neg, Pos]. */
static inline float iqf_sat(float a, float pos, float neg)
{
    return (a > pos) ? pos : ((a < neg) ? neg : a);
}
/** Integer part (toward zero) of A * B. */
static inline int32_t iqf_mpyI32int(float a, int32_t b)
{
    return (int32_t)(a * (float)b);
}
/** Fractional part (sign of the product) of A * B. */
static inline float iqf_mpyI32frac(float a, int32_t b)
{
    float p = a * (float)b;
    return p - (float)(int32_t)p;
}

#define _IQ(A)                 ((float)(A))
#define _IQtoF(A)              ((float)(A))

#define _IQmpy(A, B)           ((A) * (B))
#define _IQrmpy(A, B)          ((A) * (B))
#define _IQrsmpy(A, B)         ((A) * (B))
#define _IQmpyIQX(A, IQA, B, IQB) ((A) * (B))
#define _IQmpyI32(A, B)        ((A) * (float)(B))
#define _IQmpyI32int(A, B)     iqf_mpyI32int((A), (B))
#define _IQmpyI32frac(A, B)    iqf_mpyI32frac((A), (B))
#define _IQdiv(A, B)           ((A) / (B))

#define _IQsqrt(A)             sqrtf(A)
#define _IQisqrt(A)            (1.0f / sqrtf(A))
#define _IQmag(A, B)           iqf_mag((A), (B))

#define _IQsin(A)              sinf(A)
#define _IQcos(A)              cosf(A)
#define _IQsinPU(A)            sinf((A) * IQF_2PI)
#define _IQcosPU(A)            cosf((A) * IQF_2PI)
#define _IQatan2(A, B)         atan2f((A), (B))
#define _IQatan2PU(A, B)       iqf_atan2pu((A), (B))
#define _IQatan(A)             atanf(A)

#define _IQint(A)              ((int32_t)(A))
#define _IQfrac(A)             iqf_frac(A)
#define _IQsat(A, Pos, Neg)    iqf_sat((A), (Pos), (Neg))
#define _IQabs(A)              fabsf(A)
#define _IQdiv2(A)             ((A) * 0.5f)

#include "iqmath_qn_float.h"

#endif /* MATH_TYPE */

/* ------------------------------------------------------------------------ */
/* Not IQmath: the C28x compiler intrinsic the core uses through             */
/* include/c28x_intrinsics.h, emulated for the host (on the F2812 it is one  */
/* CSB instruction; counted here as IQMATH_FN_NORM32 for the cycle estimate) */
/* ------------------------------------------------------------------------ */

/** Redundant sign bits of @p x: the largest n in [0, 31] with x * 2^n
 *  representable in int32 (what the C28x's CSB / __norm32 return); 31 for
 *  0 and -1.  Integer only, no UB. */
static inline int16_t iqm_norm32(int32_t x)
{
    /* x's bits below the sign, as an unsigned with leading zeros */
    uint32_t u = (x < 0) ? ~(uint32_t)x : (uint32_t)x;
    int16_t n = 0;
    if (u == 0u) {
        return 31;
    }
    /* count leading zeros of u, minus the sign bit */
    if ((u & 0xFFFF0000u) == 0u) { n = (int16_t)(n + 16); u <<= 16; }
    if ((u & 0xFF000000u) == 0u) { n = (int16_t)(n + 8); u <<= 8; }
    if ((u & 0xF0000000u) == 0u) { n = (int16_t)(n + 4); u <<= 4; }
    if ((u & 0xC0000000u) == 0u) { n = (int16_t)(n + 2); u <<= 2; }
    if ((u & 0x80000000u) == 0u) { n = (int16_t)(n + 1); }
    /* u < 2^31 (the sign bit is never set in ~x or x >= 0), so n >= 1; the
     * clamp says so to the static analysis */
    return (int16_t)((n > 0) ? n - 1 : 0);
}
#define iq_norm32(X) IQM_CALL(IQMATH_FN_NORM32, iqm_norm32((int32_t)(X)))

#ifdef __cplusplus
}
#endif

#endif /* IQMATHLIB_H */
