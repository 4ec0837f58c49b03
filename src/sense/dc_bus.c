/* DC-bus voltage.  See dc_bus.h. */
#include "dc_bus.h"

#include <math.h>

/* 2^-16: raw / 65536, exact in Q24 (2^8 LSB) and in float */
#define DC_BUS_TWO_PI 6.28318530717958647692f

dc_bus_status_t dc_bus_init(dc_bus_t *d, float vdc_full_scale_V, const base_values_t *b,
                            float fc_Hz)
{
    float k;
    float a;

    d->vdc_raw = 0u;
    d->k_scale = _IQ(0.0);
    d->k_filt = _IQ(0.0);
    d->vdc = _IQ(0.0);
    d->vdc_filt = _IQ(0.0);
    d->rail = 0u;
    d->primed = 0u;

    if (b == 0 || !(b->V_base_V > 0.0f) || !(b->Ts_s > 0.0f)) {
        return DC_BUS_ERR_BASE;
    }
    /* the full-scale code is 4095 (raw 65520), not 65536 */
    k = vdc_full_scale_V / b->V_base_V * (65536.0f / 65520.0f);
    if (!(vdc_full_scale_V > 0.0f) || !(k < DC_BUS_FULL_SCALE_MAX_PU)) {
        return DC_BUS_ERR_FULL_SCALE;
    }
    if (!(fc_Hz > 0.0f) || !(fc_Hz < 0.5f / b->Ts_s)) {
        return DC_BUS_ERR_CUTOFF;
    }
    a = 1.0f - expf(-DC_BUS_TWO_PI * fc_Hz * b->Ts_s);
    if (!(a >= DC_BUS_FILTER_A_MIN)) {
        return DC_BUS_ERR_CUTOFF;
    }
    d->k_scale = _IQ(k);
    d->k_filt = _IQ(a);
    return DC_BUS_OK;
}
