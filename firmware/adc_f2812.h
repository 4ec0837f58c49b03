/**
 * @file adc_f2812.h
 * ADC set-up (the HAL seam itself is hal_adc.h).
 */
#ifndef ADC_F2812_H
#define ADC_F2812_H

/** Reset and power up the ADC; cascaded sequencer in simultaneous mode:
 *  CONV00 = pair 0 (ADCINA0 = ia -> RESULT0, ADCINB0 = ib -> RESULT1),
 *  CONV01 = pair 1 (ADCINA1 = vdc -> RESULT2), started by the EV-A SOC
 *  (T1 underflow), interrupt at the end of the sequence (ADCINT, PIE 1.6).
 *  hal_adc_read re-arms the sequencer and the interrupt each period. */
void adc_f2812_init(void);

#endif /* ADC_F2812_H */
