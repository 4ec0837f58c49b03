/* Private to src/app: the bridge's voltage-error test at standstill
 * (vi_curve.h) hooked into the sequence, the ISR and the background by one
 * line each.  See drive_vi.c. */
#ifndef DRIVE_VI_H
#define DRIVE_VI_H

#include "drive_types.h"

/** The curve is measured and applied, or the test is off: the sequence's
 *  vi_done (drive_slow.c sequence_inputs). */
static inline uint16_t drive_vi_done(const drive_t *d) { return d->vi.done; }

/* drive_t.vi.post: what the background answered */
#define DRIVE_VI_NONE 0u      /* nothing yet */
#define DRIVE_VI_CURVE 1u     /* vi.curve holds the curve to apply */
#define DRIVE_VI_REFUSED 2u   /* the fit refused the test (vi.status) */

/** The current levels' PI of the bridge's test (pu, as pi_init takes
 *  them): the gains with the zero on the stator pole, as the current loops,
 *  and the output limit +-u_max, half the linear modulation range; shared
 *  by drive_vi_init and the configuration's limit table (drive_limits.c). */
void drive_vi_gains(const drive_config_t *c, const base_values_t *b, float Ts_slow, float sls_H,
                    float *kp, float *ki, float *u_max);

/** The test's first current level i1, pu of I_base (DRIVE_VI_I1_OF_IM of
 *  i_M), as drive_vi_init gives it to vi_curve_init; shared with the
 *  configuration's limit table (drive_limits.c). */
float drive_vi_i1_pu(const drive_config_t *c, const base_values_t *b);

/** Once, from drive_init after the sequence (float): with the board's
 *  dead_time_comp the test is armed (seq.vi_test) and the compensation
 *  stays off until its curve is applied.  Returns 0, or 1 when vi_curve
 *  refused its constants. */
int16_t drive_vi_init(drive_t *d, const drive_config_t *c, float Ts_slow, float sls_H,
                      float tr_s);

/** ISR, slot SEQUENCE, before the sequence's step: the test's step, the
 *  background's answer (applied to volt_calc, vi.done) or
 *  FAULT_VI_CURVE. */
void drive_vi_slow(drive_t *d);

/** ISR: a test's voltage (alpha, beta, pu) to the modulator in place of the
 *  current loops' (their PIs held at zero): the sensor test's and this
 *  one's. */
void drive_test_voltage(drive_t *d, hal_pwm_compare_t *out, _iq u_alpha, _iq u_beta);

/** ISR, every period of the test (drive_safety_test_period): its alpha
 *  voltage to the modulator, the current PIs held at zero. */
void drive_vi_modulate(drive_t *d, hal_pwm_compare_t *out);

/** Background, each pass: the fit once the test is done (float), its
 *  curve posted to the ISR, or the refusal. */
void drive_vi_background(drive_t *d);

#endif /* DRIVE_VI_H */
