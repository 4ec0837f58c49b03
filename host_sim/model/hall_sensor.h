/**
 * @file hall_sensor.h
 * Hall-effect current transducer (closed or open loop, e.g. LEM LTS/HAIS
 * class), as seen at its output in amperes of the primary (double, SI,
 * host only).  The conditioning to volts and the ADC are in adc_f2812.h.
 *
 *   y  = first-order low-pass of the primary current i (bandwidth f_bw;
 *        f_bw = 0: no filter, y = i), exact discretisation for i held over
 *        each call's interval
 *   i_meas = (1 + gain_error) y + offset_A + noise_rms_A n,   n ~ N(0, 1)
 *
 * Noise is white per call (one sample per ADC conversion) from the
 * instance's own splitmix64 stream (model_rng.h), seeded by the parameters.
 */
#ifndef HALL_SENSOR_H
#define HALL_SENSOR_H

#include <stdint.h>
#include "model_rng.h"

typedef struct {
    double gain_error;     /* relative, e.g. 0.005 = +0.5 %; > -1 */
    double offset_A;       /* output offset, referred to the primary */
    double noise_rms_A;    /* white noise, >= 0 */
    double bandwidth_Hz;   /* -3 dB bandwidth, 0 = unlimited, else > 0 */
    uint64_t seed;         /* noise stream */
} hall_params_t;

typedef enum {
    HALL_OK = 0,
    HALL_ERR_NULL,
    HALL_ERR_GAIN,         /* gain_error not finite or <= -1 */
    HALL_ERR_OFFSET,       /* offset not finite */
    HALL_ERR_NOISE,        /* noise negative or not finite */
    HALL_ERR_BANDWIDTH     /* bandwidth negative or not finite */
} hall_status_t;

typedef struct {
    /* parameters */
    hall_params_t p;
    double tau_s;          /* 1 / (2 pi f_bw), 0 = no filter */
    /* outputs */
    double i_meas_A;       /* last measurement */
    /* state */
    double y_A;            /* filter state */
    uint16_t primed;       /* 0 until the first call (filter starts at i) */
    double k_dt_s;         /* the step the filter gain k was computed for (0: none) */
    double k;              /* 1 - exp(-k_dt_s / tau_s) */
    model_rng_t rng;
} hall_t;

/** Realistic defaults for a +-25 A class Hall transducer: gain error 0.5 %,
 *  offset 20 mA, noise 10 mA rms, bandwidth 100 kHz, seed 1. */
void hall_params_default(hall_params_t *p);
/** Error-free sensor (gain 1, no offset, no noise, unlimited bandwidth). */
void hall_params_ideal(hall_params_t *p);

hall_status_t hall_init(hall_t *h, const hall_params_t *p);

/** Advance the bandwidth filter by @p dt_s with primary current @p i_A held
 *  (dt_s <= 0: no filter advance) and return a new measurement.  The first
 *  call starts the filter at @p i_A. */
double hall_measure(hall_t *h, double i_A, double dt_s);

#endif /* HALL_SENSOR_H */
