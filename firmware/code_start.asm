; code_start.asm: the branch at BEGIN (0x3F7FF6, the last two words before
; the CSM password) that the boot ROM jumps to in "boot to flash" mode
; (SPRU095 boot ROM guide).  It goes straight to the C run-time start-up.
; The watchdog is still running here; _c_int00's initialisation of .ebss
; from .cinit is short for this image (<< the 4.4 ms watchdog period at
; reset), and main() disables the watchdog first thing.

        .ref    _c_int00
        .sect   "codestart"
code_start:
        LB      _c_int00        ; long branch: 2 words, exactly BEGIN's size
        .end
