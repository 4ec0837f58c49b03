/**
 * @file flash.h
 * Flash wait states and the flash-to-RAM copy of the time-critical code.
 */
#ifndef FLASH_H
#define FLASH_H

#include <stdint.h>

/** Linker symbols of the `ramfuncs` output section (linker/F2812_flash.cmd:
 *  LOAD in flash, RUN in L0/L1 SARAM).  It holds the control ISR, the whole
 *  core called from it (compiled with --ramfunc=on: section .TI.ramfunc),
 *  IQmath.lib's code (section IQmath) and flash_init itself. */
extern uint16_t RamfuncsLoadStart;
extern uint16_t RamfuncsLoadEnd;
extern uint16_t RamfuncsRunStart;

/** Copy `ramfuncs` from flash to RAM.  Must run before flash_init() (which
 *  lives there) and before any ISR is enabled. */
void flash_copy_ramfuncs(void);
/** Set the flash and OTP wait states for 150 MHz and enable the flash
 *  pipeline.  Runs from RAM: the flash registers must not be changed while
 *  the code that changes them is fetched from flash (SPRU078). */
void flash_init(void);

#endif /* FLASH_H */
