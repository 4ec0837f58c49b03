/**
 * @file pie.c
 * PIE initialisation.  An interrupt that should never fire (any vector the
 * firmware did not install) lands in pie_unexpected_isr, which disables the
 * bridge and stops: a bug must not leave the motor switching.
 */
#include "DSP281x_Device.h"
#include "hal_pwm.h"
#include "pie.h"

#define PIE_VECTORS 128u

static interrupt void pie_unexpected_isr(void)
{
    hal_pwm_disable();
    for (;;) {
        /* halted on purpose: the watchdog resets the device */
    }
}

void pie_init(void)
{
    PINT *v = (PINT *)&PieVectTable;
    uint16_t i;

    DINT;
    /* the PIE must be off while its registers and table are changed */
    PieCtrlRegs.PIECRTL.bit.ENPIE = 0u;
    PieCtrlRegs.PIEIER1.all = 0u;  PieCtrlRegs.PIEIFR1.all = 0u;
    PieCtrlRegs.PIEIER2.all = 0u;  PieCtrlRegs.PIEIFR2.all = 0u;
    PieCtrlRegs.PIEIER3.all = 0u;  PieCtrlRegs.PIEIFR3.all = 0u;
    PieCtrlRegs.PIEIER4.all = 0u;  PieCtrlRegs.PIEIFR4.all = 0u;
    PieCtrlRegs.PIEIER5.all = 0u;  PieCtrlRegs.PIEIFR5.all = 0u;
    PieCtrlRegs.PIEIER6.all = 0u;  PieCtrlRegs.PIEIFR6.all = 0u;
    PieCtrlRegs.PIEIER7.all = 0u;  PieCtrlRegs.PIEIFR7.all = 0u;
    PieCtrlRegs.PIEIER8.all = 0u;  PieCtrlRegs.PIEIFR8.all = 0u;
    PieCtrlRegs.PIEIER9.all = 0u;  PieCtrlRegs.PIEIFR9.all = 0u;
    PieCtrlRegs.PIEIER10.all = 0u; PieCtrlRegs.PIEIFR10.all = 0u;
    PieCtrlRegs.PIEIER11.all = 0u; PieCtrlRegs.PIEIFR11.all = 0u;
    PieCtrlRegs.PIEIER12.all = 0u; PieCtrlRegs.PIEIFR12.all = 0u;
    IER = 0x0000u;
    IFR = 0x0000u;

    EALLOW;
    for (i = 0u; i < PIE_VECTORS; i++) {
        v[i] = pie_unexpected_isr;
    }
    EDIS;

    PieCtrlRegs.PIECRTL.bit.ENPIE = 1u;
    /* acknowledge every group, as TI's EnableInterrupts(): a group left
     * un-acknowledged from before a reset by the debugger would block its
     * first interrupt */
    PieCtrlRegs.PIEACK.all = 0xFFFFu;
}
