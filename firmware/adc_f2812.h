/**
 * @file adc_f2812.h
 * ADC set-up (the HAL seam itself is hal_adc.h).
 */
#ifndef ADC_F2812_H
#define ADC_F2812_H

/** Power up the ADC, cascaded sequencer: CONV00 = ADCINA0 (ia),
 *  CONV01 = ADCINB0 (ib), CONV02 = ADCINA1 (vdc), started by the EV-A SOC
 *  (T1 underflow), interrupt at the end of the sequence (ADCINT, PIE 1.6). */
void adc_f2812_init(void);
/** End-of-sequence housekeeping in the ADC ISR: sequencer back to CONV00,
 *  INT_SEQ1 flag cleared. */
void adc_f2812_ack(void);

#endif /* ADC_F2812_H */
