/**
 * @file encoder_model.h
 * Incremental encoder on the F2812 EV-A QEP circuit (host only).
 *
 * A disc of N lines gives 4N quadrature edges per mechanical revolution; the
 * QEP counts every edge (x4) into GP timer 2, which counts up for one
 * direction and down for the other and wraps 0xFFFF <-> 0x0000 (T2PR =
 * 0xFFFF, include/hal_qep.h).  The edge positions are fixed on the shaft:
 * edge k sits at theta_m = (k + theta_offset) 2 pi / (4N), so the count is a
 * function of the shaft angle (crossing back and forth over an edge counts
 * +1 then -1), not of the path.
 *
 *   T2CNT = count0 + direction * (edges crossed since init) (mod 2^16)
 *
 * direction = -1 models swapped A/B channels (or a reversed mounting).
 * Count loss (fault tests): each crossed edge is missed with probability
 * loss_prob (seeded stream), and encoder_inject_counts() adds a deterministic
 * error; both shift the count for good, as a real lost edge does.
 */
#ifndef ENCODER_MODEL_H
#define ENCODER_MODEL_H

#include <stdint.h>
#include "model_rng.h"

typedef struct {
    uint16_t lines;        /* lines per revolution (> 0, 4*lines <= 65536) */
    int16_t direction;     /* +1 or -1 */
    uint16_t count0;       /* T2CNT at init */
    double theta_offset;   /* edge grid offset, fraction of one edge pitch [0, 1) */
    double loss_prob;      /* probability of missing an edge, [0, 1] */
    uint64_t seed;         /* loss stream */
} encoder_params_t;

typedef enum {
    ENC_OK = 0,
    ENC_ERR_NULL,
    ENC_ERR_LINES,         /* lines == 0 or 4*lines > 65536 */
    ENC_ERR_DIRECTION,     /* not +1 / -1 */
    ENC_ERR_OFFSET,        /* theta_offset not in [0, 1) */
    ENC_ERR_LOSS,          /* loss_prob not in [0, 1] */
    ENC_ERR_ANGLE          /* initial angle not finite, or beyond 2^62 edges */
} encoder_status_t;

typedef struct {
    /* parameters */
    encoder_params_t p;
    double edges_per_rad;  /* 4N / (2 pi) */
    /* outputs */
    uint16_t count;        /* T2CNT */
    /* state */
    int64_t edge;          /* index of the last edge at or below the shaft angle */
    model_rng_t rng;
} encoder_t;

/** Defaults: 1000 lines (4000 counts/rev), direction +1, count0 = 0, offset
 *  0.5 (theta = 0 mid-way between edges), no loss, seed 3. */
void encoder_params_default(encoder_params_t *p);

/** Start at shaft angle @p theta_m0_rad (unwrapped mechanical angle). */
encoder_status_t encoder_init(encoder_t *e, const encoder_params_t *p,
                              double theta_m0_rad);

/** T2CNT at shaft angle @p theta_m_rad (the motor's unwrapped angle). */
uint16_t encoder_sample(encoder_t *e, double theta_m_rad);

/** Add @p n counts of error (as if edges were gained/lost) to T2CNT. */
void encoder_inject_counts(encoder_t *e, int32_t n);

#endif /* ENCODER_MODEL_H */
