/*
 * F2812_ram.cmd: the debug image that CCS loads into RAM, without
 * programming the flash (FIRMWARE_IMAGE=ram).  Use with F2812_headers.cmd;
 * #includes F2812_isr_path.cmd and F2812_isr_slow.cmd as F2812_flash.cmd does.
 * Memory map: SPRS174, as in F2812_flash.cmd (checked by the same CI test).
 *
 * What fits: the on-chip RAM is 18K (M0 1K, M1 1K, L0 4K, L1 4K, H0 8K); the
 * firmware needs about 39K words (tools/bench_size.py --linker-cmd
 * linker/F2812_ram.cmd, CTest target_ram_fit_ram_image): the ISR path, .ebss,
 * the data log and the stack on chip as in F2812_flash.cmd, and about 30K of
 * other code and constants.  So a RAM-only image of the whole firmware does
 * NOT fit the F2812's internal RAM.  This image therefore needs a board with
 * external SRAM on XINTF zone 6 (0x100000, 64K words here, as the eZdsp
 * F2812 board has; the XINTF timing registers reset to their slowest
 * setting, SPRU067, so CCS can load there before any code ran), which takes
 * the code that runs at most once per telemetry frame (init, background,
 * telemetry, the float emulation, the IQmath functions off the ISR path) and
 * the constants.  Everything the ISR runs is on-chip in the same ranges as
 * in the flash image (F2812_flash.cmd describes them), loaded in place
 * (LOAD = RUN: flash_copy_ramfuncs copies each section onto itself, a
 * no-op, so main.c is the same for both images):
 *   L0+L1 8K   ramfuncs (RAML0L1), .ebss (RAML0L1_DATA) and, unlike the
 *              flash image, dlog (RAML1_DLOG): H0 holds the flash set too
 *   H0 8K      codestart (boot-to-H0 entry, 2 words), ramfuncs_slow
 *              (RAMH0)
 *   M0+M1 2K   .stack (0x500), bgdata and .esysmem (no heap)
 * with one difference: the ISR path's FLASH set (the functions the flash
 * image runs from flash: CALIBRATE-only, state changes, faults, the
 * sequence's step; tools/bench_size.py FLASH_ROOTS) is on chip here too
 * (ISR_FLASH_SET_IN_RAM, below): zone 6 at the XINTF's reset timing would
 * cost far more than flash.  So this debug image keeps less than 30 % of its
 * RAM blocks spare (CTest target_ram_fit_ram_image checks 10 %).
 *   XINTF 6    .text, IQmath, .cinit, .pinit, .switch, .econst
 * On a board without external RAM use the flash image.  How to load: CCS
 * "Load Program" of the FIRMWARE_IMAGE=ram build (the loader sets the PC to
 * _c_int00), or a reset in the boot ROM's "jump to H0 SARAM" mode (boot mode
 * pins: SPRS174 "Boot mode selection"), which branches to BEGINH0.
 */

MEMORY
{
PAGE 0 :
   BEGINH0    : origin = 0x3F8000, length = 0x000002   /* boot-to-H0 entry */
   RAML0L1    : origin = 0x008000, length = 0x001000   /* L0: ramfuncs */
   RAMH0      : origin = 0x3F8002, length = 0x001FFE   /* H0 after BEGINH0: ramfuncs_slow */
   XRAM6      : origin = 0x100000, length = 0x010000   /* external SRAM, XINTF zone 6 */
   CSM_PWL    : origin = 0x3F7FF8, length = 0x000008   /* CsmPwlFile (F2812_headers.cmd) */
   IQTABLES   : origin = 0x3FF000, length = 0x000B50
   RESET      : origin = 0x3FFFC0, length = 0x000002

PAGE 1 :
   RAMM0M1    : origin = 0x000000, length = 0x000800   /* M0 + M1 SARAM */
   RAML0L1_DATA : origin = 0x009000, length = 0x000C80 /* L1 up to 0x9C7F: .ebss */
   RAML1_DLOG : origin = 0x009C80, length = 0x000380   /* last 0.875K of L1: dlog */
}

/* the ISR path's flash set on chip (the #ifdef blocks of the two includes) */
#define ISR_FLASH_SET_IN_RAM
/* the control ISR's code that the flash image runs from H0 (FAST_IN_SLOW_RAM
 * of tools/bench_size.py) in L0+L1 here: this image's H0 also holds the slow
 * ISR's flash set */
#define ISR_RAM_IMAGE

SECTIONS
{
   codestart        : > BEGINH0,    PAGE = 0
   ramfuncs         : {
                         *(ramfuncs)
#include "F2812_isr_path.cmd"
                      }
                      LOAD = RAML0L1, RUN = RAML0L1,
                      LOAD_START(_RamfuncsLoadStart),
                      LOAD_END(_RamfuncsLoadEnd),
                      RUN_START(_RamfuncsRunStart),
                      PAGE = 0
   /* the slow set (reached only through drive_slow_task) and the TI IQmath
    * functions the ISR calls (members of IQmath_coff.lib named at the end of
    * F2812_isr_slow.cmd) run from H0, zero wait states as L0/L1 */
   ramfuncs_slow    : {
                         *(ramfuncs_slow)
#include "F2812_isr_slow.cmd"
                      }
                      LOAD = RAMH0, RUN = RAMH0,
                      LOAD_START(_RamfuncsSlowLoadStart),
                      LOAD_END(_RamfuncsSlowLoadEnd),
                      RUN_START(_RamfuncsSlowRunStart),
                      PAGE = 0
   /* TI's IQmath functions off the ISR path (the background's) */
   IQmath           : > XRAM6,  PAGE = 0
   .text            : > XRAM6,      PAGE = 0
   .cinit           : > XRAM6,      PAGE = 0
   .pinit           : > XRAM6,      PAGE = 0
   .switch          : > XRAM6,      PAGE = 0
   .econst          : > XRAM6,      PAGE = 0
   IQmathTables     : > IQTABLES,   PAGE = 0, TYPE = NOLOAD
   .reset           : > RESET,      PAGE = 0, TYPE = DSECT

   .stack           : > RAMM0M1,    PAGE = 1
   bgdata           : > RAMM0M1,    PAGE = 1   /* the background's state (main.c) */
   .ebss            : > RAML0L1_DATA, PAGE = 1
   dlog             : > RAML1_DLOG, PAGE = 1
   .esysmem         : > RAMM0M1,    PAGE = 1
}
