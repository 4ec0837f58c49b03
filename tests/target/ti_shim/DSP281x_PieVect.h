/* Shim (see DSP281x_Device.h): the PIE vector table, SPRU078 table
 * "PIE vector table" / DSP281x_PieVect.h names (0x000D00..0x000DFF,
 * 128 32-bit vectors). */
#ifndef DSP281x_PIE_VECT_H
#define DSP281x_PIE_VECT_H

typedef interrupt void (*PINT)(void);

struct PIE_VECT_TABLE {
    PINT PIE1_RESERVED, PIE2_RESERVED, PIE3_RESERVED, PIE4_RESERVED, PIE5_RESERVED, PIE6_RESERVED, PIE7_RESERVED, PIE8_RESERVED, PIE9_RESERVED, PIE10_RESERVED, PIE11_RESERVED, PIE12_RESERVED, PIE13_RESERVED;
    PINT XINT13, TINT2, DATALOG, RTOSINT, EMUINT, XNMI, ILLEGAL;
    PINT USER1, USER2, USER3, USER4, USER5, USER6, USER7, USER8, USER9, USER10, USER11, USER12;
    PINT PDPINTA, PDPINTB, rsvd1_3, XINT1, XINT2, ADCINT, TINT0, WAKEINT; /* group 1 */
    PINT CMP1INT, CMP2INT, CMP3INT, T1PINT, T1CINT, T1UFINT, T1OFINT, rsvd2_8; /* group 2 */
    PINT T2PINT, T2CINT, T2UFINT, T2OFINT, CAPINT1, CAPINT2, CAPINT3, rsvd3_8; /* group 3 */
    PINT CMP4INT, CMP5INT, CMP6INT, T3PINT, T3CINT, T3UFINT, T3OFINT, rsvd4_8; /* group 4 */
    PINT T4PINT, T4CINT, T4UFINT, T4OFINT, CAPINT4, CAPINT5, CAPINT6, rsvd5_8; /* group 5 */
    PINT SPIRXINTA, SPITXINTA, rsvd6_3, rsvd6_4, MRINTA, MXINTA, rsvd6_7, rsvd6_8; /* group 6 */
    PINT rsvd7_1, rsvd7_2, rsvd7_3, rsvd7_4, rsvd7_5, rsvd7_6, rsvd7_7, rsvd7_8; /* group 7 */
    PINT rsvd8_1, rsvd8_2, rsvd8_3, rsvd8_4, rsvd8_5, rsvd8_6, rsvd8_7, rsvd8_8; /* group 8 */
    PINT RXAINT, TXAINT, RXBINT, TXBINT, ECAN0INTA, ECAN1INTA, rsvd9_7, rsvd9_8; /* group 9 */
    PINT rsvd10_1, rsvd10_2, rsvd10_3, rsvd10_4, rsvd10_5, rsvd10_6, rsvd10_7, rsvd10_8; /* group 10 */
    PINT rsvd11_1, rsvd11_2, rsvd11_3, rsvd11_4, rsvd11_5, rsvd11_6, rsvd11_7, rsvd11_8; /* group 11 */
    PINT rsvd12_1, rsvd12_2, rsvd12_3, rsvd12_4, rsvd12_5, rsvd12_6, rsvd12_7, rsvd12_8; /* group 12 */
};

extern struct PIE_VECT_TABLE PieVectTable;

#endif /* DSP281x_PIE_VECT_H */
