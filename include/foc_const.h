/* Constants shared by the FOC blocks (private to src/foc).
 *
 * The irrational factors are held in Q30 (resolution 9.3e-10) rather than
 * Q24: multiplied by an input of up to 64 pu their quantisation then costs
 * at most 64 * 2^-31 = 0.5 LSB of Q24 instead of 32 LSB.  They are applied
 * with _IQmpyIQX(x, GLOBAL_Q, k, 30): Q24 * Q30 -> Q24 (GLOBAL_Q). */
#ifndef FOC_CONST_H
#define FOC_CONST_H

#include "IQmathLib.h"

#define FOC_ONE_BY_SQRT3_Q30   _IQ30(0.57735026918962576451)  /* 1/sqrt(3) */
#define FOC_TWO_BY_SQRT3_Q30   _IQ30(1.15470053837925152902)  /* 2/sqrt(3) */
#define FOC_SQRT3_BY_TWO_Q30   _IQ30(0.86602540378443864676)  /* sqrt(3)/2 */
#define FOC_ONE_THIRD_Q30      _IQ30(0.33333333333333333333)  /* 1/3 */

#endif /* FOC_CONST_H */
