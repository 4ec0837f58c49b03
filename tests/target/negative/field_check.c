/* The syntax check's own test: compiled once with FIELD=TMODE (TI's name:
 * must compile) and once with FIELD=TMODES (not a T1CON field: must fail
 * with "has no member named"), which proves that a wrong register field
 * name in firmware/ fails CI. */
#include "DSP281x_Device.h"

void field_check(void);
void field_check(void)
{
    EvaRegs.T1CON.bit.FIELD = 1u;
}
