/**
 * @file encoder_model.c
 * Incremental encoder + QEP counter; see encoder_model.h.
 */
#include "encoder_model.h"

#include <math.h>
#include <string.h>

/* Edge indices are kept within +-2^62 (4e18 edges, some 1e14 turns of a
 * 8192-line disc: beyond any run), so that a difference of two never
 * overflows int64_t and the conversion from double is defined. */
#define ENC_EDGE_MAX 4611686018427387904.0   /* 2^62 */

/* Index of the last edge at or below theta into @p k; -1 (k untouched) if
 * theta is not finite or the index is beyond +-2^62 (a diverged plant). */
static int enc_edge(const encoder_t *e, double theta_m_rad, int64_t *k)
{
    const double x = floor(theta_m_rad * e->edges_per_rad - e->p.theta_offset);
    if (!(fabs(x) < ENC_EDGE_MAX)) {   /* (NaN fails too) */
        return -1;
    }
    *k = (int64_t)x;
    return 0;
}

/* Add a signed count to the 16-bit counter: modulo-2^16 arithmetic on
 * unsigned values, which is exactly the T2 wrap 0xFFFF <-> 0. */
static void enc_add(encoder_t *e, int64_t n)
{
    const uint64_t u = (uint64_t)n; /* two's complement, mod 2^64 */
    e->count = (uint16_t)((e->count + u) & 0xFFFFu);
}

void encoder_params_default(encoder_params_t *p)
{
    p->lines = 1000u;
    p->direction = 1;
    p->count0 = 0u;
    p->theta_offset = 0.5;
    p->loss_prob = 0.0;
    p->seed = 3u;
}

encoder_status_t encoder_init(encoder_t *e, const encoder_params_t *p,
                              double theta_m0_rad)
{
    if ((e == NULL) || (p == NULL)) {
        return ENC_ERR_NULL;
    }
    memset(e, 0, sizeof(*e));
    if ((p->lines == 0u) || (4u * (uint32_t)p->lines > 65536u)) {
        return ENC_ERR_LINES;
    }
    if ((p->direction != 1) && (p->direction != -1)) {
        return ENC_ERR_DIRECTION;
    }
    if (!isfinite(p->theta_offset) || (p->theta_offset < 0.0) || !(p->theta_offset < 1.0)) {
        return ENC_ERR_OFFSET;
    }
    if (!isfinite(p->loss_prob) || (p->loss_prob < 0.0) || (p->loss_prob > 1.0)) {
        return ENC_ERR_LOSS;
    }
    e->p = *p;
    e->edges_per_rad = 4.0 * (double)p->lines / 6.283185307179586476925;
    if (enc_edge(e, theta_m0_rad, &e->edge) != 0) {
        memset(e, 0, sizeof(*e));
        return ENC_ERR_ANGLE;
    }
    e->count = p->count0;
    model_rng_seed(&e->rng, p->seed);
    return ENC_OK;
}

uint16_t encoder_sample(encoder_t *e, double theta_m_rad)
{
    int64_t k, delta, counted;

    if (enc_edge(e, theta_m_rad, &k) != 0) {
        return e->count; /* not finite, or beyond any run: no new information */
    }
    delta = k - e->edge;   /* both within +-2^62: no overflow */
    e->edge = k;
    counted = delta;
    /* (a step of more than 2^16 edges is a wrapped count whatever was lost:
     * the loss is drawn per edge only below that, which bounds the loop) */
    if ((e->p.loss_prob > 0.0) && (delta != 0) && (delta <= 65536) && (delta >= -65536)) {
        /* each crossed edge is missed independently; |delta| is a few edges
         * per 66.7 us period at any realistic speed */
        const int64_t n = (delta > 0) ? delta : -delta;
        int64_t j, kept = 0;
        for (j = 0; j < n; j++) {
            if (model_rng_uniform(&e->rng) >= e->p.loss_prob) {
                kept++;
            }
        }
        counted = (delta > 0) ? kept : -kept;
    }
    enc_add(e, (int64_t)e->p.direction * counted);
    return e->count;
}

void encoder_inject_counts(encoder_t *e, int32_t n)
{
    enc_add(e, (int64_t)n);
}
