/**
 * @file sysctrl.c
 * Watchdog, PLL and peripheral clocks (SPRU078, "Clocking" and "Watchdog").
 */
#include "DSP281x_Device.h"
#include "board_config.h"
#include "sysctrl.h"

/* WDCR (SPRU078): WDCHK (5:3) must be written 101 on every write or the
 * device resets; WDDIS is bit 6; WDPS (2:0) = 111 divides WDCLK by 64. */
#define WDCR_DISABLE   0x0068u   /* WDDIS = 1, WDCHK = 101, WDPS = 000 */
#define WDCR_ENABLE    0x002Fu   /* WDDIS = 0, WDCHK = 101, WDPS = 111 */
#define WDCR_FASTEST   0x0028u   /* WDDIS = 0, WDCHK = 101, WDPS = 000: 256 / (OSCCLK / 512) = 4.4 ms */
#define WDCR_BAD_CHECK 0x0000u   /* WDCHK = 000: a system reset */

/* The PLL locks within 131072 OSCCLK cycles (SPRU078).  The CPU runs from
 * OSCCLK/2 while the PLL relocks, so the wait below (>= 4 CPU cycles per
 * iteration) is >= 131072 OSCCLK cycles with margin. */
#define PLL_LOCK_LOOPS 65536UL

static void pll_wait_lock(void)
{
    volatile uint32_t n;
    for (n = 0u; n < PLL_LOCK_LOOPS; n++) {
        /* busy wait: no timer is running yet */
    }
}

void sysctrl_init(void)
{
    EALLOW;
    SysCtrlRegs.WDCR = WDCR_DISABLE;
    EDIS;

    /* Change the PLL only if it is not already set (e.g. after a debugger
     * reset): writing PLLCR restarts the lock sequence. */
    if (SysCtrlRegs.PLLCR.bit.DIV != BOARD_PLLCR_DIV) {
        EALLOW;
        SysCtrlRegs.PLLCR.bit.DIV = BOARD_PLLCR_DIV;
        EDIS;
        pll_wait_lock();
    }

    EALLOW;
    SysCtrlRegs.HISPCP.all = BOARD_HISPCP;   /* HSPCLK = 150 MHz */
    SysCtrlRegs.LOSPCP.all = BOARD_LOSPCP;   /* LSPCLK = 37.5 MHz */
    SysCtrlRegs.PCLKCR.all = 0u;             /* every unused peripheral off */
    SysCtrlRegs.PCLKCR.bit.EVAENCLK = 1u;
    SysCtrlRegs.PCLKCR.bit.ADCENCLK = 1u;
    SysCtrlRegs.PCLKCR.bit.SCIAENCLK = 1u;
    EDIS;
}

void sysctrl_watchdog_enable(void)
{
    sysctrl_watchdog_service();
    EALLOW;
    SysCtrlRegs.WDCR = WDCR_ENABLE;
    EDIS;
}

void sysctrl_reset_now(void)
{
    /* the watchdog on at its fastest first (the check bits right): should a
     * silicon revision ignore the wrong check bits while the watchdog is
     * disabled, as TI's later C28x devices do, its overflow resets within
     * 4.4 ms; then the write with the wrong check bits, which resets at once
     * (SPRU078, "Watchdog block": WDCHK must be written 101 on every write
     * of WDCR, any other value resets the device) */
    EALLOW;
    SysCtrlRegs.WDCR = WDCR_FASTEST;
    SysCtrlRegs.WDCR = WDCR_BAD_CHECK;
    EDIS;
}

void sysctrl_watchdog_service(void)
{
    EALLOW;
    SysCtrlRegs.WDKEY = 0x0055u;
    SysCtrlRegs.WDKEY = 0x00AAu;
    EDIS;
}
