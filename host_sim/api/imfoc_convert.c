/* Physical -> raw conversions of the co-simulation API; see imfoc_convert.h. */
#include "imfoc_convert.h"

#include <math.h>

#define IMFOC_TWO_PI 6.28318530717958647692

#include "adc_f2812.h"

/* The F281x quantiser without errors or noise (adc_f2812.h): one shared
 * definition of floor(4095 v / 3), the clamping and the << 4. */
static uint16_t adc_ideal(double v_pin)
{
    adc_f2812_t a;
    adc_f2812_params_t p;
    adc_f2812_params_ideal(&p);
    (void)adc_f2812_init(&a, &p);
    return adc_f2812_convert(&a, v_pin);
}

uint16_t imfoc_adc_current(double i_A, double i_full_scale_A)
{
    sig_cond_t c;
    if (sig_cond_init_current(&c, i_full_scale_A) != SIG_COND_OK) {
        return 0u;
    }
    return adc_ideal(sig_cond_apply(&c, i_A));
}

uint16_t imfoc_adc_vdc(double vdc_V, double vdc_full_scale_V)
{
    sig_cond_t c;
    if (sig_cond_init_vdc(&c, vdc_full_scale_V) != SIG_COND_OK) {
        return 0u;
    }
    return adc_ideal(sig_cond_apply(&c, vdc_V));
}

uint16_t imfoc_qep_count(double theta_m_rad, uint16_t lines)
{
    double edges = floor(theta_m_rad * (4.0 * (double)lines) / (IMFOC_TWO_PI) + 0.5);
    /* 16-bit wrap of the (possibly negative) edge count: fmod keeps the
     * value exact, then shift it into [0, 65536) */
    double w = fmod(edges, 65536.0);
    if (!isfinite(w)) {
        return 0u;
    }
    if (w < 0.0) {
        w += 65536.0;
    }
    return (uint16_t)w;
}

double imfoc_unwrap(double theta_unwrapped, double old_in, double new_in)
{
    return theta_unwrapped + remainder(new_in - old_in, IMFOC_TWO_PI);
}
