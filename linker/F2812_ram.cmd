/*
 * F2812_ram.cmd: the debug image, loaded by CCS into RAM and started in
 * "boot to H0" mode (or run from the debugger).  Use with F2812_headers.cmd.
 * Memory map: SPRS174, as in F2812_flash.cmd (checked by the same CI test).
 *
 * Budget (16-bit words): H0 8K = code (.text, constants, init tables);
 * L0 4K = ramfuncs (LOAD = RUN here: flash_copy_ramfuncs copies the section
 * onto itself, a no-op, so main.c is the same for both images);
 * L1 4K = .ebss + dlog; M1 1K = stack; M0 1K = .esysmem / spare.
 */

MEMORY
{
PAGE 0 :
   BEGINH0    : origin = 0x3F8000, length = 0x000002   /* boot-to-H0 entry */
   PRAMH0     : origin = 0x3F8002, length = 0x001FFE
   RAML0      : origin = 0x008000, length = 0x001000
   CSM_PWL    : origin = 0x3F7FF8, length = 0x000008   /* CsmPwlFile (F2812_headers.cmd) */
   IQTABLES   : origin = 0x3FF000, length = 0x000B50
   RESET      : origin = 0x3FFFC0, length = 0x000002

PAGE 1 :
   RAMM0      : origin = 0x000000, length = 0x000400
   RAMM1      : origin = 0x000400, length = 0x000400
   RAML1      : origin = 0x009000, length = 0x001000
}

SECTIONS
{
   codestart        : > BEGINH0,    PAGE = 0
   ramfuncs         : { *(ramfuncs) *(.TI.ramfunc) *(IQmath) }
                      LOAD = RAML0, RUN = RAML0,
                      LOAD_START(_RamfuncsLoadStart),
                      LOAD_END(_RamfuncsLoadEnd),
                      RUN_START(_RamfuncsRunStart),
                      PAGE = 0
   .text            : > PRAMH0,     PAGE = 0
   .cinit           : > PRAMH0,     PAGE = 0
   .pinit           : > PRAMH0,     PAGE = 0
   .switch          : > PRAMH0,     PAGE = 0
   .econst          : > PRAMH0,     PAGE = 0
   IQmathTables     : > IQTABLES,   PAGE = 0, TYPE = NOLOAD
   .reset           : > RESET,      PAGE = 0, TYPE = DSECT

   .stack           : > RAMM1,      PAGE = 1
   .ebss            : > RAML1,      PAGE = 1
   dlog             : > RAML1,      PAGE = 1
   .esysmem         : > RAMM0,      PAGE = 1
}
