/**
 * @file f2812_timing.h
 * Register values that follow from the configuration by arithmetic only
 * (no register access, so they are unit-tested on the host): the EV-A T1
 * period, the dead-band register and the SCI baud-rate register.
 * Computed once at start-up, never in the ISR.
 */
#ifndef F2812_TIMING_H
#define F2812_TIMING_H

#include <stdint.h>

typedef enum {
    TIMING_OK = 0,
    TIMING_ERR_PWM_FREQ,   /* T1PR would not fit 16 bits or be < 100 */
    TIMING_ERR_DEAD_TIME,  /* dead time <= 0, NaN, or > 15 * 32 / HSPCLK */
    TIMING_ERR_BAUD        /* BRR outside 1..0xFFFF */
} timing_status_t;

typedef struct {
    /* outputs */
    uint16_t t1pr;     /* T1PR for continuous up/down: HSPCLK / (2 f_pwm) */
    uint16_t dbtcona;  /* DBTCONA value: DBT (11:8), EDBT1..3 (7:5) set, DBTPS (4:2) */
    uint16_t dbt;      /* DBT field, 1..15 */
    uint16_t dbtps;    /* DBTPS field, 0..5 (prescale 2^dbtps) */
    float dead_time_s; /* the dead time actually programmed, >= the request */
    uint16_t brr;      /* SCI BRR = LSPCLK / (8 baud) - 1, rounded */
} f2812_timing_t;

/** T1PR = round(hspclk / (2 f_pwm)) for the up/down count (period 2 T1PR
 *  ticks). */
timing_status_t f2812_timing_t1pr(f2812_timing_t *t, float hspclk_Hz, float pwm_freq_Hz);
/** The smallest prescaler 2^DBTPS (1..32) for which DBT = ceil(dt * HSPCLK /
 *  2^DBTPS) <= 15: the dead time is never shorter than asked (shoot-through
 *  safety) and at most one prescaled tick longer. */
timing_status_t f2812_timing_deadband(f2812_timing_t *t, float hspclk_Hz, float dead_time_s);
/** SCI BRR for the asynchronous baud rate (SPRU051: BAUD = LSPCLK / ((BRR+1) 8)). */
timing_status_t f2812_timing_brr(f2812_timing_t *t, float lspclk_Hz, float baud);

#endif /* F2812_TIMING_H */
