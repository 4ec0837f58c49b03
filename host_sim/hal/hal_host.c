/* Host HAL: see hal_host.h.  Calls made with no port bound are a programming
 * error of the simulator; they abort with a message rather than write through
 * a null pointer. */
#include "hal_host.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static hal_host_port_t *g_port;

static hal_host_port_t *port(void)
{
    if (g_port == NULL) {
        fprintf(stderr, "hal_host: HAL called with no port bound\n");
        abort();
    }
    return g_port;
}

void hal_host_port_init(hal_host_port_t *p, uint16_t t1pr)
{
    memset(p, 0, sizeof *p);
    p->cmp.cmpr[0] = p->cmp.cmpr[1] = p->cmp.cmpr[2] = t1pr; /* upper switches off */
    p->adc.ia_raw = p->adc.ib_raw = 0x8000u;
}

void hal_host_bind(hal_host_port_t *p) { g_port = p; }

/* the bound port, with the call logged */
static hal_host_port_t *logged(hal_host_call_t c)
{
    hal_host_port_t *p = port();
    if (p->n_calls < HAL_HOST_CALL_LOG) {
        p->calls[p->n_calls++] = (uint16_t)c;
    }
    return p;
}

void hal_adc_read(hal_adc_sample_t *s) { *s = logged(HAL_HOST_ADC_READ)->adc; }
uint16_t hal_qep_read_count(void) { return logged(HAL_HOST_QEP_READ)->qep_count; }

void hal_pwm_write(const hal_pwm_compare_t *c)
{
    hal_host_port_t *p = logged(HAL_HOST_PWM_WRITE);
    p->cmp = *c;
    p->writes++;
}

void hal_pwm_enable(void)
{
    hal_host_port_t *p = logged(HAL_HOST_PWM_ENABLE);
    /* as on the F2812: the outputs cannot be enabled while PDPINTA is active
     * or its latch is set */
    p->outputs_enabled = (uint16_t)(p->trip_input == 0u && p->trip_latch == 0u);
}

void hal_pwm_disable(void) { logged(HAL_HOST_PWM_DISABLE)->outputs_enabled = 0u; }
uint16_t hal_pwm_tripped(void)
{
    const hal_host_port_t *p = logged(HAL_HOST_PWM_TRIPPED);
    return (uint16_t)(p->trip_input | p->trip_latch);
}

void hal_host_pdpinta_pulse(hal_host_port_t *p)
{
    p->trip_latch = 1u;
    p->outputs_enabled = 0u;
}

uint16_t hal_host_clear_trip(hal_host_port_t *p)
{
    if (p == NULL) {
        p = port();
    }
    if (p->trip_input == 0u) {
        p->trip_latch = 0u;
    }
    return p->trip_latch;
}
uint16_t hal_isr_overrun(void) { return logged(HAL_HOST_ISR_OVERRUN)->overrun; }
void hal_slow_isr_request(void) { logged(HAL_HOST_SLOW_REQUEST)->slow_requests++; }
