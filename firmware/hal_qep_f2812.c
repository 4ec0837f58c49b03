/**
 * @file hal_qep_f2812.c
 * hal_qep.h on EV-A's QEP circuit (SPRU065 "Quadrature encoder pulse
 * circuit").  GP timer 2 is the QEP time base: TMODE = 11 (directional
 * up/down, the direction from the decoder), TCLKS10 = 11 (clock from the QEP
 * circuit), TPS = 000.  Capture units 1 and 2 are disabled (CAP12EN = 00) so
 * that the CAP1/QEP1 and CAP2/QEP2 pins feed the decoder, as TI's F281x QEP
 * driver (DMC library, F281XQEP) configures it.  T2PR = 0xFFFF: the count
 * wraps modulo 2^16 and the core takes differences modulo 2^16.
 */
#include "DSP281x_Device.h"
#include "hal_qep.h"
#include "qep_f2812.h"

#pragma CODE_SECTION(hal_qep_read_count, "ramfuncs")

void qep_f2812_init(void)
{
    EvaRegs.CAPCONA.all = 0u;
    EvaRegs.CAPCONA.bit.CAPRES = 1u;     /* reset the capture units (reads 0) */
    EvaRegs.CAPCONA.bit.CAP12EN = 0u;
    EvaRegs.CAPCONA.bit.CAP3EN = 0u;     /* no index used */

    EvaRegs.T2PR = 0xFFFFu;
    EvaRegs.T2CNT = 0u;
    EvaRegs.T2CON.all = 0u;
    EvaRegs.T2CON.bit.FREE = 1u;         /* keep counting on an emulator halt */
    EvaRegs.T2CON.bit.TMODE = 3u;
    EvaRegs.T2CON.bit.TPS = 0u;
    EvaRegs.T2CON.bit.TCLKS10 = 3u;
    EvaRegs.T2CON.bit.TENABLE = 1u;
}

uint16_t hal_qep_read_count(void)
{
    return EvaRegs.T2CNT;
}
