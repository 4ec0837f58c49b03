/* Shim (see DSP281x_Device.h): ADC registers, SPRU060 / DSP281x_Adc.h names. */
#ifndef DSP281x_ADC_H
#define DSP281x_ADC_H

struct ADCTRL1_BITS {
    Uint16 rsvd1:4;      /* 3:0 */
    Uint16 SEQ_CASC:1;   /* 4 */
    Uint16 SEQ_OVRD:1;   /* 5 */
    Uint16 CONT_RUN:1;   /* 6 */
    Uint16 CPS:1;        /* 7 */
    Uint16 ACQ_PS:4;     /* 11:8 */
    Uint16 SUSMOD:2;     /* 13:12 */
    Uint16 RESET:1;      /* 14 */
    Uint16 rsvd2:1;      /* 15 */
};
union ADCTRL1_REG { Uint16 all; struct ADCTRL1_BITS bit; };

struct ADCTRL2_BITS {
    Uint16 EVB_SOC_SEQ2:1; /* 0 */
    Uint16 rsvd1:1;        /* 1 */
    Uint16 INT_MOD_SEQ2:1; /* 2 */
    Uint16 INT_ENA_SEQ2:1; /* 3 */
    Uint16 rsvd2:1;        /* 4 */
    Uint16 SOC_SEQ2:1;     /* 5 */
    Uint16 RST_SEQ2:1;     /* 6 */
    Uint16 EXT_SOC_SEQ1:1; /* 7 */
    Uint16 EVA_SOC_SEQ1:1; /* 8 */
    Uint16 rsvd3:1;        /* 9 */
    Uint16 INT_MOD_SEQ1:1; /* 10 */
    Uint16 INT_ENA_SEQ1:1; /* 11 */
    Uint16 rsvd4:1;        /* 12 */
    Uint16 SOC_SEQ1:1;     /* 13 */
    Uint16 RST_SEQ1:1;     /* 14 */
    Uint16 EVB_SOC_SEQ:1;  /* 15 */
};
union ADCTRL2_REG { Uint16 all; struct ADCTRL2_BITS bit; };

struct ADCASEQSR_BITS {
    Uint16 SEQ1_STATE:4; Uint16 SEQ2_STATE:3; Uint16 rsvd1:1;
    Uint16 SEQ_CNTR:4; Uint16 rsvd2:4;
};
union ADCASEQSR_REG { Uint16 all; struct ADCASEQSR_BITS bit; };

struct ADCMAXCONV_BITS { Uint16 MAX_CONV1:4; Uint16 MAX_CONV2:3; Uint16 rsvd1:9; };
union ADCMAXCONV_REG { Uint16 all; struct ADCMAXCONV_BITS bit; };

struct ADCCHSELSEQ1_BITS { Uint16 CONV00:4; Uint16 CONV01:4; Uint16 CONV02:4; Uint16 CONV03:4; };
union ADCCHSELSEQ1_REG { Uint16 all; struct ADCCHSELSEQ1_BITS bit; };
struct ADCCHSELSEQ2_BITS { Uint16 CONV04:4; Uint16 CONV05:4; Uint16 CONV06:4; Uint16 CONV07:4; };
union ADCCHSELSEQ2_REG { Uint16 all; struct ADCCHSELSEQ2_BITS bit; };
struct ADCCHSELSEQ3_BITS { Uint16 CONV08:4; Uint16 CONV09:4; Uint16 CONV10:4; Uint16 CONV11:4; };
union ADCCHSELSEQ3_REG { Uint16 all; struct ADCCHSELSEQ3_BITS bit; };
struct ADCCHSELSEQ4_BITS { Uint16 CONV12:4; Uint16 CONV13:4; Uint16 CONV14:4; Uint16 CONV15:4; };
union ADCCHSELSEQ4_REG { Uint16 all; struct ADCCHSELSEQ4_BITS bit; };

struct ADCTRL3_BITS {
    Uint16 SMODE_SEL:1;  /* 0 */
    Uint16 ADCCLKPS:4;   /* 4:1 */
    Uint16 ADCPWDN:1;    /* 5 */
    Uint16 ADCBGRFDN:2;  /* 7:6 */
    Uint16 rsvd1:8;
};
union ADCTRL3_REG { Uint16 all; struct ADCTRL3_BITS bit; };

struct ADCST_BITS {
    Uint16 INT_SEQ1:1; Uint16 INT_SEQ2:1; Uint16 SEQ1_BSY:1; Uint16 SEQ2_BSY:1;
    Uint16 INT_SEQ1_CLR:1; Uint16 INT_SEQ2_CLR:1; Uint16 EOS_BUF1:1; Uint16 EOS_BUF2:1;
    Uint16 rsvd1:8;
};
union ADCST_REG { Uint16 all; struct ADCST_BITS bit; };

struct ADC_REGS {
    union ADCTRL1_REG ADCTRL1;           /* 0x7100 */
    union ADCTRL2_REG ADCTRL2;
    union ADCMAXCONV_REG ADCMAXCONV;
    union ADCCHSELSEQ1_REG ADCCHSELSEQ1;
    union ADCCHSELSEQ2_REG ADCCHSELSEQ2;
    union ADCCHSELSEQ3_REG ADCCHSELSEQ3;
    union ADCCHSELSEQ4_REG ADCCHSELSEQ4;
    union ADCASEQSR_REG ADCASEQSR;
    Uint16 ADCRESULT0;  Uint16 ADCRESULT1;  Uint16 ADCRESULT2;  Uint16 ADCRESULT3;
    Uint16 ADCRESULT4;  Uint16 ADCRESULT5;  Uint16 ADCRESULT6;  Uint16 ADCRESULT7;
    Uint16 ADCRESULT8;  Uint16 ADCRESULT9;  Uint16 ADCRESULT10; Uint16 ADCRESULT11;
    Uint16 ADCRESULT12; Uint16 ADCRESULT13; Uint16 ADCRESULT14; Uint16 ADCRESULT15;
    union ADCTRL3_REG ADCTRL3;           /* 0x7118 */
    union ADCST_REG ADCST;               /* 0x7119 */
};

extern volatile struct ADC_REGS AdcRegs;

#endif /* DSP281x_ADC_H */
