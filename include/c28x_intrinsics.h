/**
 * @file c28x_intrinsics.h
 * The C28x compiler intrinsics the core uses, under one portable name.
 *
 *   iq_norm32(x)  redundant sign bits of a 32-bit value: the largest n in
 *                 [0, 31] with x * 2^n still an int32 (31 for 0 and -1).
 *                 The exponent of a block-floating-point mantissa in one
 *                 instruction (CSB) instead of a search by compares.
 *
 * On the F2812 (TI cl2000, __TMS320C2000__) they are the compiler's own
 * intrinsics (SPRU514, "Using intrinsics": __norm32 is CSB ACC + the
 * normalising shift).  Everywhere else (the host, the AVR co-simulation)
 * the host IQmath library supplies the same function in portable C
 * (host_sim/iqmath/IQmathLib.h: iqm_norm32), counted as one C28x
 * operation by the cycle estimate (tools/bench_isr.py).
 */
#ifndef C28X_INTRINSICS_H
#define C28X_INTRINSICS_H

#include <stdint.h>
#include "IQmathLib.h"

#if defined(__TMS320C2000__)
static inline int16_t iq_norm32(int32_t x)
{
    int shift;
    (void)__norm32(x, &shift);
    return (int16_t)shift;
}
#endif

#endif /* C28X_INTRINSICS_H */
