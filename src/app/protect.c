/* Drive protections.  See protect.h.  Comparisons only: no arithmetic that
 * could overflow (|x| of a Q24 value is taken with _IQabs, which is exact for
 * every value but INT32_MIN, far outside any sensor's range: +-1 pu full scale). */
#include "protect.h"

int16_t protect_init(protect_t *p, _iq i_trip, _iq vdc_max, _iq vdc_min)
{
    p->ia = p->ib = p->ic = _IQ(0.0);
    p->vdc = _IQ(0.0);
    p->pwm_on = p->adc_rail = p->encoder_fault = p->current_fault = p->hw_trip = 0u;
    p->fault = FAULT_NONE;
    p->trip = 0u;
    p->i_trip = i_trip;
    p->vdc_max = vdc_max;
    p->vdc_min = vdc_min;
    if (!(i_trip > _IQ(0.0)) || !(vdc_min > _IQ(0.0)) || !(vdc_max > vdc_min)) {
        return 1;
    }
    return 0;
}

/* strict: check the undervoltage also with the bridge off (protect_clear). */
static fault_code_t protect_check(const protect_t *p, uint16_t strict)
{
    if (p->hw_trip != 0u) {
        return FAULT_HW_TRIP;
    }
    if (_IQabs(p->ia) > p->i_trip || _IQabs(p->ib) > p->i_trip || _IQabs(p->ic) > p->i_trip) {
        return FAULT_OVERCURRENT;
    }
    if (p->adc_rail != 0u) {
        return FAULT_ADC_RAIL;
    }
    if (p->vdc > p->vdc_max) {
        return FAULT_BUS_OVERVOLTAGE;
    }
    if ((p->pwm_on != 0u || strict != 0u) && p->vdc < p->vdc_min) {
        return FAULT_BUS_UNDERVOLTAGE;
    }
    if (p->encoder_fault != 0u) {
        return FAULT_ENCODER;
    }
    if (p->current_fault != 0u) {
        return FAULT_CURRENT_SENSOR;
    }
    return FAULT_NONE;
}

void protect_latch(protect_t *p, fault_code_t code)
{
    if (p->fault == FAULT_NONE && code != FAULT_NONE) {
        p->fault = code;
        p->trip = 1u;
    }
}

void protect_step(protect_t *p)
{
    protect_latch(p, protect_check(p, 0u));
}

uint16_t protect_clear(protect_t *p)
{
    if (p->fault == FAULT_NONE) {
        return 1u;
    }
    if (protect_check(p, 1u) != FAULT_NONE) {
        return 0u;
    }
    p->fault = FAULT_NONE;
    p->trip = 0u;
    return 1u;
}
