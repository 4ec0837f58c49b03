/**
 * @file hal_host.h
 * Host implementation of the HAL seams (include/hal_*.h): the link-time fake
 * that replaces firmware/hal_*_f2812.c in the host build.  The simulator
 * fills a hal_host_port_t with what the F2812's ADC and QEP would hold at the
 * period start, binds it, calls the very same drive_isr() the target runs,
 * and reads back the compare values and the output-enable state.
 *
 * One port per drive instance; hal_host_bind() selects the one the HAL calls
 * act on (the ISR of one instance runs at a time, as on the target).
 */
#ifndef HAL_HOST_H
#define HAL_HOST_H

#include <stdint.h>
#include "hal_adc.h"
#include "hal_pwm.h"
#include "hal_qep.h"

/** HAL calls, in the order an ISR made them (hal_host_port_t.calls). */
typedef enum {
    HAL_HOST_ADC_READ = 1, HAL_HOST_QEP_READ, HAL_HOST_PWM_WRITE, HAL_HOST_PWM_ENABLE,
    HAL_HOST_PWM_DISABLE, HAL_HOST_PWM_TRIPPED, HAL_HOST_ISR_OVERRUN, HAL_HOST_SLOW_REQUEST
} hal_host_call_t;
#define HAL_HOST_CALL_LOG 16u

typedef struct {
    /* written by the simulator before the ISR */
    hal_adc_sample_t adc;
    uint16_t qep_count;
    uint16_t trip_input;       /* PDPINTA level: 1 = the power stage tripped */
    uint16_t trip_latch;       /* a PDPINTA pulse seen (the F2812's latch: its falling edge
                                  cleared FCOMPOE in hardware and the PDPINTA ISR latched it,
                                  hal_pwm_f2812.c); set by hal_host_pdpinta_pulse, cleared by
                                  hal_host_clear_trip with the line high */
    uint16_t overrun;          /* what hal_isr_overrun() reports for this ISR (a test's fake:
                                  the host ISR never runs late) */
    /* written by the HAL calls of the ISR */
    hal_pwm_compare_t cmp;     /* last CMPR1..3 written (takes effect next period) */
    uint16_t outputs_enabled;  /* COMCONA.FCOMPOE */
    uint32_t writes;           /* number of hal_pwm_write calls */
    uint32_t slow_requests;    /* number of hal_slow_isr_request calls (the caller runs
                                  drive_slow_isr itself: the host has no interrupt) */
    uint16_t calls[HAL_HOST_CALL_LOG];  /* hal_host_call_t, in order (a test clears n_calls) */
    uint16_t n_calls;          /* calls logged (stops at HAL_HOST_CALL_LOG) */
} hal_host_port_t;

void hal_host_port_init(hal_host_port_t *p, uint16_t t1pr);
/** A PDPINTA pulse (the bridge's comparator, plant.h): outputs off at once
 *  (the EV's hardware), the trip latched until hal_host_clear_trip. */
void hal_host_pdpinta_pulse(hal_host_port_t *p);
/** The board's fault-reset path (firmware/main.c: pwm_f2812_clear_trip
 *  before the drive's reset): the latch clears only with the line high.
 *  @p p NULL: the bound port.  Returns the latch after the call. */
uint16_t hal_host_clear_trip(hal_host_port_t *p);
void hal_host_bind(hal_host_port_t *p);

#endif /* HAL_HOST_H */
