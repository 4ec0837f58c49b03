/* Shim (see DSP281x_Device.h): system control, CSM and flash registers,
 * SPRU078 (system control and interrupts) / DSP281x_SysCtrl.h names.
 * SCSR, WDKEY and WDCR have no bit fields in TI's header on purpose (a
 * read-modify-write of SCSR clears WDOVERRIDE; WDCR needs WDCHK = 101 on
 * every write), so they are plain Uint16 here too. */
#ifndef DSP281x_SYS_CTRL_H
#define DSP281x_SYS_CTRL_H

struct HISPCP_BITS { Uint16 HSPCLK:3; Uint16 rsvd1:13; };
union HISPCP_REG { Uint16 all; struct HISPCP_BITS bit; };
struct LOSPCP_BITS { Uint16 LSPCLK:3; Uint16 rsvd1:13; };
union LOSPCP_REG { Uint16 all; struct LOSPCP_BITS bit; };

struct PCLKCR_BITS {
    Uint16 EVAENCLK:1;   /* 0 */
    Uint16 EVBENCLK:1;   /* 1 */
    Uint16 rsvd1:1;      /* 2 */
    Uint16 ADCENCLK:1;   /* 3 */
    Uint16 rsvd2:4;      /* 7:4 */
    Uint16 SPIENCLK:1;   /* 8 */
    Uint16 rsvd3:1;      /* 9 */
    Uint16 SCIAENCLK:1;  /* 10 */
    Uint16 SCIBENCLK:1;  /* 11 */
    Uint16 MCBSPENCLK:1; /* 12 */
    Uint16 rsvd4:1;      /* 13 */
    Uint16 ECANENCLK:1;  /* 14 */
    Uint16 rsvd5:1;      /* 15 */
};
union PCLKCR_REG { Uint16 all; struct PCLKCR_BITS bit; };

struct PLLCR_BITS { Uint16 DIV:4; Uint16 rsvd1:12; };
union PLLCR_REG { Uint16 all; struct PLLCR_BITS bit; };

struct LPMCR0_BITS { Uint16 LPM:2; Uint16 QUALSTDBY:6; Uint16 rsvd1:8; };
union LPMCR0_REG { Uint16 all; struct LPMCR0_BITS bit; };
union LPMCR1_REG { Uint16 all; };

struct SYS_CTRL_REGS {
    Uint16 rsvd1[10];          /* 0x7010 */
    union HISPCP_REG HISPCP;   /* 0x701A */
    union LOSPCP_REG LOSPCP;   /* 0x701B */
    union PCLKCR_REG PCLKCR;   /* 0x701C */
    Uint16 rsvd2;
    union LPMCR0_REG LPMCR0;   /* 0x701E */
    union LPMCR1_REG LPMCR1;   /* 0x701F */
    Uint16 rsvd3;
    union PLLCR_REG PLLCR;     /* 0x7021 */
    Uint16 SCSR;               /* 0x7022 */
    Uint16 WDCNTR;             /* 0x7023 */
    Uint16 rsvd4;
    Uint16 WDKEY;              /* 0x7025 */
    Uint16 rsvd5[3];
    Uint16 WDCR;               /* 0x7029 */
    Uint16 rsvd6[6];
};

/* Flash registers (SPRU078 / DSP281x_SysCtrl.h) */
struct FOPT_BITS { Uint16 ENPIPE:1; Uint16 rsvd:15; };
union FOPT_REG { Uint16 all; struct FOPT_BITS bit; };
struct FPWR_BITS { Uint16 PWR:2; Uint16 rsvd:14; };
union FPWR_REG { Uint16 all; struct FPWR_BITS bit; };
struct FSTATUS_BITS {
    Uint16 PWRS:2; Uint16 STDBYWAITS:1; Uint16 ACTIVEWAITS:1; Uint16 rsvd1:4;
    Uint16 V3STAT:1; Uint16 rsvd2:7;
};
union FSTATUS_REG { Uint16 all; struct FSTATUS_BITS bit; };
struct FSTDBYWAIT_BITS { Uint16 STDBYWAIT:8; Uint16 rsvd:8; };
union FSTDBYWAIT_REG { Uint16 all; struct FSTDBYWAIT_BITS bit; };
struct FACTIVEWAIT_BITS { Uint16 ACTIVEWAIT:8; Uint16 rsvd:8; };
union FACTIVEWAIT_REG { Uint16 all; struct FACTIVEWAIT_BITS bit; };
struct FBANKWAIT_BITS { Uint16 RANDWAIT:4; Uint16 rsvd1:4; Uint16 PAGEWAIT:4; Uint16 rsvd2:4; };
union FBANKWAIT_REG { Uint16 all; struct FBANKWAIT_BITS bit; };
struct FOTPWAIT_BITS { Uint16 OTPWAIT:5; Uint16 rsvd:11; };
union FOTPWAIT_REG { Uint16 all; struct FOTPWAIT_BITS bit; };

struct FLASH_REGS {
    union FOPT_REG FOPT;               /* 0x0A80 */
    Uint16 rsvd1;
    union FPWR_REG FPWR;
    union FSTATUS_REG FSTATUS;
    union FSTDBYWAIT_REG FSTDBYWAIT;
    union FACTIVEWAIT_REG FACTIVEWAIT;
    union FBANKWAIT_REG FBANKWAIT;
    union FOTPWAIT_REG FOTPWAIT;
};

extern volatile struct SYS_CTRL_REGS SysCtrlRegs;
extern volatile struct FLASH_REGS FlashRegs;

#endif /* DSP281x_SYS_CTRL_H */
