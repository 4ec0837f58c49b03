/* Fixture of CTest target_ram_fit_ramfuncs_can_fail: F2812_flash.cmd with the
 * code part of L0+L1 (RAML0L1, ramfuncs: the control ISR's path) cut to 3K
 * words, so that ramfuncs (about 2 800 words) exceeds 70 % of it;
 * tools/bench_size.py --check ramfuncs must say so.  Not a linker file of
 * the build. */
MEMORY
{
PAGE 0 :   /* program */
   RAML0L1    : origin = 0x008000, length = 0x000C00   /* cut to 3K: ramfuncs RUN */
   RAMH0      : origin = 0x3F8000, length = 0x001A80   /* first 6.625K of H0: ramfuncs_slow RUN */
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
   RAML0L1_DATA : origin = 0x009040, length = 0x000FC0 /* rest of L1: .ebss */
   RAMH0_DATA : origin = 0x3F9A80, length = 0x000580   /* last 1.375K of H0: dlog, bgdata */
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
   /* the slow set (reached only through drive_slow_task) and TI's IQmath
    * (called from both sets) run from H0, zero wait states as L0/L1 */
   ramfuncs_slow    : {
                         *(ramfuncs_slow)
#include "F2812_isr_slow.cmd"
                      }
                      LOAD = FLASHC, RUN = RAMH0,
                      LOAD_START(_RamfuncsSlowLoadStart),
                      LOAD_END(_RamfuncsSlowLoadEnd),
                      RUN_START(_RamfuncsSlowRunStart),
                      PAGE = 0
   IQmath           : >> FLASHJ | FLASHI | FLASHH | FLASHG,  PAGE = 0
   .text            : >> FLASHJ | FLASHI | FLASHH | FLASHG,  PAGE = 0
   .cinit           : > FLASHE,     PAGE = 0
   .pinit           : > FLASHE,     PAGE = 0
   .switch          : > FLASHE,     PAGE = 0
   .econst          : > FLASHF,     PAGE = 0
   IQmathTables     : > IQTABLES,   PAGE = 0, TYPE = NOLOAD
   .reset           : > RESET,      PAGE = 0, TYPE = DSECT   /* boot ROM supplies it */

   .stack           : > RAMM0M1,    PAGE = 1
   bgdata           : > RAMH0_DATA, PAGE = 1
   .ebss            : > RAML0L1_DATA, PAGE = 1
   dlog             : > RAMH0_DATA, PAGE = 1
   .esysmem         : > RAMM0M1,    PAGE = 1
}
