/* Private to src/app: the protections that do not rely on one sensor
 * (drive_safety.c), hooked into the ISR and the background by one line
 * each.  See drive_safety.c for what they judge and how each threshold was
 * chosen. */
#ifndef DRIVE_SAFETY_H
#define DRIVE_SAFETY_H

#include "drive_types.h"

/** The sensor test passed (as of the last SAFETY slot): the sequence's
 *  test_done (drive_slow.c sequence_inputs). */
static inline uint16_t drive_safety_test_done(const drive_t *d) { return d->prot.model.test_done; }

/** Once, from drive_init after every other module (float).  Returns 0, or
 *  1 when a module refused its constants. */
int16_t drive_safety_init(drive_t *d, const drive_config_t *c);

/** ISR, every period, after the voltage of the period that just ended is
 *  known (drive_step.c's voltage model): the model check's window sum. */
static inline void drive_safety_fast(drive_t *d)
{
    current_model_check_accumulate(&d->prot.model.cmc, d->pwm.volt.valpha, d->pwm.volt.vbeta, d->pwm.on_last);
}

/** Slow ISR, slot SEQUENCE, right after the sequence's step: the sensor
 *  test disarmed as the sequence leaves CALIBRATE, here rather than in the
 *  next control ISR (drive_safety_modulate then skips it from the first
 *  period of the next state on: no control ISR carries the disarm). */
void drive_safety_state(drive_t *d);

/** Non-inline part of drive_safety_modulate (the sensor test's period). */
uint16_t drive_safety_test_period(drive_t *d, hal_pwm_compare_t *out, uint16_t pwm_on);

/** ISR, every period, after the modulation: while the sequence runs the
 *  sensor test (CALIBRATE), its voltage replaces the current loops' (the
 *  PIs are held at zero) or, when it fails, the bridge goes off with
 *  FAULT_SENSOR_TEST.  Returns the period's PWM state.  Idle: one compare. */
static inline uint16_t drive_safety_modulate(drive_t *d, hal_pwm_compare_t *out,
                                             uint16_t pwm_on)
{
    if ((d->seq.state != ID_CALIBRATE) & (d->prot.model.stest.armed == 0u)) {
        return pwm_on;
    }
    return drive_safety_test_period(d, out, pwm_on);
}

/** ISR, slot SAFETY: the model check's step over the slow window, the
 *  encoder's count step, the sensor test's verdict to the sequence
 *  (drive_safety_test_verdict, in CALIBRATE), the publish guard's tick;
 *  latches their faults. */
void drive_safety_slow(drive_t *d);

/** Slot SAFETY, in CALIBRATE (and once after it): the sensor test's vectors
 *  judged (sensor_test_judge: out of the control ISR), its verdict to the
 *  sequence (test_done). */
void drive_safety_test_verdict(drive_t *d);

/** ISR, two slots after SAFETY's (drive_slow.c), one per half: the model
 *  check's sequence tests on SAFETY's last residual (each window runs one
 *  half: current_model_check_half), a trip latched there.  Half a slow
 *  period later than in SAFETY's own ISR: 0.5 ms against their detection
 *  times of 12-64 ms (drive_safety.c). */
void drive_safety_symmetrical(drive_t *d, uint16_t phase);

/** Latch the model check's trip (FAULT_CURRENT_SENSOR). */
static inline void drive_safety_latch_cmc(drive_t *d)
{
    if (d->prot.model.cmc.fault != 0u) {
        protect_latch(&d->prot.trip, FAULT_CURRENT_SENSOR);
    }
}

/** ISR, right after the encoder's frozen test (slot FILTERS_C, the same
 *  ISR: before protect() latches FAULT_ENCODER in the next one): at a
 *  frozen trip, the locked-rotor decision on the model check's last
 *  residual; latches FAULT_STALL. */
void drive_safety_stall(drive_t *d);

/** Background, on the fault-reset command: re-arm (a cause still there
 *  trips again once the drive runs). */
void drive_safety_reset(drive_t *d);

/** Background: the gain error (relative, >= 0) one current sensor may
 *  carry that the model check has not found: its negative sequence, all
 *  of it, per unit of the one a gain error gives (CMC_NEG_PER_GAIN sigma
 *  Ls |i|), as the mean vector over the last pass's steady states (a gain
 *  error's is constant there; the bridge's harmonics turn and average
 *  out): an upper bound; where the sequence tests were never armed (below
 *  their speed gate), the sensor test's bound (sensor_test.h).  For the
 *  confidences (drive_background.c). */
float drive_safety_sensor_gain(const drive_t *d);

/** Background, each pass: the sums drive_safety_sensor_gain averages (the
 *  last pass's SETTLE and RUN, the sequence tests armed); and their reset
 *  (each start). */
void drive_safety_sensor_gain_sample(drive_t *d);
void drive_safety_sensor_gain_reset(drive_t *d);

/** Background, last in each pass: the publish guard (publish_guard.h) on
 *  the telemetry's published set. */
void drive_safety_background(drive_t *d);

#endif /* DRIVE_SAFETY_H */
