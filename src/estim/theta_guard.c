/* Estimator safeguard: hold the last good theta.  See theta_guard.h. */
#include "theta_guard.h"

#include <math.h>
#include <string.h>

/* the model's signs: K1 < 0, K2 > 0, K3 (K3') > 0, K4 < 0 */
static const int16_t k_sign[RLS_N] = {-1, 1, 1, -1};

theta_guard_status_t theta_guard_check(const float k_nom[RLS_N], float span, uint16_t *bad_k)
{
    uint16_t i;
    if (bad_k != NULL) {
        *bad_k = RLS_N;
    }
    if (!(span > 1.0f) || !(span < 1e6f)) {
        return THETA_GUARD_ERR_ARG;
    }
    for (i = 0u; i < RLS_N; i++) {
        float m = (float)k_sign[i] * k_nom[i];
        if (!(m > 0.0f) || !(m < RLS_THETA_MAX)) {
            if (bad_k != NULL) {
                *bad_k = i;
            }
            return THETA_GUARD_ERR_ARG;
        }
    }
    return THETA_GUARD_OK;
}

theta_guard_status_t theta_guard_init(theta_guard_t *g, const float k_nom[RLS_N], float span)
{
    uint16_t i;
    memset(g, 0, sizeof *g);
    if (theta_guard_check(k_nom, span, NULL) != THETA_GUARD_OK) {
        return THETA_GUARD_ERR_ARG;
    }
    for (i = 0u; i < RLS_N; i++) {
        float m = (float)k_sign[i] * k_nom[i];
        float hi;
        hi = fminf(m * span, RLS_THETA_MAX);   /* the RLS saturates theta there anyway */
        g->lo[i] = _IQ(m / span);
        g->hi[i] = _IQ(hi);
        g->sign[i] = k_sign[i];
    }
    g->required = 0xFu;
    return THETA_GUARD_OK;
}

theta_guard_status_t theta_guard_set_required(theta_guard_t *g, uint16_t mask)
{
    uint16_t i;
    if (mask == 0u || (mask & ~0xFu) != 0u) {
        return THETA_GUARD_ERR_ARG;
    }
    /* a K that is not required gets the whole range of the RLS's theta
     * (|theta| <= RLS_THETA_MAX < 16, either sign): the per-sample check
     * stays two compares per K, with no mask test in the ISR */
    for (i = 0u; i < RLS_N; i++) {
        if ((mask & (uint16_t)(1u << i)) == 0u) {
            g->lo[i] = -_IQ(16.0);
            g->hi[i] = _IQ(16.0);
        }
    }
    g->required = mask;
    return THETA_GUARD_OK;
}

void theta_guard_reset(theta_guard_t *g)
{
    uint16_t i;
    for (i = 0u; i < RLS_N; i++) {
        g->theta_good[i] = _IQ(0.0);
    }
    g->good = 0u;
    g->held = 0u;
}

static uint16_t plausible(const theta_guard_t *g)
{
    uint16_t i;
    for (i = 0u; i < RLS_N; i++) {
        /* |theta| < 16 pu (RLS saturation), so negating cannot wrap */
        _iq m = (g->sign[i] > 0) ? g->theta[i] : -g->theta[i];
        if (m < g->lo[i] || m > g->hi[i]) {
            return 0u;
        }
    }
    return 1u;
}

void theta_guard_step(theta_guard_t *g)
{
    uint16_t i;
    if (g->updated == 0u) {
        return;                       /* nothing new: keep the last verdict */
    }
    if (g->windup_hold == 0u && plausible(g) != 0u) {
        for (i = 0u; i < RLS_N; i++) {
            g->theta_good[i] = g->theta[i];
        }
        g->good = 1u;
        g->held = 0u;
    } else {
        g->held = 1u;
        if (g->reject_count < 0xFFFFFFFFu) {
            g->reject_count++;
        }
    }
}
