/**
 * @file pie.c
 * PIE initialisation.  An interrupt that should never fire (any vector the
 * firmware did not install) lands in pie_unexpected_isr, which disables the
 * bridge and resets the device: a bug must not leave the motor switching,
 * nor the board hanging (it may come before the watchdog is enabled, which
 * main.c does just before EINT).
 */
#include "DSP281x_Device.h"
#include "hal_pwm.h"
#include "pie.h"
#include "sysctrl.h"

#define PIE_VECTORS 128u

static interrupt void pie_unexpected_isr(void)
{
    hal_pwm_disable();
    sysctrl_reset_now();
    for (;;) {
        /* until the reset (at most the watchdog's 4.4 ms) */
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
