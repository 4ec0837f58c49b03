/**
 * @file hall_sensor.c
 * Hall current transducer; see hall_sensor.h.
 */
#include "hall_sensor.h"

#include <math.h>
#include <string.h>

void hall_params_default(hall_params_t *p)
{
    p->gain_error = 0.005;
    p->offset_A = 0.02;
    p->noise_rms_A = 0.01;
    p->bandwidth_Hz = 100.0e3;
    p->seed = 1u;
}

void hall_params_ideal(hall_params_t *p)
{
    p->gain_error = 0.0;
    p->offset_A = 0.0;
    p->noise_rms_A = 0.0;
    p->bandwidth_Hz = 0.0;
    p->seed = 1u;
}

hall_status_t hall_init(hall_t *h, const hall_params_t *p)
{
    if ((h == NULL) || (p == NULL)) {
        return HALL_ERR_NULL;
    }
    memset(h, 0, sizeof(*h));
    if (!isfinite(p->gain_error) || !(p->gain_error > -1.0)) {
        return HALL_ERR_GAIN;
    }
    if (!isfinite(p->offset_A)) {
        return HALL_ERR_OFFSET;
    }
    if (!isfinite(p->noise_rms_A) || (p->noise_rms_A < 0.0)) {
        return HALL_ERR_NOISE;
    }
    if (!isfinite(p->bandwidth_Hz) || (p->bandwidth_Hz < 0.0)) {
        return HALL_ERR_BANDWIDTH;
    }
    h->p = *p;
    h->tau_s = (p->bandwidth_Hz > 0.0) ? 1.0 / (6.283185307179586476925 * p->bandwidth_Hz)
                                       : 0.0;
    model_rng_seed(&h->rng, p->seed);
    return HALL_OK;
}

double hall_measure(hall_t *h, double i_A, double dt_s)
{
    if ((h->primed == 0u) || (h->tau_s <= 0.0)) {
        h->y_A = i_A;
        h->primed = 1u;
    } else if (dt_s > 0.0) {
        /* exact zero-order-hold discretisation of tau dy/dt = i - y */
        if (!(h->k_dt_s == dt_s)) {   /* the gain kept for a recurring step */
            h->k_dt_s = dt_s;
            h->k = 1.0 - exp(-dt_s / h->tau_s);
        }
        h->y_A += h->k * (i_A - h->y_A);
    } else {
        /* no time elapsed: the filter holds */
    }
    h->i_meas_A = (1.0 + h->p.gain_error) * h->y_A + h->p.offset_A;
    if (h->p.noise_rms_A > 0.0) {
        h->i_meas_A += h->p.noise_rms_A * model_rng_gauss(&h->rng);
    }
    return h->i_meas_A;
}
