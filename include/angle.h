/**
 * @file angle.h
 * Per-unit electrical angle helpers shared by park and ipark.
 *
 * Angles are pu of one electrical revolution (1.0 pu = 2 pi rad), as TI's
 * _IQsinPU / _IQcosPU take them.  The caller computes sin and cos ONCE per
 * sample with angle_sincos() and hands the pair to park_t and ipark_t, so
 * the forward and inverse rotations of one sample use bit-identical values
 * (ipark(park(x)) then differs from x only by product rounding).
 */
#ifndef ANGLE_H
#define ANGLE_H

#include <stdint.h>
#include "IQmathLib.h"

/**
 * Wrap a pu angle into [0, 1).
 *
 * @param angle_pu  any _iq (Q24: [-128, 128) pu, i.e. +-128 revolutions).
 * @return          angle_pu - floor(angle_pu), in [0, 1).
 *
 * Scaling and overflow: exact in IQ_MATH (only the integer part is removed,
 * no rounding, no overflow possible).  In FLOAT_MATH the result is exact for
 * |angle| < 128 as well (float subtraction of the integer part is exact by
 * Sterbenz), except that a tiny negative input such as -1e-9 rounds to 1.0f;
 * that case is mapped to 0.0 so the result stays in [0, 1).
 */
_iq angle_wrap_pu(_iq angle_pu);

/**
 * sin and cos of a pu angle: *s = sin(2 pi a), *c = cos(2 pi a), Q24.
 *
 * @param angle_pu  any _iq; wrapped first with angle_wrap_pu(), so an
 *                  integrator that wraps at +-1 or not at all works alike.
 * @param s, c      outputs, Q24, in [-1, 1].
 *
 * Accuracy is that of the IQmath _IQsinPU/_IQcosPU (see IQmathLib.h); the
 * wrap itself adds no error.
 */
void angle_sincos(_iq angle_pu, _iq *s, _iq *c);

/** Largest |d| (pu of a revolution) that angle_sincos_step() rotates by;
 *  beyond it the sin/cos come from the absolute angle. */
#define ANGLE_STEP_MAX_PU 0.03125f

/**
 * sin and cos of a + d (pu), given sin a = @p s and cos a = @p c: a
 * rotation by the small angle d, x = 2 pi d,
 *     cos x = 1 - (x^2/2)(1 - x^2/12),  sin x = x (1 - (x^2/6)(1 - x^2/20)),
 *     *s2 = s cos x + c sin x,  *c2 = c cos x - s sin x,
 * 11 multiplies instead of the wrap and two table look-ups of
 * angle_sincos() (the drive's modulation angle theta_k + 1.5 w_s Ts and the
 * regression's mid-period angle theta_k - step/2 are such small steps from
 * the Park angle).  If |d| > ANGLE_STEP_MAX_PU, *s2, *c2 =
 * angle_sincos(@p a_pu + @p d_pu) instead (an angle that jumped; wrapped
 * there, so a in [0, 1) and |d| < 1 need no wrap here).
 *
 * Accuracy (|d| <= 1/32 rev, x <= 0.196 rad): series error below x^6/720 =
 * 8e-8 (1.3 LSB of Q24) in cos x and x^7/5040 in sin x; each of the 11
 * products truncates (< 1 LSB); against double sin/cos(a_new), within
 * 4 LSB plus the error of the input pair (tests/foc/test_foc_park.c).  The
 * result can exceed 1 by a few LSB; it stays < 1.01 in magnitude (products
 * of |.| <= 1.01 stay in Q24).  In FLOAT_MATH the same formulas in float.
 */
static inline void angle_sincos_step(_iq s, _iq c, _iq a_pu, _iq d_pu, _iq *s2, _iq *c2)
{
    _iq x;
    _iq x2;
    _iq cx;
    _iq sx;

    if (_IQabs(d_pu) > _IQ(ANGLE_STEP_MAX_PU)) {   /* |d| < 1: _IQabs exact */
        angle_sincos(a_pu + d_pu, s2, c2);   /* |a| < 1, |d| < 1: no overflow */
        return;
    }
    x = _IQmpy(d_pu, _IQ(6.28318530717958647692));      /* rad, |x| <= 0.197 */
    x2 = _IQmpy(x, x);                                    /* <= 0.039 */
    /* Horner; every factor in (0.99, 1]: no overflow, < 1 LSB each */
    cx = _IQ(1.0) - _IQmpy(_IQmpy(x2, _IQ(0.5)), _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 12.0)));
    sx = _IQmpy(x, _IQ(1.0) - _IQmpy(_IQmpy(x2, _IQ(1.0 / 6.0)),
                                      _IQ(1.0) - _IQmpy(x2, _IQ(0.05))));
    /* |s|, |c| <= 1.01: each sum <= 1.01 (|cx| + |sx|) < 1.3 */
    *s2 = _IQmpy(s, cx) + _IQmpy(c, sx);
    *c2 = _IQmpy(c, cx) - _IQmpy(s, sx);
}

/**
 * An angle (pu) that is within one revolution of [0, 1) (|x| < 2), brought
 * into [0, 1) exactly.  IQ_MATH: the fraction bits of the two's complement
 * integer, by a mask (the C28x's AND: no compare, no branch; the integer
 * part, whatever its sign, is a whole number of revolutions); the cast back
 * to int32 is of a value below 2^GLOBAL_Q, so it is exact.  FLOAT_MATH: one
 * revolution added or subtracted (as a branch: the float build is the
 * reference, not the target).
 */
static inline _iq angle_wrap_unit(_iq x)
{
#if MATH_TYPE == IQ_MATH
    return (_iq)(int32_t)((uint32_t)x & (((uint32_t)1 << GLOBAL_Q) - 1u));
#else
    if (x >= _IQ(1.0)) {
        x -= _IQ(1.0);
    } else if (x < _IQ(0.0)) {
        x += _IQ(1.0);
    }
    return x;
#endif
}

/** Signed difference b - a of two angles in [0, 1) (pu), along the shorter
 *  arc: the result is in [-0.5, 0.5).  Exact; the inputs must already be
 *  wrapped.  IQ_MATH: ((b - a + 1/2) mod 1) - 1/2 by angle_wrap_unit's mask
 *  (|b - a + 1/2| < 1.5: no overflow). */
static inline _iq angle_diff_pu(_iq b, _iq a)
{
#if MATH_TYPE == IQ_MATH
    return angle_wrap_unit(b - a + _IQ(0.5)) - _IQ(0.5);
#else
    _iq d = b - a;   /* both in [0, 1): the raw difference is in (-1, 1), no overflow */

    if (d >= _IQ(0.5)) {
        d -= _IQ(1.0);
    } else if (d < _IQ(-0.5)) {
        d += _IQ(1.0);
    }
    return d;
#endif
}

/**
 * A phase accumulator: an angle integrated sample by sample, one electrical
 * revolution = 2^32 counts, wrapping by the unsigned overflow (a DDS's
 * accumulator).  Why not the Q24 pu angle: a slip of 0.01-0.02 pu at 15 kHz
 * turns by 3-7e-5 of a revolution per sample, 500-1 000 LSB of Q24, so a
 * truncated increment is 0.05-0.1 % slow on average, and a float32 sum in
 * [0, 1) rounds each increment to the grid of the angle's binade (up to
 * 0.1 %, of a sign that changes with the binade).  At w_r Tr = 40 that
 * orientation error, 3-4e-4 rad, leaks u_T into u_M (method §1) and moved the
 * 15 kW motor's Rs by 0.9 % between the two builds.  With 2^32 counts the
 * increment is 2^-32 of a revolution coarse, 3e-6 of a 0.01 pu slip's.
 *
 * k_acc (Q30): f_base Ts 2^(32 - GLOBAL_Q), revolutions per sample at 1 pu
 * speed in the accumulator's counts per 2^-GLOBAL_Q; below 2 when
 * f_base Ts < 1/128 (ifo_init's check), so it fits Q30 (angle_acc_k()).
 */
typedef uint32_t angle_acc_t;

/** k_acc from f_base Ts (float: init only); f_base Ts in (0, 1/128). */
#define angle_acc_k(fbase_ts) _IQ30((fbase_ts) * (float)(1UL << (32 - GLOBAL_Q)))

/**
 * acc + w k_acc: one sample of an angle turning at @p w_pu (Q24, pu of
 * w_base).  Scaling: Q24 * Q30 -> counts (2^-32 revolution), truncated
 * (0.5 count = 1.2e-10 revolution of bias per sample).  Overflow: none that
 * matters: |w| f_base Ts may exceed half a revolution (|w| < 128 pu), then
 * the int32 increment wraps modulo 2^32 (_IQmpyIQX, TI's __IQxmpy), which is
 * the same angle modulo one revolution; the sum wraps modulo 2^32 (unsigned:
 * defined).  FLOAT_MATH: the increment in revolutions (float, 6e-8
 * relative) is brought into [-0.5, 0.5) and truncated to counts; the sum is the
 * same integer accumulator, so the float build's sum is exact too (a float
 * sum rounds each increment to the angle's grid).
 */
static inline angle_acc_t angle_acc_step(angle_acc_t acc, _iq w_pu, _iq30 k_acc)
{
#if MATH_TYPE == IQ_MATH
    return acc + (uint32_t)_IQmpyIQX(w_pu, GLOBAL_Q, k_acc, 30);
#else
    float rev = w_pu * k_acc * (1.0f / (float)(1UL << (32 - GLOBAL_Q)));

    /* into [-0.5, 0.5) revolution, keeping a small rev exact (no 1 - |rev|);
     * the two compares catch floorf's argument rounded across an integer */
    rev -= floorf(rev + 0.5f);
    if (rev >= 0.5f) {
        rev -= 1.0f;
    } else if (rev < -0.5f) {
        rev += 1.0f;
    }
    /* x 2^32 exact, in [-2^31, 2^31): the int32 conversion is defined */
    return acc + (uint32_t)(int32_t)(rev * 4294967296.0f);
#endif
}

/** The accumulator as a pu angle in [0, 1): its GLOBAL_Q top bits, rounded
 *  (at most 0.5 LSB of Q24, not accumulated; a carry into bit 32 wraps to 0).
 *  FLOAT_MATH: the same 24 bits, exactly representable in float. */
static inline _iq angle_acc_pu(angle_acc_t acc)
{
    const uint32_t top = ((acc + ((uint32_t)1 << (31 - GLOBAL_Q))) >> (32 - GLOBAL_Q)) &
                         (((uint32_t)1 << GLOBAL_Q) - 1u);
#if MATH_TYPE == IQ_MATH
    return (_iq)(int32_t)top;
#else
    return (float)top * (1.0f / (float)(1UL << GLOBAL_Q));
#endif
}

/** A pu angle in [0, 1) as an accumulator (exact in IQ_MATH; FLOAT_MATH
 *  truncates to counts, < 2^-32 revolution). */
static inline angle_acc_t angle_acc_from_pu(_iq a_pu)
{
#if MATH_TYPE == IQ_MATH
    return (uint32_t)a_pu << (32 - GLOBAL_Q);
#else
    return (uint32_t)(a_pu * 4294967296.0f);   /* a in [0, 1): < 2^32 */
#endif
}

#endif /* ANGLE_H */
