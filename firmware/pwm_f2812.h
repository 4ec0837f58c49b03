/**
 * @file pwm_f2812.h
 * EV-A set-up for the three-phase PWM (the HAL seam itself is hal_pwm.h).
 */
#ifndef PWM_F2812_H
#define PWM_F2812_H

#include <stdint.h>

/** T1 continuous up/down with period @p t1pr (no prescale, HSPCLK), full
 *  compare units 1..3 with reload at underflow, dead band @p dbtcona, T1
 *  underflow as the ADC start of conversion, outputs disabled (FCOMPOE = 0)
 *  and PDPINTA armed.  T1 is started by pwm_f2812_start. */
void pwm_f2812_init(uint16_t t1pr, uint16_t dbtcona);
/** Start T1 (and with it the ADC conversions and the control ISR). */
void pwm_f2812_start(void);
/** The PDPINTA ISR's part: latch the trip, outputs off, clear the flag. */
void pwm_f2812_trip(void);
/** Clear the trip latch (fault-reset path, background) if the PDPINTA line
 *  is high again; returns the latch (0 = cleared). */
uint16_t pwm_f2812_clear_trip(void);
/** T1PR as programmed (for the CPU-load measurement). */
uint16_t pwm_f2812_period(void);

#endif /* PWM_F2812_H */
