/**
 * @file sysctrl.h
 * System control of the F2812 (SPRU078): watchdog, PLL, peripheral clocks.
 */
#ifndef SYSCTRL_H
#define SYSCTRL_H

/** Disable the watchdog, set the PLL to 150 MHz from the 30 MHz clock and
 *  wait for lock, set HSPCLK / LSPCLK and enable the clocks of EV-A, ADC and
 *  SCI-A.  First call after reset (the boot ROM leaves the watchdog running). */
void sysctrl_init(void);
/** Enable the watchdog (reset after 256 / (OSCCLK / 512 / 64) = 280 ms
 *  without service).  Called before interrupts are enabled (main.c): from
 *  then on a hang anywhere resets. */
void sysctrl_watchdog_enable(void);
/** Reset the device now through the watchdog (enabled at its fastest, then
 *  a write of WDCR with wrong check bits); whether or not the watchdog was
 *  enabled before.  Does not return on the F2812 (the caller loops anyway:
 *  at most 4.4 ms until the watchdog's overflow). */
void sysctrl_reset_now(void);
/** Service the watchdog (key sequence 0x55, 0xAA).  Background loop only:
 *  a stuck background loop, or an ISR that takes all the CPU, resets. */
void sysctrl_watchdog_service(void);

#endif /* SYSCTRL_H */
