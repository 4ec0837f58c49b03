/**
 * @file flash.c
 * Flash wait states (F2812 datasheet SPRS174, "Flash timing": at 150 MHz
 * paged and random wait states >= 5, OTP >= 8) and the copy of `ramfuncs`
 * and `ramfuncs_slow`.
 */
#include <stdint.h>
#include <string.h>

#include "DSP281x_Device.h"
#include "flash.h"

#pragma CODE_SECTION(flash_init, "ramfuncs")

#define FLASH_PAGEWAIT     5u
#define FLASH_RANDWAIT     5u
#define FLASH_OTPWAIT      8u
#define FLASH_STDBYWAIT    0x01FFu   /* SPRU078 recommended (9-bit count) */
#define FLASH_ACTIVEWAIT   0x01FFu

void flash_copy_ramfuncs(void)
{
    /* The three symbols are distinct objects to C (the linker places them),
     * so their distance is taken between addresses, not pointers (pointer
     * subtraction across objects is undefined).  On the C28x an address
     * counts 16-bit words, the unit of sizeof and memcpy there. */
    size_t n = (size_t)((uintptr_t)&RamfuncsLoadEnd - (uintptr_t)&RamfuncsLoadStart);
    memcpy(&RamfuncsRunStart, &RamfuncsLoadStart, n);
    n = (size_t)((uintptr_t)&RamfuncsSlowLoadEnd - (uintptr_t)&RamfuncsSlowLoadStart);
    memcpy(&RamfuncsSlowRunStart, &RamfuncsSlowLoadStart, n);
}

void flash_init(void)
{
    EALLOW;
    FlashRegs.FOPT.bit.ENPIPE = 1u;
    FlashRegs.FBANKWAIT.bit.PAGEWAIT = FLASH_PAGEWAIT;
    FlashRegs.FBANKWAIT.bit.RANDWAIT = FLASH_RANDWAIT;
    FlashRegs.FOTPWAIT.bit.OTPWAIT = FLASH_OTPWAIT;
    /* written as whole registers: SPRU078 gives these counters 9 bits, the
     * DSP281x header's bit fields only 8 */
    FlashRegs.FSTDBYWAIT.all = FLASH_STDBYWAIT;
    FlashRegs.FACTIVEWAIT.all = FLASH_ACTIVEWAIT;
    EDIS;
    /* SPRU078: wait 8 cycles for the pipeline to take the new values before
     * returning to code in flash */
    __asm(" RPT #7 || NOP");
}
