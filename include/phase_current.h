/**
 * @file phase_current.h
 * Phase currents from the two Hall sensors (phases a and b) via the ADC.
 *
 * Signal chain: the Hall sensor and its conditioning map -I_base..+I_base to
 * 0..3 V around 1.5 V; the F2812 ADC leaves a 12-bit result left-justified in
 * ADCRESULTn (bits 15..4).  So a raw reading of 32768 is nominally 0 A and
 * one pu of current is 32768 raw counts:
 *
 *     i_pu = polarity * gain_corr * (raw - offset) / 32768
 *
 * The ADC resolution is 16 raw counts = 2^-11 pu (4.9e-4 pu); the Q24 result
 * carries it without loss (one raw count is 2^9 Q24 LSBs).
 * ic = -ia - ib (a three-wire motor: no zero-sequence current).
 *
 * Offset calibration (while the bridge is off, so that the true current is
 * 0): phase_current_cal_start() then phase_current_cal_step() once per ISR
 * until it returns a final status.  The mean raw reading becomes the new
 * offset if it lies within the window around 32768 set at init; outside it,
 * the sensor (or its supply) is faulty: the nominal offset is kept for that
 * phase, cal_fault says which phase, and the caller latches a sensor fault.
 */
#ifndef PHASE_CURRENT_H
#define PHASE_CURRENT_H

#include <stdint.h>
#include "IQmathLib.h"

/** Raw reading of 0 A (mid-scale, 1.5 V). */
#define PHASE_CURRENT_OFFSET_NOMINAL 32768u
/** A raw value >= this is at the top rail (ADC code 4095 = 0xFFF0). */
#define PHASE_CURRENT_RAIL_HIGH 0xFFF0u
/** Accepted range of the gain correction (a Hall sensor's gain tolerance is
 *  a few per cent; anything outside this is a configuration error). */
#define PHASE_CURRENT_GAIN_MIN 0.8f
#define PHASE_CURRENT_GAIN_MAX 1.25f
/** Largest accepted offset window, fraction of full scale (65536 counts). */
#define PHASE_CURRENT_WINDOW_MAX 0.25f

/** Status of phase_current_init and phase_current_cal_start. */
/* 2^-15: one raw count is 2^-15 pu (32768 counts = 1 pu).  Exact in Q24
 * (2^9 LSB) and in float. */
#define PC_COUNT_TO_PU _IQ(3.0517578125e-5)

typedef enum {
    PHASE_CURRENT_OK = 0,
    PHASE_CURRENT_ERR_GAIN,      /* a gain correction outside [0.8, 1.25] (or NaN) */
    PHASE_CURRENT_ERR_POLARITY,  /* polarity not +1 or -1 */
    PHASE_CURRENT_ERR_WINDOW,    /* offset window not in (0, 0.25] of full scale */
    PHASE_CURRENT_ERR_SAMPLES    /* cal_start with n_samples == 0 */
} phase_current_status_t;

/** Result of phase_current_cal_step. */
typedef enum {
    PHASE_CURRENT_CAL_BUSY = 0,  /* still accumulating */
    PHASE_CURRENT_CAL_DONE,      /* both offsets measured and accepted */
    PHASE_CURRENT_CAL_REJECTED,  /* at least one offset outside the window:
                                    see cal_fault; nominal offset kept there */
    PHASE_CURRENT_CAL_IDLE       /* no calibration running (call cal_start) */
} phase_current_cal_t;

/** cal_fault and rail bits. */
#define PHASE_CURRENT_PHASE_A 0x1u
#define PHASE_CURRENT_PHASE_B 0x2u

typedef struct {
    /* inputs */
    uint16_t ia_raw;          /* ADCRESULT of phase a: 12 bits left-justified */
    uint16_t ib_raw;          /* ADCRESULT of phase b */
    /* parameters */
    uint16_t offset_a;        /* raw reading of 0 A, phase a (nominal 32768) */
    uint16_t offset_b;        /* raw reading of 0 A, phase b */
    _iq gain_a;               /* Q24: polarity * gain correction, phase a */
    _iq gain_b;               /* Q24: polarity * gain correction, phase b */
    uint16_t offset_window;   /* largest accepted |offset - 32768|, raw counts */
    /* outputs */
    _iq ia, ib, ic;           /* Q24, pu of I_base */
    uint16_t rail;            /* PHASE_CURRENT_PHASE_x bits: reading at 0 or >= 0xFFF0 */
    uint16_t cal_fault;       /* PHASE_CURRENT_PHASE_x bits: offset rejected by the
                                 last calibration */
    /* state */
    uint32_t cal_sum_a;       /* sum of raw readings (<= 65535 * 65520 < 2^32) */
    uint32_t cal_sum_b;
    uint16_t cal_n;           /* samples requested */
    uint32_t cal_recip;       /* the mean's multiplier for cal_recip_n samples (0: divide) */
    uint16_t cal_rshift;      /* ... and the shift of the product's high word (0..31;
                                 phase_current_cal_design) */
    uint16_t cal_recip_n;
    uint16_t cal_left;        /* samples still to take; 0 = no calibration running */
} phase_current_t;

/**
 * Set the parameters: per-phase gain corrections (1.0 = nominal sensor),
 * the common polarity (+1, or -1 if the sensors are mounted reversed), and
 * the offset window as a fraction of full scale (e.g. 0.05f: 3277 counts,
 * 5 % of 65536).  Offsets start nominal.  On error nothing is usable.
 */
phase_current_status_t phase_current_init(phase_current_t *pc, float gain_a, float gain_b,
                                          int16_t polarity, float offset_window_fs);

/* A reading at a rail (0, or RAIL_HIGH and above) as one unsigned compare
 * per phase, no branch: raw - 1 wraps 0 to 0xFFFF, so raw - 1 >= RAIL_HIGH
 * - 1 holds exactly for raw == 0 or raw >= RAIL_HIGH.  Phase A's bit is 1,
 * B's is 2 (the compare's 0/1 shifted). */
static inline uint16_t phase_current_rail_bits(uint16_t a_raw, uint16_t b_raw)
{
    const uint16_t a = (uint16_t)((uint16_t)(a_raw - 1u) >= (uint16_t)(PHASE_CURRENT_RAIL_HIGH - 1u));
    const uint16_t b = (uint16_t)((uint16_t)(b_raw - 1u) >= (uint16_t)(PHASE_CURRENT_RAIL_HIGH - 1u));
    return (uint16_t)(a | (uint16_t)(b << 1));
}

/**
 * One sample: raw -> pu.
 * Scaling: raw - offset is an exact integer in [-65535, 65535]; times 2^-15
 * it is an exact Q24 value in [-2, 2) pu; times gain (<= 1.25) stays within
 * +-2.5 pu, far inside Q24's +-128.  The only rounding is the gain product
 * (_IQmpy truncation: < 1 LSB = 6e-8 pu).  No overflow is possible, so
 * nothing saturates; the rail flag says when a reading is clipped.
 */
static inline void phase_current_step(phase_current_t *pc)
{
    /* exact integers in [-65535, 65535] (int32: no 16-bit overflow on C28x) */
    int32_t da = (int32_t)pc->ia_raw - (int32_t)pc->offset_a;
    int32_t db = (int32_t)pc->ib_raw - (int32_t)pc->offset_b;

    /* count * 2^-15 -> Q24 exact (|.| < 2); Q24*Q24 -> Q24 (|.| < 2.5) */
    pc->ia = _IQmpy(pc->gain_a, _IQmpyI32(PC_COUNT_TO_PU, da));
    pc->ib = _IQmpy(pc->gain_b, _IQmpyI32(PC_COUNT_TO_PU, db));
    pc->ic = -pc->ia - pc->ib;   /* |.| < 5: no overflow */
    pc->rail = phase_current_rail_bits(pc->ia_raw, pc->ib_raw);
}

/** Once, after init (integer, not for an ISR: a 64-bit division): the
 *  calibration's mean over @p n_samples samples as a multiply and a shift,
 *  exactly the rounded division's result for every sum (Granlund &
 *  Montgomery, theorem 4.2); phase_current_cal_start takes this count only.
 *  PHASE_CURRENT_ERR_SAMPLES if n is 0 or the multiplier would not fit 32
 *  bits (n = 1, or n above 32768). */
phase_current_status_t phase_current_cal_design(phase_current_t *pc, uint16_t n_samples);

/** Start an offset calibration over @p n_samples samples (1..65535; e.g.
 *  1024 = 68 ms at 15 kHz), the count phase_current_cal_design made (else
 *  PHASE_CURRENT_ERR_SAMPLES, nothing started).  Clears cal_fault. */
phase_current_status_t phase_current_cal_start(phase_current_t *pc, uint16_t n_samples);

/**
 * Accumulate this sample's ia_raw, ib_raw (call instead of, or before,
 * phase_current_step while the PWM is off).  On the last sample computes the
 * rounded mean (one 32-bit division, once), checks the window and loads the
 * offsets; returns BUSY until then.
 */
phase_current_cal_t phase_current_cal_step(phase_current_t *pc);

#endif /* PHASE_CURRENT_H */
