/*
 * F2812_flash.cmd: the stand-alone (boot to flash) image of the F2812
 * firmware.  Use with F2812_headers.cmd (peripheral register frames).
 *
 * Memory map: TMS320F2812 data sheet (SPRS174), "F2812 memory map" and
 * "Flash sectors" tables; tools/target/check_linker_cmd.py checks every
 * range below against that table in CI (test target_linker_memory_map).
 * The C28x has one unified memory: PAGE 0 (program) and PAGE 1 (data) name
 * the same address space, so no range may appear on both pages.
 *
 * RAM budget (16-bit words):
 *   L0+L1 SARAM 8K  ramfuncs RUN: the control ISR and its HAL reads/writes,
 *                   the whole portable core (compiled --ramfunc=on: every
 *                   core function, _init included, is in .TI.ramfunc) and
 *                   IQmath.lib's code (section IQmath).  Estimated 5-6K;
 *                   the link fails if it does not fit (.map shows the size).
 *                   L0/L1 are CSM-secure RAM: secure code may run there.
 *   H0 SARAM 8K     .ebss (drive_t, telemetry 0.6K, statics) and dlog
 *                   (the data log, 4 x 256 x 32 bit = 2K, fixed address
 *                   for the CCS graph window)
 *   M1 SARAM 1K     .stack (ISR + background, no recursion)
 *   M0 SARAM 1K     .esysmem (no heap is used: -heap 0) and spare
 * Flash 128K: code in J..E, constants in F, ramfuncs LOAD image in D, C..B
 * spare, A holds only codestart (BEGIN), the CSM reserved words and password.
 */

MEMORY
{
PAGE 0 :   /* program */
   RAML0L1    : origin = 0x008000, length = 0x002000   /* L0 + L1 SARAM, ramfuncs RUN */
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
   RAMM0      : origin = 0x000000, length = 0x000400
   RAMM1      : origin = 0x000400, length = 0x000400
   RAMH0      : origin = 0x3F8000, length = 0x002000
}

SECTIONS
{
   codestart        : > BEGIN,      PAGE = 0
   ramfuncs         : { *(ramfuncs) *(.TI.ramfunc) *(IQmath) }
                      LOAD = FLASHD, RUN = RAML0L1,
                      LOAD_START(_RamfuncsLoadStart),
                      LOAD_END(_RamfuncsLoadEnd),
                      RUN_START(_RamfuncsRunStart),
                      PAGE = 0
   .text            : >> FLASHJ | FLASHI | FLASHH | FLASHG,  PAGE = 0
   .cinit           : > FLASHE,     PAGE = 0
   .pinit           : > FLASHE,     PAGE = 0
   .switch          : > FLASHE,     PAGE = 0
   .econst          : > FLASHF,     PAGE = 0
   IQmathTables     : > IQTABLES,   PAGE = 0, TYPE = NOLOAD
   .reset           : > RESET,      PAGE = 0, TYPE = DSECT   /* boot ROM supplies it */

   .stack           : > RAMM1,      PAGE = 1
   .ebss            : > RAMH0,      PAGE = 1
   dlog             : > RAMH0,      PAGE = 1
   .esysmem         : > RAMM0,      PAGE = 1
}
