/* Drive protections.  See protect.h.  Comparisons only: no arithmetic that
 * could overflow (|x| of a Q24 value is taken with _IQabs, which is exact for
 * every value but INT32_MIN, far outside any sensor's range: +-1 pu full scale). */
#include "protect.h"

protect_args_t protect_args_ok(_iq i_trip, _iq vdc_max, _iq vdc_min)
{
    if (!(i_trip > _IQ(0.0)) || !(i_trip < _IQ(32.0))) {
        return PROTECT_ERR_TRIP;
    }
    if (!(vdc_min > _IQ(0.0))) {
        return PROTECT_ERR_VDC_MIN;
    }
    if (!(vdc_max > vdc_min)) {
        return PROTECT_ERR_VDC_MAX;
    }
    return PROTECT_ARGS_OK;
}

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
    p->i_span = i_trip + i_trip;
    return (int16_t)(protect_args_ok(i_trip, vdc_max, vdc_min) != PROTECT_ARGS_OK);
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
