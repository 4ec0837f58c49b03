/**
 * @file qep_speed.h
 * Rotor angle and speed from the quadrature-encoder counter (EV-A T2 in QEP
 * mode: x4 counting, free-running over 0..0xFFFF, see hal_qep.h).
 *
 * Angle.  The count difference of one sample, taken modulo 2^16 as a signed
 * 16-bit number, is correct through the counter wrap in both directions as
 * long as the shaft turns less than 32768 counts per sample.  The differences
 * are accumulated modulo counts-per-revolution (cpr = 4 * lines) in integers,
 * one accumulator for the mechanical and one for the electrical angle
 * (pole_pairs * difference), so the angle is exact modulo the counts and
 * never drifts; only the final conversion to pu rounds (1/cpr truncated to
 * Q30, times the count, truncated to Q24: the angle reads low by less than
 * 1 + cpr/64 LSB of Q24, 64 LSB = 3.8e-6 rev at cpr = 4000; a fixed error
 * that does not accumulate).  The angles are relative to
 * the position at qep_speed_reset() (indirect field orientation needs only
 * the speed; no index pulse is used).
 *
 * Speed.  At 1000 lines and 1400 r/min the counter moves only ~6 counts per
 * 66.7 us sample, so a one-sample difference would quantise the speed to
 * ~16 %.  The speed is therefore the count difference over a window of W
 * samples (a ring buffer of the last W counts), i.e. the mean speed over the
 * last W samples:
 *
 *     speed_raw = pp * (count(k) - count(k-W)) / (W * cpr * Ts * f_base)   [pu of w_base]
 *
 * Resolution (one count in the window): pp / (W cpr Ts f_base); with pp = 2,
 * cpr = 4000, Ts = 1/15000 s, f_base = 50 Hz, W = 16: 0.009375 pu (14 r/min,
 * 1 % of 1400 r/min).  Error of speed_raw against the true mean speed over
 * the window: less than one count (each count reading is the floor of the
 * true position in counts).  Delay: the window mean is the speed at the
 * window's middle, W/2 samples ago (exact for constant acceleration).
 * speed = first-order low-pass of speed_raw, exact (ZOH) discretisation with
 * a = 1 - exp(-2 pi fc Ts); it averages the count dithering and adds a lag
 * of (1-a)/a samples for a ramp.  Total lag of `speed` behind a speed ramp:
 * W/2 + (1-a)/a samples (W = 16, fc = 100 Hz: 8 + 23.4 = 31.4 samples,
 * 2.1 ms).
 */
#ifndef QEP_SPEED_H
#define QEP_SPEED_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"

/** Largest speed window (ring-buffer length), samples. */
#define QEP_SPEED_WINDOW_MAX 64u
/** Largest accepted encoder line count (cpr = 4 * lines <= 32768 keeps the
 *  Q30 angle conversion below 1.0). */
#define QEP_SPEED_LINES_MAX 8192u
/** Largest accepted pole-pair count (keeps pole_pairs * difference in int32). */
#define QEP_SPEED_POLE_PAIRS_MAX 64u
/** Smallest accepted speed-filter coefficient a. */
#define QEP_SPEED_FILTER_A_MIN 1.0e-4f

typedef enum {
    QEP_SPEED_OK = 0,
    QEP_SPEED_ERR_BASE,        /* bases NULL or not initialised, or pole pairs > 64 */
    QEP_SPEED_ERR_LINES,       /* lines == 0 or > 8192 */
    QEP_SPEED_ERR_WINDOW,      /* window not a power of two in [1, 64] */
    QEP_SPEED_ERR_RESOLUTION,  /* one count in the window, or in one sample, >= 1 pu of speed */
    QEP_SPEED_ERR_CUTOFF       /* fc not in (0, 1/(2 Ts)), or a < 1e-4 */
} qep_speed_status_t;

typedef struct {
    /* inputs */
    uint16_t count;            /* T2CNT this sample */
    /* parameters */
    int32_t cpr;               /* counts per mechanical revolution, 4 * lines */
    int32_t pole_pairs;
    uint16_t window;           /* W, samples, power of two */
    int32_t d_max;             /* largest |window difference| converted, counts
                                  (speed_raw saturates at d_max counts, <= 63 pu) */
    _iq30 k_angle;             /* Q30: 1/cpr, pu of a revolution per count */
    _iq k_speed;               /* Q24: pp / (W cpr Ts f_base), pu speed per count */
    _iq k_filt;                /* Q24: a = 1 - exp(-2 pi fc Ts) */
    int32_t d_max1;            /* as d_max, for the one-sample difference */
    _iq k_speed1;              /* Q24: pp / (cpr Ts f_base), pu speed per count in one sample */
    /* outputs */
    _iq theta_mech;            /* Q24, pu of a mechanical revolution, [0, 1) */
    _iq theta_elec;            /* Q24, pu of an electrical revolution, [0, 1) */
    _iq speed_raw;             /* Q24, electrical speed, pu of w_base (window mean) */
    _iq speed_1;               /* Q24, electrical speed over the last sample alone, pu of
                                  w_base (lag Ts/2; coarse: k_speed1 per count; the
                                  identification filters it) - the same value a W = 1
                                  instance gives as speed_raw */
    _iq speed;                 /* Q24, electrical speed, pu of w_base (filtered) */
    int16_t dir;               /* +1 counting up, -1 down, 0 no count in the window */
    /* state */
    uint16_t prev_count;       /* T2CNT of the previous sample */
    int32_t pos_mech;          /* counts, [0, cpr) */
    int32_t pos_elec;          /* pole_pairs * counts modulo cpr, [0, cpr) */
    uint16_t hist[QEP_SPEED_WINDOW_MAX];  /* the last W counts (ring) */
    uint16_t head;             /* index of count(k - W) in hist */
} qep_speed_t;

/**
 * @p encoder_lines: lines per revolution (the QEP counts 4 per line);
 * pole pairs, Ts and f_base come from @p b; @p speed_filter_Hz: cut-off of
 * `speed`; @p window: W.  Leaves the module reset at count 0: call
 * qep_speed_reset() with the counter's value before the first step.
 */
qep_speed_status_t qep_speed_init(qep_speed_t *q, uint16_t encoder_lines,
                                  const base_values_t *b, float speed_filter_Hz,
                                  uint16_t window);

/** Restart from @p count_now: angles 0, speeds 0, the window filled with
 *  count_now (the shaft assumed at rest). */
void qep_speed_reset(qep_speed_t *q, uint16_t count_now);

/**
 * One sample.  Scaling and overflow: count differences are taken modulo
 * 2^16 and read as signed (wrap-safe by construction); the position
 * accumulators stay in [0, cpr) (int32).  The window difference is
 * saturated to +-d_max counts before the Q24 conversion, so speed_raw cannot
 * overflow (a difference that large is an encoder fault or > 60x base
 * speed; the protections judge plausibility).  The filter increment is a
 * rounded product: speed settles within 0.5/a LSB of speed_raw.
 */
void qep_speed_step(qep_speed_t *q);

#endif /* QEP_SPEED_H */
