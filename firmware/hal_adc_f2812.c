/**
 * @file hal_adc_f2812.c
 * hal_adc.h on the F2812 ADC (SPRU060).
 *
 * Why the control ISR is the ADC end-of-sequence interrupt and not the T1
 * underflow interrupt: the T1 underflow starts the conversions (EV-A SOC),
 * so at that instant the results are not there yet (3 conversions take
 * ~1.5 us); a T1UFINT ISR would have to busy-wait on SEQ1_BSY or read the
 * previous period's samples.  ADCINT fires when the three results are in
 * ADCRESULT0..2, so the ISR reads fresh samples without waiting, at a fixed
 * delay after the period start (the sampling instant is still the underflow,
 * the centre of the zero vector, where the currents equal their period
 * average).
 *
 * Clocks: HSPCLK 150 MHz, ADCCLKPS = 3 -> 25 MHz, CPS = 1 -> ADCCLK 12.5 MHz
 * (under the 25 MHz maximum, with the better linearity of the slower clock);
 * ACQ_PS = 3 -> a 4-ADCCLK (320 ns) sample window.  That window settles the
 * sample capacitor to 1/2 LSB (9 time constants) only from a source of at
 * most about 2.9 kohm, or from an RC at the pin whose capacitor is at least
 * 2^13 times the sample capacitor's, 13.4 nF (charge sharing); the board notes of
 * docs/board.md give the ADC's input model (SPRS174) and the arithmetic.  A
 * longer window would move the current's sampling instant further from the
 * period's start, the centre of the zero vector.
 *
 * Simultaneous sampling (SMODE_SEL = 1): i_a (ADCINA0) and i_b (ADCINB0) are
 * held by the two sample-and-hold units at the same instant, so the Clarke
 * transform and the voltage reconstruction see one current vector, not two
 * phases taken ~0.4 us apart (at high modulation the zero vector around the
 * sampling instant is short, and the ripple between the two would enter the
 * vector as an error).  Pair 0 -> RESULT0 (A0), RESULT1 (B0); pair 1 ->
 * RESULT2 (A1: the bus), RESULT3 (B1, not read).  A pair is always sampled
 * whole, so B1 is converted too: the board ties ADCINB1 to analog ground
 * (docs/board.md).  Left open it would float, and the B sample-and-hold,
 * which converts B1 just before the next period's ib, would carry an
 * undefined charge into ib's sample.
 *
 * Re-arm at the top of the ISR (hal_adc_read): the sequencer is reset and
 * INT_SEQ1 cleared right after the results are read, the PIE group
 * acknowledged and the T1 underflow flag cleared.  An ISR that overruns its
 * period then still has the next conversion land in RESULT0-3 (with the
 * reset at the end, the next SOC continued the cascaded sequence into
 * RESULT4-7) and its interrupt pending; the flag lets hal_isr_overrun see
 * the overrun.
 */
#include "DSP281x_Device.h"
#include "adc_f2812.h"
#include "hal_adc.h"

#pragma CODE_SECTION(hal_adc_read, "ramfuncs")

/* ADCTRL3.ADCBGRFDN = 11 (band gap and reference on), then ADCPWDN = 1; the
 * SPRU060 power-up delays: 7 ms after the reference, 20 us after the rest. */
#define ADC_REF_DELAY_LOOPS   350000UL   /* >= 7 ms at 150 MHz, >= 3 cycles/loop */
#define ADC_PWR_DELAY_LOOPS   1000UL     /* >= 20 us */

/* ADCCHSELSEQ code in simultaneous mode: pair n = ADCINAn with ADCINBn */
#define ADC_PAIR_0 0x0u   /* ia (A0), ib (B0) */
#define ADC_PAIR_1 0x1u   /* vdc (A1), B1 (tied to analog ground, not read) */
/* the ADC module reset (ADCTRL1.RESET) takes effect within 2 ADCCLK; the
 * register writes after it must wait (SPRU060) */
#define ADC_RESET_LOOPS 64UL
/* EVAIFRA: T1 underflow flag, write 1 to clear (the other flags: written 0,
 * untouched; a read-modify-write of .bit would also clear a pending PDPINTA) */
#define EVAIFRA_T1UFINT 0x0200u

static void adc_delay(uint32_t loops)
{
    volatile uint32_t n;
    for (n = 0u; n < loops; n++) {
        /* power-up wait (start-up only) */
    }
}

void adc_f2812_init(void)
{
    /* the whole module to its reset state first (a debugger reload leaves
     * it running), as TI's InitAdc does */
    AdcRegs.ADCTRL1.bit.RESET = 1u;
    adc_delay(ADC_RESET_LOOPS);
    AdcRegs.ADCTRL3.bit.ADCBGRFDN = 3u;
    adc_delay(ADC_REF_DELAY_LOOPS);
    AdcRegs.ADCTRL3.bit.ADCPWDN = 1u;
    adc_delay(ADC_PWR_DELAY_LOOPS);

    AdcRegs.ADCTRL3.bit.ADCCLKPS = 3u;
    AdcRegs.ADCTRL3.bit.SMODE_SEL = 1u;    /* simultaneous: ia and ib at one instant */
    AdcRegs.ADCTRL1.bit.CPS = 1u;
    AdcRegs.ADCTRL1.bit.ACQ_PS = 3u;
    AdcRegs.ADCTRL1.bit.SEQ_CASC = 1u;     /* one 16-state sequencer */
    AdcRegs.ADCTRL1.bit.CONT_RUN = 0u;     /* start-stop: one sequence per SOC */
    AdcRegs.ADCTRL1.bit.SUSMOD = 0u;

    AdcRegs.ADCMAXCONV.bit.MAX_CONV1 = 1u; /* two simultaneous pairs */
    AdcRegs.ADCCHSELSEQ1.bit.CONV00 = ADC_PAIR_0;  /* ia -> ADCRESULT0, ib -> ADCRESULT1 */
    AdcRegs.ADCCHSELSEQ1.bit.CONV01 = ADC_PAIR_1;  /* vdc -> ADCRESULT2 */

    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 1u;
    AdcRegs.ADCST.bit.INT_SEQ1_CLR = 1u;
    AdcRegs.ADCTRL2.bit.EVA_SOC_SEQ1 = 1u; /* EV-A (T1 underflow) starts it */
    AdcRegs.ADCTRL2.bit.INT_MOD_SEQ1 = 0u; /* interrupt at every sequence end */
    AdcRegs.ADCTRL2.bit.INT_ENA_SEQ1 = 1u;
}

void hal_adc_read(hal_adc_sample_t *s)
{
    /* ADCRESULTn are left-justified 12-bit (bits 15..4), as hal_adc.h
     * specifies: passed through unchanged */
    s->ia_raw = AdcRegs.ADCRESULT0;
    s->ib_raw = AdcRegs.ADCRESULT1;
    s->vdc_raw = AdcRegs.ADCRESULT2;
    /* re-arm at once (file comment): the next SOC starts at CONV00, this
     * period's interrupt is acknowledged, the overrun flag armed */
    AdcRegs.ADCTRL2.bit.RST_SEQ1 = 1u;
    AdcRegs.ADCST.bit.INT_SEQ1_CLR = 1u;
    PieCtrlRegs.PIEACK.all = PIEACK_GROUP1;
    EvaRegs.EVAIFRA.all = EVAIFRA_T1UFINT;
}
