/**
 * @file f2812_timing.c
 * Register values from the configuration (see f2812_timing.h).  Float is
 * used here only, at start-up; the results are plain integers.
 */
#include "f2812_timing.h"

/* DBTCONA (SPRU065): DBT in bits 11:8, EDBT3..1 in bits 7:5, DBTPS in 4:2. */
#define DBTCON_DBT_SHIFT    8u
#define DBTCON_EDBT_ALL     0x00E0u
#define DBTCON_DBTPS_SHIFT  2u
#define DBT_MAX             15u
#define DBTPS_MAX           5u   /* 101: x/32 (110 and 111 are also x/32) */

timing_status_t f2812_timing_t1pr(f2812_timing_t *t, float hspclk_Hz, float pwm_freq_Hz)
{
    float ticks;
    if (!(hspclk_Hz > 0.0f) || !(pwm_freq_Hz > 0.0f)) {
        return TIMING_ERR_PWM_FREQ;
    }
    ticks = hspclk_Hz / (2.0f * pwm_freq_Hz);
    /* >= 100 ticks keeps the PWM resolution above 1 %; <= 0xFFFF fits T1PR */
    if (!(ticks >= 100.0f) || ticks > 65535.0f) {
        return TIMING_ERR_PWM_FREQ;
    }
    t->t1pr = (uint16_t)(ticks + 0.5f);
    return TIMING_OK;
}

timing_status_t f2812_timing_deadband(f2812_timing_t *t, float hspclk_Hz, float dead_time_s)
{
    uint16_t ps;
    float ticks;
    if (!(hspclk_Hz > 0.0f) || !(dead_time_s > 0.0f)) {
        return TIMING_ERR_DEAD_TIME;
    }
    ticks = dead_time_s * hspclk_Hz;   /* in HSPCLK periods */
    for (ps = 0u; ps <= DBTPS_MAX; ps++) {
        float scaled = ticks / (float)(1u << ps);
        /* ceil, with a 1e-4 tolerance so that an exact multiple (1.0 us =
         * 150 ticks) is not rounded up by the float representation error */
        uint16_t dbt;
        if (scaled > (float)DBT_MAX + 1.0e-4f) {
            continue;
        }
        dbt = (uint16_t)scaled;
        if (scaled - (float)dbt > 1.0e-4f) {
            dbt++;
        }
        if (dbt == 0u) {
            dbt = 1u;   /* DBT = 0 would disable the dead band */
        }
        t->dbt = dbt;
        t->dbtps = ps;
        t->dbtcona = (uint16_t)((uint16_t)(dbt << DBTCON_DBT_SHIFT) | DBTCON_EDBT_ALL
                                | (uint16_t)(ps << DBTCON_DBTPS_SHIFT));
        t->dead_time_s = (float)dbt * (float)(1u << ps) / hspclk_Hz;
        return TIMING_OK;
    }
    return TIMING_ERR_DEAD_TIME;
}

timing_status_t f2812_timing_brr(f2812_timing_t *t, float lspclk_Hz, float baud)
{
    float brr;
    if (!(lspclk_Hz > 0.0f) || !(baud > 0.0f)) {
        return TIMING_ERR_BAUD;
    }
    brr = lspclk_Hz / (8.0f * baud) - 1.0f;
    if (!(brr >= 0.5f) || brr > 65535.0f) {
        return TIMING_ERR_BAUD;
    }
    t->brr = (uint16_t)(brr + 0.5f);
    return TIMING_OK;
}
