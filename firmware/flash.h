/**
 * @file flash.h
 * Flash wait states and the flash-to-RAM copy of the time-critical code.
 */
#ifndef FLASH_H
#define FLASH_H

#include <stdint.h>

/** Linker symbols of the `ramfuncs` output section (linker/F2812_flash.cmd:
 *  LOAD in flash, RUN in L0/L1 SARAM).  It holds the control ISR, what it
 *  calls every period (linker/F2812_isr_path.cmd) and flash_init itself. */
extern uint16_t RamfuncsLoadStart;
extern uint16_t RamfuncsLoadEnd;
extern uint16_t RamfuncsRunStart;
/** ... and of `ramfuncs_slow` (LOAD in flash, RUN in H0 SARAM): what the ISR
 *  reaches only through the slow-task dispatch (linker/F2812_isr_slow.cmd)
 *  and IQmath.lib's code (section IQmath). */
extern uint16_t RamfuncsSlowLoadStart;
extern uint16_t RamfuncsSlowLoadEnd;
extern uint16_t RamfuncsSlowRunStart;

/** Copy `ramfuncs` and `ramfuncs_slow` from flash to RAM.  Must run before flash_init() (which
 *  lives there) and before any ISR is enabled. */
void flash_copy_ramfuncs(void);
/** Set the flash and OTP wait states for 150 MHz and enable the flash
 *  pipeline.  Runs from RAM: the flash registers must not be changed while
 *  the code that changes them is fetched from flash (SPRU078). */
void flash_init(void);

#endif /* FLASH_H */
