/*
 * F2812_flash.cmd: the stand-alone (boot to flash) image of the F2812
 * firmware.  Use with F2812_headers.cmd (peripheral register frames); it
 * #includes F2812_isr_path.cmd and F2812_isr_slow.cmd (generated, the ISR
 * path's functions, every period / only through the slow dispatch), found
 * through the link's --search_path (firmware/CMakeLists.txt, the CCS project).
 *
 * Memory map: TMS320F2812 data sheet (SPRS174), "F2812 memory map" and
 * "Flash sectors" tables; tools/target/check_linker_cmd.py checks every
 * range below against that table in CI (test target_linker_memory_map).
 * The C28x has one unified memory: PAGE 0 (program) and PAGE 1 (data) name
 * the same address space, so no range may appear on both pages.
 *
 * RAM plan, 16-bit words.  The words each range holds are estimated by
 * tools/bench_size.py (Thumb-2 stand-in compiler x 1.2, TI's IQmath at its
 * library's sizes; `--markdown` prints the table that docs/board.md shows
 * and checks); CTests target_ram_fit_* fail above 70 % of a range (30 %
 * kept spare, for the stand-in's error and for growth).  Only the ISR path
 * runs from RAM, split by the call graph in two sets, less its FLASH set
 * (the functions that run only in CALIBRATE, on a state change, after a
 * fault, or the sequence's step once per slow period: bench_size.py
 * FLASH_ROOTS, the `#ifdef ISR_FLASH_SET_IN_RAM` blocks of the two includes),
 * which stays in .text and runs from flash, its wait states costed by
 * tools/bench_isr.py.  All SARAM is zero-wait at 150 MHz (SPRS174), so which
 * block an ISR function runs from does not change its cycles.  L0+L1 and H0 are each
 * split in a program range (PAGE 0) and a data range (PAGE 1) that do not
 * overlap (one unified memory); the boundaries balance the two parts:
 *   L0+L1 8K  RAML0L1: ramfuncs RUN: the every-period set
 *             (F2812_isr_path.cmd: src/ functions the control ISR reaches
 *             without going through drive_slow_task, drive_slow_task
 *             itself included), the firmware's ISR and HAL functions
 *             (#pragma CODE_SECTION "ramfuncs"), flash_init (reprograms the
 *             wait states).
 *             RAML0L1_DATA: .ebss (drive_t and the firmware's statics).
 *   H0 8K     RAMH0: ramfuncs_slow RUN: the set the ISR reaches only
 *             through drive_slow_task (F2812_isr_slow.cmd: the slot tasks:
 *             filters, observer, sequence, adaptation, tracker) and the TI
 *             IQmath functions the ISR calls (members of IQmath_coff.lib
 *             named at the end of F2812_isr_slow.cmd; TI's IQmath examples
 *             run IQmath from RAM too: 2812_IQmath_lnk.cmd); the IQmath
 *             functions only the background calls stay in flash (IQmath).
 *             RAMH0_DATA: dlog (the data log, 16-bit samples; a CCS
 *             graph takes its address from the symbol g_dlog) and bgdata
 *             (the background's state: telemetry rings, frame timer; main.c).
 *   M0+M1 2K  .stack alone (--stack_size=0x500 in firmware/CMakeLists.txt:
 *             the estimate / 0.7; the stack pointer is 16 bits, so the stack
 *             must be in the low 64K words: M0/M1 or L0/L1, SPRU430; the
 *             estimate is the deepest background chain + the deepest ISR
 *             chains + the interrupt contexts) and .esysmem (no heap:
 *             --heap_size=0).
 * Code security (CSM): on the F281x the CSM protects the flash, the OTP and
 * the L0/L1 SARAM (TI SPRU078, "Code Security Module"; H0, M0, M1 are not
 * secure memory).  With a password programmed and the device locked, code
 * running from unsecure memory cannot read secure memory (reads return 0).
 * ramfuncs_slow runs from H0 and reads .ebss (L1) and flash constants, so a
 * locked device would break the slow tasks: run the drive with the CSM
 * unlocked (erased password, as in development), or move ramfuncs_slow to
 * secure memory.  (This reading of SPRU078 could not be checked against the
 * document here; confirm it before programming a password.)
 * Flash 128K: code in J..E, constants in F, ramfuncs LOAD image in D,
 * ramfuncs_slow LOAD image in C, B spare, A holds only
 * codestart (BEGIN), the CSM reserved words and password.
 * IQmathTables (sin/cos/atan/div/sqrt seed tables) stay in boot ROM
 * (NOLOAD; 1 wait state, SPRS174): TI's IQmath functions read them there.
 * Constants (.econst) and switch tables (.switch) the ISR reads are in flash
 * (5 wait states): a cost for the ISR's cycles, not a placement error.
 */

MEMORY
{
PAGE 0 :   /* program */
   RAML0L1    : origin = 0x008000, length = 0x001000   /* L0: ramfuncs RUN */
   RAMH0      : origin = 0x3F8000, length = 0x001AA0   /* first 6816 words of H0: ramfuncs_slow RUN */
   OTP        : origin = 0x3D7800, length = 0x000400   /* 1K OTP, not used */
   FLASHJ     : origin = 0x3D8000, length = 0x002000
   FLASHI     : origin = 0x3DA000, length = 0x002000
   FLASHH     : origin = 0x3DC000, length = 0x004000
   FLASHG     : origin = 0x3E0000, length = 0x004000
   FLASHF     : origin = 0x3E4000, length = 0x004000
   FLASHE     : origin = 0x3E8000, length = 0x004000
   FLASHD     : origin = 0x3EC000, length = 0x004000
   FLASHC     : origin = 0x3F0000, length = 0x004000
   FLASHB     : origin = 0x3F4000, length = 0x002000
   FLASHA     : origin = 0x3F6000, length = 0x001F80
   CSM_RSVD   : origin = 0x3F7F80, length = 0x000076   /* program 0x0000 when the CSM is used */
   BEGIN      : origin = 0x3F7FF6, length = 0x000002   /* boot-to-flash entry */
   CSM_PWL    : origin = 0x3F7FF8, length = 0x000008   /* CSM password */
   IQTABLES   : origin = 0x3FF000, length = 0x000B50   /* IQmath tables in boot ROM */
   RESET      : origin = 0x3FFFC0, length = 0x000002   /* boot ROM reset vector */

PAGE 1 :   /* data */
   RAMM0M1    : origin = 0x000000, length = 0x000800   /* M0 + M1 SARAM */
   RAML0L1_DATA : origin = 0x009000, length = 0x001000 /* L1: .ebss */
   RAMH0_DATA : origin = 0x3F9AA0, length = 0x000560   /* last 1376 words of H0: dlog, bgdata */
}

SECTIONS
{
   codestart        : > BEGIN,      PAGE = 0
   /* exactly the ISR path: the firmware's #pragma'd functions, the src/
    * functions of F2812_isr_path.cmd (named input sections take precedence
    * over the generic .text below: SPRU513 "Subsections"), TI's IQmath */
   ramfuncs         : {
                         *(ramfuncs)
#include "F2812_isr_path.cmd"
                      }
                      LOAD = FLASHD, RUN = RAML0L1,
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
                      LOAD = FLASHC, RUN = RAMH0,
                      LOAD_START(_RamfuncsSlowLoadStart),
                      LOAD_END(_RamfuncsSlowLoadEnd),
                      RUN_START(_RamfuncsSlowRunStart),
                      PAGE = 0
   /* TI's IQmath functions off the ISR path (the background's) */
   IQmath           : >> FLASHJ | FLASHI | FLASHH | FLASHG,  PAGE = 0
   .text            : >> FLASHJ | FLASHI | FLASHH | FLASHG,  PAGE = 0
   .cinit           : > FLASHE,     PAGE = 0
   .pinit           : > FLASHE,     PAGE = 0
   .switch          : > FLASHE,     PAGE = 0
   .econst          : > FLASHF,     PAGE = 0
   IQmathTables     : > IQTABLES,   PAGE = 0, TYPE = NOLOAD
   .reset           : > RESET,      PAGE = 0, TYPE = DSECT   /* boot ROM supplies it */

   .stack           : > RAMM0M1,    PAGE = 1
   bgdata           : > RAMH0_DATA, PAGE = 1   /* the background's state (main.c) */
   .ebss            : > RAML0L1_DATA, PAGE = 1
   dlog             : > RAMH0_DATA, PAGE = 1
   .esysmem         : > RAMM0M1,    PAGE = 1
}
