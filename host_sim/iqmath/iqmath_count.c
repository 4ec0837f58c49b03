/**
 * @file iqmath_count.c
 * Operation names and, in an IQMATH_COUNT_CALLS build, the call counters
 * used to estimate the ISR cycle budget (calls per ISR times TI's cycle
 * counts per function).  Without IQMATH_COUNT_CALLS there is no global.
 */
#include "IQmathLib.h"

const char *iqmath_fn_name(int id)
{
    static const char *const names[IQMATH_FN_COUNT] = {
        "_IQmpy", "_IQrmpy", "_IQrsmpy", "_IQmpyI32", "_IQmpyI32int",
        "_IQmpyI32frac", "_IQmpyIQX", "_IQdiv", "_IQsqrt", "_IQisqrt",
        "_IQmag", "_IQsin", "_IQcos", "_IQsinPU", "_IQcosPU", "_IQatan2",
        "_IQatan2PU", "_IQatan", "_IQint", "_IQfrac", "_IQsat", "_IQabs",
        "_IQtoF", "_IQtoIQN", "_IQtoQN", "iq_norm32"
    };
    return (id >= 0 && id < (int)IQMATH_FN_COUNT) ? names[id] : "?";
}

#if defined(IQMATH_COUNT_CALLS) && (MATH_TYPE == IQ_MATH)
uint32_t iqmath_call_count[IQMATH_FN_COUNT];

void iqmath_count_reset(void)
{
    int i;
    for (i = 0; i < (int)IQMATH_FN_COUNT; i++) {
        iqmath_call_count[i] = 0u;
    }
}
#endif
