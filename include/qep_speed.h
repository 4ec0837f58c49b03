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
    int32_t d1;                /* count difference of the last sample (qep_angle_step) */
    /* multi-rate (qep_speed_set_decim): the angle every sample, the speeds
     * every decim samples */
    uint16_t decim;            /* samples per speed update, power of two <= window (1) */
    uint16_t hist_len;         /* window / decim: counts kept */
    _iq k_speedn;              /* Q24: pp / (decim cpr Ts f_base): speed_1 per count */
    int32_t d_maxn;            /* as d_max, for the decim-sample difference */
    /* state */
    uint16_t prev_count;       /* T2CNT of the previous sample */
    uint16_t count_speed;      /* T2CNT at the last speed update */
    int32_t pos_mech;          /* counts, [0, cpr) */
    int32_t pos_elec;          /* pole_pairs * counts modulo cpr, [0, cpr) */
    uint16_t hist[QEP_SPEED_WINDOW_MAX];  /* the counts of the last W / decim updates (ring) */
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

/** qep_speed_init's check of its arguments alone (no struct), the status it
 *  would return: _BASE, _LINES, _WINDOW, then _RESOLUTION (one count in
 *  the window, or in one sample, not below 1 pu of speed), then _CUTOFF.
 *  The configuration's table of limits calls it too (drive_limits.c).
 *  Float: init only. */
qep_speed_status_t qep_speed_check(uint16_t encoder_lines, const base_values_t *b,
                                   float speed_filter_Hz, uint16_t window);

/** Restart from @p count_now: angles 0, speeds 0, the window filled with
 *  count_now (the shaft assumed at rest). */
void qep_speed_reset(qep_speed_t *q, uint16_t count_now);

/**
 * Multi-rate: the angle every sample (qep_angle_step), the speeds every
 * @p decim samples (qep_speed_update), decim a power of two <= window; the
 * speed filter's corner @p speed_filter_Hz at that rate.  speed_raw keeps
 * its meaning (the mean over the last W samples), speed_1 becomes the mean
 * speed over the last decim samples (the sum of the one-sample speeds:
 * what a decimated regression needs).  Restarts the speeds at the present
 * count.  Returns QEP_SPEED_ERR_WINDOW, _BASE or _CUTOFF on a bad argument
 * (nothing changed).
 */
qep_speed_status_t qep_speed_set_decim(qep_speed_t *q, uint16_t decim, const base_values_t *b,
                                       float speed_filter_Hz);

/** qep_speed_set_decim's check alone, for a module initialised with
 *  @p window: _WINDOW (decim not a power of two <= window), _BASE, then
 *  _CUTOFF (the corner not in (0, 1/(2 decim Ts)), or its coefficient below
 *  QEP_SPEED_FILTER_A_MIN).  Also the table of limits' (drive_limits.c). */
qep_speed_status_t qep_speed_decim_check(uint16_t decim, uint16_t window,
                                         const base_values_t *b, float speed_filter_Hz);

/* a - b modulo 2^16, read as a signed number in [-32768, 32767].  Written
 * without the implementation-defined uint16 -> int16 conversion, and
 * without a branch: flipping bit 15 of the unsigned difference maps
 * [0, 32767] to [32768, 65535] and [32768, 65535] to [0, 32767]; less
 * 32768 that is the two's complement reading (0 -> 0, 65535 -> -1). */
static inline int32_t qep_diff(uint16_t a, uint16_t b)
{
    return (int32_t)(uint16_t)((uint16_t)(a - b) ^ 0x8000u) - (int32_t)32768;
}

/* p modulo n into [0, n).  The common case (|step| < n) costs two compares;
 * the division runs only after a step of more than one revolution. */
static inline int32_t qep_wrap(int32_t p, int32_t n)
{
    if (p >= n) {
        p -= n;
        if (p >= n) {
            p %= n;
        }
    } else if (p < 0) {
        p += n;
        if (p < 0) {
            p %= n;          /* C99: in (-n, 0] */
            if (p < 0) {
                p += n;
            }
        }
    }
    return p;
}

/** Every sample: the electrical angle from the count (exact integer
 * accumulator modulo cpr; Q30 * count -> Q24).  Scaling: as qep_speed_step. */
static inline void qep_angle_step(qep_speed_t *q)
{
    const int32_t d1 = qep_diff(q->count, q->prev_count);   /* this sample, counts */
    q->d1 = d1;
    q->prev_count = q->count;
    /* |pole_pairs * d1| <= 64 * 32768 = 2^21 */
    q->pos_elec = qep_wrap(q->pos_elec + q->pole_pairs * d1, q->cpr);
    q->theta_elec = _IQ30toIQ(_IQ30mpyI32(q->k_angle, q->pos_elec));
}

/** Every decim samples (after qep_angle_step of that sample): the
 *  mechanical angle, speed_1, speed_raw and the filtered speed. */
void qep_speed_update(qep_speed_t *q);

/** The mean electrical speed over the decim samples since the count
 *  *since (pu, Q24; the sum of their one-sample speeds), and *since = this
 *  sample's count: for a consumer whose window is not qep_speed_update's
 *  (the regression's, one sample later).  Q24 * count -> Q24, the
 *  difference saturated as speed_1's (|.| <= 63). */
static inline _iq qep_mean_speed(const qep_speed_t *q, uint16_t *since)
{
    int32_t dn = qep_diff(q->count, *since);
    *since = q->count;
    if (dn > q->d_maxn) {
        dn = q->d_maxn;
    } else if (dn < -q->d_maxn) {
        dn = -q->d_maxn;
    }
    return _IQmpyI32(q->k_speedn, dn);
}

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
