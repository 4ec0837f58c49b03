/**
 * @file imfoc_convert.h
 * Physical quantities -> what the F2812 would read (host only, double):
 * the board's signal conditioning and ADC (adc_f2812.h) and the QEP count.
 * Used by the co-simulation API (imfoc_api.h) for plants without a sensor
 * model; kept apart so that the conversions can be tested alone.
 */
#ifndef IMFOC_CONVERT_H
#define IMFOC_CONVERT_H

#include <stdint.h>

/** ADCRESULTn of a current channel: pin = 1.5 V + 1.5 V i / I_fs, then the
 *  ideal 12-bit quantiser (floor, clamped to 0..4095), left-justified.
 *  A non-finite @p i_A reads as 0 V (the caller rejects it first). */
uint16_t imfoc_adc_current(double i_A, double i_full_scale_A);
/** ADCRESULTn of the bus divider: pin = 3.0 V vdc / Vdc_fs. */
uint16_t imfoc_adc_vdc(double vdc_V, double vdc_full_scale_V);
/** T2CNT for an unwrapped mechanical angle: round(theta 4 N / 2 pi) mod 2^16
 *  (edges half a pitch either side of theta = 0, as encoder_model.h's
 *  default grid).  Exact for |theta| < 2^52 / (4 N) revolutions. */
uint16_t imfoc_qep_count(double theta_m_rad, uint16_t lines);
/** theta + (new - old) wrapped to (-pi, pi]: the unwrapped angle that follows
 *  @p theta_unwrapped when the (possibly wrapped) input moves from
 *  @p old_in to @p new_in. */
double imfoc_unwrap(double theta_unwrapped, double old_in, double new_in);

#endif /* IMFOC_CONVERT_H */
