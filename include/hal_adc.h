/**
 * @file hal_adc.h
 * HAL seam: the ADC results of one control period.
 *
 * Implemented by firmware/hal_adc_f2812.c on the target (ADCRESULTn of the
 * sequence started by EV-A T1 underflow) and by host_sim/hal/ on the host.
 * Chosen at link time; the core never touches a register.
 */
#ifndef HAL_ADC_H
#define HAL_ADC_H

#include <stdint.h>

/** Raw results as the F2812 leaves them in ADCRESULTn: a 12-bit conversion of
 *  0..3 V, left-justified in 16 bits (bits 15..4; bits 3..0 read 0). */
typedef struct {
    uint16_t ia_raw;   /* phase-a Hall current sensor (ADCINA0) */
    uint16_t ib_raw;   /* phase-b Hall current sensor (ADCINB0) */
    uint16_t vdc_raw;  /* DC-bus voltage divider        (ADCINA1) */
} hal_adc_sample_t;

/** Read the results of the conversion started at this period's start. */
void hal_adc_read(hal_adc_sample_t *s);

#endif /* HAL_ADC_H */
