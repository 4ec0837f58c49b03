/**
 * @file adc_f2812.h
 * Analog front end and the F2812 ADC (double in, ADCRESULTn out; host only).
 *
 * Signal conditioning (a linear map to the 0..3 V ADC pin, no clamping: the
 * pin clamps in the ADC):
 *   current channel  v = 1.5 V + 1.5 V * i / I_fs   (-I_fs..+I_fs -> 0..3 V,
 *                    include/hal_adc.h, drive_board_t.current_full_scale_A)
 *   DC-bus divider   v = 3.0 V * vdc / Vdc_fs       (Vdc_fs reads 3.0 V,
 *                    drive_board_t.vdc_adc_full_scale_V)
 *
 * ADC (TMS320F281x ADC reference guide, SPRU060): 12 bits over
 * ADCLO = 0 .. 3.0 V,
 *   code = 0                         for v <= 0
 *        = floor(4095 v / 3.0)       for 0 < v < 3.0 (fraction truncated)
 *        = 4095                      for v >= 3.0,
 * here with optional static errors and white noise added before the
 * truncation (code = floor(4095 v/3 (1 + gain_error) + offset_lsb +
 * noise_lsb_rms n)), then clamped to the rails 0..4095.  The result register
 * holds it left-justified: ADCRESULTn = code << 4 (bits 3..0 read 0).
 *
 * The ADC samples at the start of the control period (EV-A T1 underflow):
 * convert the plant's state at that instant (motor_model.h outputs before
 * the period is stepped).
 */
#ifndef ADC_F2812_H
#define ADC_F2812_H

#include <stdint.h>
#include "model_rng.h"

#define ADC_F2812_VREF_V 3.0
#define ADC_F2812_CODE_MAX 4095u

/* ---- conditioning ---------------------------------------------------- */

typedef struct {
    /* parameters */
    double gain_V_per_unit;  /* V at the pin per A (or per V of bus) */
    double offset_V;         /* V at the pin for a zero input */
} sig_cond_t;

typedef enum {
    SIG_COND_OK = 0,
    SIG_COND_ERR_NULL,
    SIG_COND_ERR_FULL_SCALE  /* full scale not finite and > 0 */
} sig_cond_status_t;

/** Current channel: -I_fs..+I_fs -> 0..3 V around 1.5 V. */
sig_cond_status_t sig_cond_init_current(sig_cond_t *c, double i_full_scale_A);
/** DC-bus divider: @p vdc_full_scale_V reads 3.0 V. */
sig_cond_status_t sig_cond_init_vdc(sig_cond_t *c, double vdc_full_scale_V);
/** Pin voltage for input @p x (A or V). */
double sig_cond_apply(const sig_cond_t *c, double x);

/* ---- ADC -------------------------------------------------------------- */

typedef struct {
    double gain_error;       /* relative, > -1 */
    double offset_lsb;       /* static offset, LSB */
    double noise_lsb_rms;    /* white noise, LSB rms, >= 0 */
    uint64_t seed;           /* noise stream */
} adc_f2812_params_t;

typedef enum {
    ADC_F2812_OK = 0,
    ADC_F2812_ERR_NULL,
    ADC_F2812_ERR_GAIN,      /* gain_error not finite or <= -1 */
    ADC_F2812_ERR_OFFSET,    /* offset not finite */
    ADC_F2812_ERR_NOISE      /* noise negative or not finite */
} adc_f2812_status_t;

typedef struct {
    /* parameters */
    adc_f2812_params_t p;
    /* outputs */
    uint16_t code;           /* last 12-bit code */
    uint16_t raw;            /* last ADCRESULTn (code << 4) */
    /* state */
    model_rng_t rng;
} adc_f2812_t;

/** Realistic defaults: no static error (the offset/gain are calibrated out
 *  on the real board), 1.0 LSB rms noise (the F281x ADC's ~10.5 effective
 *  bits at 12.5 MSPS), seed 2. */
void adc_f2812_params_default(adc_f2812_params_t *p);
/** Perfect quantiser (no error, no noise). */
void adc_f2812_params_ideal(adc_f2812_params_t *p);

adc_f2812_status_t adc_f2812_init(adc_f2812_t *a, const adc_f2812_params_t *p);

/** Convert the pin voltage @p v_pin_V; returns ADCRESULTn (code << 4).
 *  A non-finite input converts as 0 V. */
uint16_t adc_f2812_convert(adc_f2812_t *a, double v_pin_V);

#endif /* ADC_F2812_H */
