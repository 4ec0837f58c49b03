/**
 * @file iq_rmpy.h
 * A rounded Q GLOBAL_Q product from the truncating multiply, for the core's
 * integrators (src/estim: filters, regression, RLS; src/orient: the
 * observer's correction and current model), where a truncated product
 * would bias the state by -1/2 LSB per sample.
 *
 * iq_rmpy(a, b) is _IQrmpy(a, b) bit for bit (round half up), computed as
 * the truncating _IQmpyIQX one bit finer (the 5-cycle C28x intrinsic) and
 * iq_round_half (two ALU operations) instead of the 22-cycle library call.
 * Valid for |a b| < 2^(30 - GLOBAL_Q) (64 pu at Q24; beyond, it wraps as
 * _IQrmpy does beyond 128 pu): each caller states why its product is in
 * range.  In FLOAT_MATH the product is exact to float precision and the
 * rounding step is the identity.
 */
#ifndef IQ_RMPY_H
#define IQ_RMPY_H

#include <stdint.h>
#include "IQmathLib.h"

#if MATH_TYPE == IQ_MATH
/**
 * y = floor(2x) in Q(n+1), the result of _IQ(N-1)mpy(a, b) where
 * _IQNrmpy(a, b) = x in Q(n) is wanted; returns floor((y + 1) / 2) =
 * floor(x + 1/2), bit-identical to _IQNrmpy (nested floors:
 * floor((floor(z) + 1) / 2) = floor((z + 1) / 2)).  Needs |2x| < 2^31 raw;
 * written as floor(y / 2) + b, b = the low bit (= floor((y + 1) / 2): no sum
 * that can overflow), floor(y / 2) by _IQdiv2, IQmath's arithmetic shift
 * (the C28x's ASR; host_sim's IQmathLib.h the same), two cycles where a
 * signed C division by 2 costs a sign correction as well.
 */
static inline _iq iq_round_half(_iq y)
{
    return _IQdiv2(y) + (int32_t)((uint32_t)y & 1u);
}
#else
/** FLOAT: the product is exact to float precision; nothing to round. */
static inline _iq iq_round_half(_iq y)
{
    return y;
}
#endif

/** _IQrmpy(a, b) for |a b| < 2^(30 - GLOBAL_Q): see the file comment. */
static inline _iq iq_rmpy(_iq a, _iq b)
{
    /* a b 2^-(GLOBAL_Q - 1): a read as Q(GLOBAL_Q - 1), result in Q(GLOBAL_Q + 1) */
    return iq_round_half(_IQmpyIQX(a, GLOBAL_Q - 1, b, GLOBAL_Q));
}

#endif /* IQ_RMPY_H */
