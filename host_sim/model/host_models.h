/**
 * @file host_models.h
 * The host plant models in one include, and how one F2812 control period is
 * simulated with them (double precision, SI, host only).
 *
 *   motor_model.h     induction motor, 5th order, RK4      (+ motor_load.h)
 *   inverter_model.h  averaged two-level bridge, dead time, DC link
 *   hall_sensor.h     Hall current transducer
 *   adc_f2812.h       conditioning + 12-bit ADC, ADCRESULTn format
 *   encoder_model.h   incremental encoder into the QEP / T2 counter
 *   model_rng.h       per-instance seeded noise
 *
 * Timing as on the F2812 (EV-A T1 up/down, period Ts = 2 T1PR / 150 MHz):
 * the ADC conversion and the QEP read happen at the period start (T1
 * underflow); compare values written by the ISR take effect at the next
 * underflow.  One period k of the simulator loop:
 *
 *   1. sample the plant as it is now (start of period k):
 *        ia = hall_measure(&hall_a, m.ia_A, Ts); ib = ... m.ib_A ...
 *        adc.ia_raw  = adc_f2812_convert(&adc_a, sig_cond_apply(&cond_i, ia));
 *        adc.vdc_raw = adc_f2812_convert(&adc_v, sig_cond_apply(&cond_v,
 *                          inverter_bus_voltage_V(&inv, m.t_s, inv.i_dc_A)));
 *        qep = encoder_sample(&enc, m.theta_m_rad);
 *   2. run the controller (drive_step) -> new compare values, kept for k+1
 *   3. apply the compare values written in period k-1:
 *        d_x = inverter_duty_from_cmpr(cmpr_prev[x], T1PR);
 *        i_abc = {m.ia_A, m.ib_A, m.ic_A};          (start-of-period current)
 *        inverter_step(&inv, m.t_s, d, i_abc);
 *        motor_step(&m, inv.v_alpha_V, inv.v_beta_V, Ts, n_sub);
 *      (host_sim/sim/plant.c then redoes the period from the same state
 *      with inverter_step_implicit: the edge currents consistent with
 *      their own voltage)
 *      or, with the outputs disabled: motor_step_open(&m, Ts, n_sub).
 *
 * n_sub = 1 already keeps the model within 1e-6 A / 1e-6 rad/s of the
 * converged solution through a direct-on-line start (test model_motor).
 */
#ifndef HOST_MODELS_H
#define HOST_MODELS_H

#include "adc_f2812.h"
#include "encoder_model.h"
#include "hall_sensor.h"
#include "inverter_model.h"
#include "model_rng.h"
#include "motor_load.h"
#include "motor_model.h"

#endif /* HOST_MODELS_H */
