/**
 * @file encoder_model.c
 * Incremental encoder + QEP counter; see encoder_model.h.
 */
#include "encoder_model.h"

#include <math.h>
#include <string.h>

/* index of the last edge at or below theta */
static int64_t enc_edge(const encoder_t *e, double theta_m_rad)
{
    return (int64_t)floor(theta_m_rad * e->edges_per_rad - e->p.theta_offset);
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
    if (!isfinite(theta_m0_rad)) {
        return ENC_ERR_ANGLE;
    }
    e->p = *p;
    e->edges_per_rad = 4.0 * (double)p->lines / 6.283185307179586476925;
    e->count = p->count0;
    e->edge = enc_edge(e, theta_m0_rad);
    model_rng_seed(&e->rng, p->seed);
    return ENC_OK;
}

uint16_t encoder_sample(encoder_t *e, double theta_m_rad)
{
    int64_t k, delta, counted;

    if (!isfinite(theta_m_rad)) {
        return e->count; /* no new information */
    }
    k = enc_edge(e, theta_m_rad);
    delta = k - e->edge;
    e->edge = k;
    counted = delta;
    if ((e->p.loss_prob > 0.0) && (delta != 0)) {
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
