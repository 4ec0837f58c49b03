/* DC-bus voltage.  See dc_bus.h. */
#include "dc_bus.h"

#include <math.h>

/* 2^-16: raw / 65536, exact in Q24 (2^8 LSB) and in float */
#define DC_BUS_TWO_PI 6.28318530717958647692f

/* pu of V_base per (raw / 65536): the full-scale code is 4095 (raw 65520),
 * not 65536 */
static float dc_bus_k_scale(float vdc_full_scale_V, const base_values_t *b)
{
    return vdc_full_scale_V / b->V_base_V * (65536.0f / 65520.0f);
}

/* The low-pass coefficient a = 1 - exp(-2 pi fc Ts) (dc_bus.h). */
static float dc_bus_filter_a(float fc_Hz, float Ts_s)
{
    return 1.0f - expf(-DC_BUS_TWO_PI * fc_Hz * Ts_s);
}

dc_bus_status_t dc_bus_check(float vdc_full_scale_V, const base_values_t *b, float fc_Hz)
{
    if (b == 0 || !(b->V_base_V > 0.0f) || !(b->Ts_s > 0.0f)) {
        return DC_BUS_ERR_BASE;
    }
    if (!(vdc_full_scale_V > 0.0f) ||
        !(dc_bus_k_scale(vdc_full_scale_V, b) < DC_BUS_FULL_SCALE_MAX_PU)) {
        return DC_BUS_ERR_FULL_SCALE;
    }
    if (!(fc_Hz > 0.0f) || !(fc_Hz < 0.5f / b->Ts_s)) {
        return DC_BUS_ERR_CUTOFF;
    }
    if (!(dc_bus_filter_a(fc_Hz, b->Ts_s) >= DC_BUS_FILTER_A_MIN)) {
        return DC_BUS_ERR_CUTOFF;
    }
    return DC_BUS_OK;
}

dc_bus_status_t dc_bus_init(dc_bus_t *d, float vdc_full_scale_V, const base_values_t *b,
                            float fc_Hz)
{
    dc_bus_status_t st;
    float k;
    float a;

    d->vdc_raw = 0u;
    d->k_scale = _IQ(0.0);
    d->k_filt = _IQ(0.0);
    d->vdc = _IQ(0.0);
    d->vdc_filt = _IQ(0.0);
    d->rail = 0u;
    d->primed = 0u;

    st = dc_bus_check(vdc_full_scale_V, b, fc_Hz);
    if (st != DC_BUS_OK) {
        return st;
    }
    k = dc_bus_k_scale(vdc_full_scale_V, b);
    a = dc_bus_filter_a(fc_Hz, b->Ts_s);
    d->k_scale = _IQ(k);
    d->k_filt = _IQ(a);
    return DC_BUS_OK;
}
