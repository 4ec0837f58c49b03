/* Shim (see DSP281x_Device.h): Event Manager A registers, SPRU065 /
 * DSP281x_Ev.h (v1.00) names.  EV-B is not used by the firmware. */
#ifndef DSP281x_EV_H
#define DSP281x_EV_H

struct GPTCONA_BITS {
    Uint16 T1PIN:2;    /* 1:0 */
    Uint16 T2PIN:2;    /* 3:2 */
    Uint16 T1CMPOE:1;  /* 4 */
    Uint16 T2CMPOE:1;  /* 5 */
    Uint16 TCMPOE:1;   /* 6 */
    Uint16 T1TOADC:2;  /* 8:7 */
    Uint16 T2TOADC:2;  /* 10:9 */
    Uint16 T1CTRIPE:1; /* 11 */
    Uint16 T2CTRIPE:1; /* 12 */
    Uint16 T1STAT:1;   /* 13 */
    Uint16 T2STAT:1;   /* 14 */
    Uint16 rsvd:1;     /* 15 */
};
union GPTCONA_REG { Uint16 all; struct GPTCONA_BITS bit; };

struct T1CON_BITS {
    Uint16 rsvd1:1;    /* 0 */
    Uint16 TECMPR:1;   /* 1 */
    Uint16 TCLD10:2;   /* 3:2 */
    Uint16 TCLKS10:2;  /* 5:4 */
    Uint16 TENABLE:1;  /* 6 */
    Uint16 rsvd2:1;    /* 7 */
    Uint16 TPS:3;      /* 10:8 */
    Uint16 TMODE:2;    /* 12:11 */
    Uint16 rsvd:1;     /* 13 */
    Uint16 FREE:1;     /* 14 */
    Uint16 SOFT:1;     /* 15 */
};
union T1CON_REG { Uint16 all; struct T1CON_BITS bit; };

struct T2CON_BITS {
    Uint16 SET1PR:1;   /* 0 */
    Uint16 TECMPR:1;   /* 1 */
    Uint16 TCLD10:2;   /* 3:2 */
    Uint16 TCLKS10:2;  /* 5:4 */
    Uint16 TENABLE:1;  /* 6 */
    Uint16 T2SWT1:1;   /* 7 */
    Uint16 TPS:3;      /* 10:8 */
    Uint16 TMODE:2;    /* 12:11 */
    Uint16 rsvd:1;     /* 13 */
    Uint16 FREE:1;     /* 14 */
    Uint16 SOFT:1;     /* 15 */
};
union T2CON_REG { Uint16 all; struct T2CON_BITS bit; };

struct EXTCONA_BITS {
    Uint16 INDCOE:1; Uint16 QEPIQUAL:1; Uint16 QEPIE:1; Uint16 EVSOCE:1; Uint16 rsvd:12;
};
union EXTCONA_REG { Uint16 all; struct EXTCONA_BITS bit; };

struct COMCONA_BITS {
    Uint16 C1TRIPE:1;       /* 0 */
    Uint16 C2TRIPE:1;       /* 1 */
    Uint16 C3TRIPE:1;       /* 2 */
    Uint16 rsvd:2;          /* 4:3 */
    Uint16 FCMP1OE:1;       /* 5 */
    Uint16 FCMP2OE:1;       /* 6 */
    Uint16 FCMP3OE:1;       /* 7 */
    Uint16 PDPINTASTATUS:1; /* 8 */
    Uint16 FCOMPOE:1;       /* 9 */
    Uint16 ACTRLD:2;        /* 11:10 */
    Uint16 SVENABLE:1;      /* 12 */
    Uint16 CLD:2;           /* 14:13 */
    Uint16 CENABLE:1;       /* 15 */
};
union COMCONA_REG { Uint16 all; struct COMCONA_BITS bit; };

struct ACTRA_BITS {
    Uint16 CMP1ACT:2; Uint16 CMP2ACT:2; Uint16 CMP3ACT:2; Uint16 CMP4ACT:2;
    Uint16 CMP5ACT:2; Uint16 CMP6ACT:2; Uint16 D:3; Uint16 SVRDIR:1;
};
union ACTRA_REG { Uint16 all; struct ACTRA_BITS bit; };

struct DBTCON_BITS {
    Uint16 rsvd1:2;  /* 1:0 */
    Uint16 DBTPS:3;  /* 4:2 */
    Uint16 EDBT1:1;  /* 5 */
    Uint16 EDBT2:1;  /* 6 */
    Uint16 EDBT3:1;  /* 7 */
    Uint16 DBT:4;    /* 11:8 */
    Uint16 rsvd2:4;  /* 15:12 */
};
union DBTCON_REG { Uint16 all; struct DBTCON_BITS bit; };

struct CAPCONA_BITS {
    Uint16 rsvd1:2;     /* 1:0 */
    Uint16 CAP3EDGE:2;  /* 3:2 */
    Uint16 CAP2EDGE:2;  /* 5:4 */
    Uint16 CAP1EDGE:2;  /* 7:6 */
    Uint16 CAP3TOADC:1; /* 8 */
    Uint16 CAP12TSEL:1; /* 9 */
    Uint16 CAP3TSEL:1;  /* 10 */
    Uint16 rsvd2:1;     /* 11 */
    Uint16 CAP3EN:1;    /* 12 */
    Uint16 CAP12EN:2;   /* 14:13 */
    Uint16 CAPRES:1;    /* 15 */
};
union CAPCONA_REG { Uint16 all; struct CAPCONA_BITS bit; };

struct EVAIMRA_BITS {
    Uint16 PDPINTA:1; Uint16 CMP1INT:1; Uint16 CMP2INT:1; Uint16 CMP3INT:1;
    Uint16 rsvd1:3; Uint16 T1PINT:1; Uint16 T1CINT:1; Uint16 T1UFINT:1;
    Uint16 T1OFINT:1; Uint16 rsvd2:5;
};
union EVAIMRA_REG { Uint16 all; struct EVAIMRA_BITS bit; };
struct EVAIMRB_BITS { Uint16 T2PINT:1; Uint16 T2CINT:1; Uint16 T2UFINT:1; Uint16 T2OFINT:1; Uint16 rsvd1:12; };
union EVAIMRB_REG { Uint16 all; struct EVAIMRB_BITS bit; };
struct EVAIMRC_BITS { Uint16 CAP1INT:1; Uint16 CAP2INT:1; Uint16 CAP3INT:1; Uint16 rsvd1:13; };
union EVAIMRC_REG { Uint16 all; struct EVAIMRC_BITS bit; };
struct EVAIFRA_BITS {
    Uint16 PDPINTA:1; Uint16 CMP1INT:1; Uint16 CMP2INT:1; Uint16 CMP3INT:1;
    Uint16 rsvd1:3; Uint16 T1PINT:1; Uint16 T1CINT:1; Uint16 T1UFINT:1;
    Uint16 T1OFINT:1; Uint16 rsvd2:5;
};
/* TI's v1.00 header declares EVAIFRA's `bit` member with the EVAIMRA_BITS
 * struct (same field names); the shim uses the flag struct, same names. */
union EVAIFRA_REG { Uint16 all; struct EVAIFRA_BITS bit; };
struct EVAIFRB_BITS { Uint16 T2PINT:1; Uint16 T2CINT:1; Uint16 T2UFINT:1; Uint16 T2OFINT:1; Uint16 rsvd1:12; };
union EVAIFRB_REG { Uint16 all; struct EVAIFRB_BITS bit; };
struct EVAIFRC_BITS { Uint16 CAP1INT:1; Uint16 CAP2INT:1; Uint16 CAP3INT:1; Uint16 rsvd1:13; };
union EVAIFRC_REG { Uint16 all; struct EVAIFRC_BITS bit; };

struct EVA_REGS {
    union GPTCONA_REG GPTCONA;   /* 0x7400 */
    Uint16 T1CNT;                /* 0x7401 */
    Uint16 T1CMPR;               /* 0x7402 */
    Uint16 T1PR;                 /* 0x7403 */
    union T1CON_REG T1CON;       /* 0x7404 */
    Uint16 T2CNT;                /* 0x7405 */
    Uint16 T2CMPR;               /* 0x7406 */
    Uint16 T2PR;                 /* 0x7407 */
    union T2CON_REG T2CON;       /* 0x7408 */
    union EXTCONA_REG EXTCONA;   /* 0x7409 */
    Uint16 rsvd1[7];
    union COMCONA_REG COMCONA;   /* 0x7411 */
    Uint16 rsvd2;
    union ACTRA_REG ACTRA;       /* 0x7413 */
    Uint16 rsvd3;
    union DBTCON_REG DBTCONA;    /* 0x7415 */
    Uint16 rsvd4;
    Uint16 CMPR1;                /* 0x7417 */
    Uint16 CMPR2;                /* 0x7418 */
    Uint16 CMPR3;                /* 0x7419 */
    Uint16 rsvd5[6];
    union CAPCONA_REG CAPCONA;   /* 0x7420 */
    Uint16 rsvd6;
    Uint16 CAPFIFOA;             /* 0x7422 (bit fields not used) */
    Uint16 CAP1FIFO;
    Uint16 CAP2FIFO;
    Uint16 CAP3FIFO;
    Uint16 rsvd7;
    Uint16 CAP1FBOT;
    Uint16 CAP2FBOT;
    Uint16 CAP3FBOT;
    Uint16 rsvd8[2];
    union EVAIMRA_REG EVAIMRA;   /* 0x742C */
    union EVAIMRB_REG EVAIMRB;
    union EVAIMRC_REG EVAIMRC;
    union EVAIFRA_REG EVAIFRA;   /* 0x742F */
    union EVAIFRB_REG EVAIFRB;
    union EVAIFRC_REG EVAIFRC;
};

extern volatile struct EVA_REGS EvaRegs;

#endif /* DSP281x_EV_H */
