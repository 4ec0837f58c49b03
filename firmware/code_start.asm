; code_start.asm: the branch at BEGIN (0x3F7FF6, the last two words before
; the CSM password) that the boot ROM jumps to in "boot to flash" mode
; (SPRU095 boot ROM guide).  It disables the watchdog first (as TI's
; DSP281x_CodeStartBranch.asm with WD_DISABLE = 1), then goes to the C
; run-time start-up: _c_int00 initialises .ebss from .cinit, and with the
; watchdog running (4.4 ms at reset) a larger image would reset the device
; before main() could disable it.  main() keeps it off during the start-up
; and enables it before the background loop (sysctrl.c).

WDCR    .set    0x7029          ; watchdog control register (SPRU078)
WD_OFF  .set    0x0068          ; WDDIS = 1, WDCHK = 101 (any other WDCHK resets)

        .ref    _c_int00
        .sect   "codestart"
code_start:
        LB      wd_disable      ; long branch: 2 words, exactly BEGIN's size

        .text
wd_disable:
        SETC    OBJMODE         ; C28x object mode (the boot ROM leaves it set)
        EALLOW                  ; WDCR is EALLOW-protected
        MOVZ    DP, #WDCR >> 6  ; data page of WDCR
        MOV     @WDCR, #WD_OFF
        EDIS
        LB      _c_int00
        .end
