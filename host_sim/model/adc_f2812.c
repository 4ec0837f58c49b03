/**
 * @file adc_f2812.c
 * Conditioning and F2812 ADC; see adc_f2812.h.
 */
#include "adc_f2812.h"

#include <math.h>
#include <string.h>

sig_cond_status_t sig_cond_init_current(sig_cond_t *c, double i_full_scale_A)
{
    if (c == NULL) {
        return SIG_COND_ERR_NULL;
    }
    memset(c, 0, sizeof(*c));
    if (!isfinite(i_full_scale_A) || !(i_full_scale_A > 0.0)) {
        return SIG_COND_ERR_FULL_SCALE;
    }
    c->gain_V_per_unit = 0.5 * ADC_F2812_VREF_V / i_full_scale_A;
    c->offset_V = 0.5 * ADC_F2812_VREF_V;
    return SIG_COND_OK;
}

sig_cond_status_t sig_cond_init_vdc(sig_cond_t *c, double vdc_full_scale_V)
{
    if (c == NULL) {
        return SIG_COND_ERR_NULL;
    }
    memset(c, 0, sizeof(*c));
    if (!isfinite(vdc_full_scale_V) || !(vdc_full_scale_V > 0.0)) {
        return SIG_COND_ERR_FULL_SCALE;
    }
    c->gain_V_per_unit = ADC_F2812_VREF_V / vdc_full_scale_V;
    c->offset_V = 0.0;
    return SIG_COND_OK;
}

double sig_cond_apply(const sig_cond_t *c, double x)
{
    return c->offset_V + c->gain_V_per_unit * x;
}

void adc_f2812_params_default(adc_f2812_params_t *p)
{
    p->gain_error = 0.0;
    p->offset_lsb = 0.0;
    p->noise_lsb_rms = 1.0;
    p->seed = 2u;
}

void adc_f2812_params_ideal(adc_f2812_params_t *p)
{
    p->gain_error = 0.0;
    p->offset_lsb = 0.0;
    p->noise_lsb_rms = 0.0;
    p->seed = 2u;
}

adc_f2812_status_t adc_f2812_init(adc_f2812_t *a, const adc_f2812_params_t *p)
{
    if ((a == NULL) || (p == NULL)) {
        return ADC_F2812_ERR_NULL;
    }
    memset(a, 0, sizeof(*a));
    if (!isfinite(p->gain_error) || !(p->gain_error > -1.0)) {
        return ADC_F2812_ERR_GAIN;
    }
    if (!isfinite(p->offset_lsb)) {
        return ADC_F2812_ERR_OFFSET;
    }
    if (!isfinite(p->noise_lsb_rms) || (p->noise_lsb_rms < 0.0)) {
        return ADC_F2812_ERR_NOISE;
    }
    a->p = *p;
    model_rng_seed(&a->rng, p->seed);
    return ADC_F2812_OK;
}

uint16_t adc_f2812_convert(adc_f2812_t *a, double v_pin_V)
{
    const double v = isfinite(v_pin_V) ? v_pin_V : 0.0;
    double c;
    uint16_t code;

    /* the input clamps at the rails first (ADCLO .. 3 V): beyond them the
     * result saturates at 0 / 4095 whatever the noise */
    if (v <= 0.0) {
        code = 0u;
    } else if (v >= ADC_F2812_VREF_V) {
        code = ADC_F2812_CODE_MAX;
    } else {
        c = (double)ADC_F2812_CODE_MAX * v / ADC_F2812_VREF_V * (1.0 + a->p.gain_error) +
            a->p.offset_lsb;
        if (a->p.noise_lsb_rms > 0.0) {
            c += a->p.noise_lsb_rms * model_rng_gauss(&a->rng);
        }
        c = floor(c);
        if (c < 0.0) {
            code = 0u;
        } else if (c > (double)ADC_F2812_CODE_MAX) {
            code = ADC_F2812_CODE_MAX;
        } else {
            code = (uint16_t)c;
        }
    }
    a->code = code;
    a->raw = (uint16_t)(code << 4);
    return a->raw;
}
