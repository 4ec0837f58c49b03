/**
 * @file hal_pwm.h
 * HAL seam: the three-phase PWM of EV-A (T1 continuous up/down, full compare
 * units 1..3, PWM1..6 with dead band).
 *
 * Compare convention (the whole project uses it): T1 counts 0 -> T1PR -> 0;
 * the control period starts at T1 underflow (CNT = 0).  The upper switch of
 * phase x is on while T1CNT > CMPRx, centred on the period match, so its
 * on-time fraction is  d_x = (T1PR - CMPRx) / T1PR:
 * CMPRx = T1PR -> upper always off (d = 0); CMPRx = 0 -> upper always on
 * (d = 1).  Compare values are shadowed and take effect at the next
 * underflow, i.e. in the next control period.
 */
#ifndef HAL_PWM_H
#define HAL_PWM_H

#include <stdint.h>

typedef struct {
    uint16_t cmpr[3];  /* CMPR1..3, each in [0, T1PR] */
} hal_pwm_compare_t;

/** Load CMPR1..3 (effective from the next period). */
void hal_pwm_write(const hal_pwm_compare_t *c);
/** Enable the six outputs (COMCONA.FCOMPOE = 1). */
void hal_pwm_enable(void);
/** Force all six outputs to their inactive state at once (FCOMPOE = 0). */
void hal_pwm_disable(void);
/** Non-zero while the hardware trip (PDPINTA) has disabled the outputs. */
uint16_t hal_pwm_tripped(void);
/** Non-zero if the PWM period that this ISR serves has already ended: the
 *  timer's underflow flag (cleared when the ISR read its samples,
 *  hal_adc_read) is set again, i.e. the ISR overran its period.  Called as
 *  the ISR's last action (drive_isr). */
uint16_t hal_isr_overrun(void);
/** Request the slow ISR (drive_slow_isr), to run when the control ISR
 *  returns, at a lower priority: the next control ISR may preempt it.  On
 *  the F2812 a software-forced CPU interrupt (INT14); on the host a count
 *  (the simulator calls drive_slow_isr after drive_isr itself). */
void hal_slow_isr_request(void);

#endif /* HAL_PWM_H */
