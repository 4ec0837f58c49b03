/**
 * @file drive.h
 * The drive application: owns one instance of every control and estimation
 * module and runs them in the order of the 15 kHz ISR.  (CONTRACT STUB: the
 * full struct is filled in by the integration work; the signatures below are
 * fixed and used by firmware/ and host_sim/.)
 *
 * drive_isr()  = hal_adc_read + hal_qep_read_count + drive_step + hal_pwm_write
 * drive_step() = the pure core: raw inputs in, compare values out, no HAL,
 *                so the co-simulation API and tests can call it directly.
 */
#ifndef DRIVE_H
#define DRIVE_H

#include <stdint.h>
#include "drive_config.h"
#include "hal_adc.h"
#include "hal_pwm.h"

typedef struct drive drive_t;   /* defined in drive_types.h */

/** Compute every constant from the SI configuration.  Returns 0 on success,
 *  a non-zero drive_cfg_status_t naming the bad field otherwise (the drive
 *  then stays in its safe state: PWM off). */
int16_t drive_init(drive_t *d, const drive_config_t *cfg);
/** One control period: the body of the EV-A T1-underflow ISR. */
void drive_isr(drive_t *d);
/** The same without the HAL. */
void drive_step(drive_t *d, const hal_adc_sample_t *adc, uint16_t qep_count,
                hal_pwm_compare_t *out);
/** Low-priority work for the background loop (publishing, telemetry). */
void drive_background(drive_t *d);

#endif /* DRIVE_H */
