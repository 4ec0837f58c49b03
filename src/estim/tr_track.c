/* Rotor-time-constant tracker from the observer's slip.  See tr_track.h. */
#include "tr_track.h"

#include <math.h>

#include "estim_bfp.h"

#define P_MIN _IQ(1.0e-6)   /* P never reaches 0 (it would freeze theta); 16 LSB in Q24 */

/* inline: nine calls per tracker update in the ISR */
static inline _iq clamp(_iq x, _iq lo, _iq hi, uint32_t *count)
{
    if (x > hi) {
        estim_count(count);
        return hi;
    }
    if (x < lo) {
        estim_count(count);
        return lo;
    }
    return x;
}

float tr_track_settle_s(float memory_s, float tr_s)
{
    /* NaN fails every comparison; an infinity the last */
    if (!(memory_s > 0.0f) || !(tr_s > 0.0f) || !(memory_s + tr_s < 1.0e30f)) {
        return 0.0f;
    }
    return TR_TRACK_SETTLE_TR * tr_s + TR_TRACK_SETTLE_MEMORIES * memory_s;
}

tr_track_status_t tr_track_init(tr_track_t *t, float Ts_s, uint16_t decim, float lpf_Hz,
                                float memory_s, float phi_min_pu, float theta_min,
                                float theta_max, float theta0)
{
    float x;
    float lambda;
    float p0;

    t->kf = t->lambda = t->p_max = t->p0 = t->phi_min = _IQ(0.0);
    t->theta_min = t->theta_max = _IQ(0.0);
    t->decim = 1u;
    t->enable = 0u;
    tr_track_restart(t, _IQ(0.0));
    x = 6.2831853f * lpf_Hz * Ts_s;
    if (!(Ts_s > 0.0f) || decim < 1u || decim > 64u || !(x > 0.0f && x <= 0.5f)) {
        return TR_TRACK_ERR_RATE;
    }
    if (!(memory_s >= 0.2f && memory_s <= 20.0f)) {
        return TR_TRACK_ERR_MEMORY;
    }
    lambda = 1.0f - (float)decim * Ts_s / memory_s;
    if (!(lambda >= 0.9f)) {
        return TR_TRACK_ERR_MEMORY;
    }
    if (!(theta_min > 0.0f && theta_min < theta_max && theta_max <= 30.0f &&
          theta0 >= theta_min && theta0 <= theta_max)) {
        return TR_TRACK_ERR_RANGE;
    }
    if (!(phi_min_pu > 0.0f && phi_min_pu <= 1.0f)) {
        return TR_TRACK_ERR_PHI;
    }
    t->kf = _IQ(1.0f - expf(-x));
    t->lambda = _IQ(lambda);
    t->p_max = _IQ(TR_TRACK_P_MAX);
    /* the steady-state P of a forgetting RLS at the least excitation,
     * (1 - lambda) / phi_min^2: the estimate moves with the memory time
     * from the first update, without the jump of a huge P(0) */
    p0 = (1.0f - lambda) / (phi_min_pu * phi_min_pu);
    t->p0 = _IQ(fminf(p0, TR_TRACK_P_MAX));
    t->phi_min = _IQ(phi_min_pu);
    t->theta_min = _IQ(theta_min);
    t->theta_max = _IQ(theta_max);
    t->decim = decim;
    tr_track_restart(t, _IQ(theta0));
    return TR_TRACK_OK;
}

void tr_track_restart(tr_track_t *t, _iq theta0)
{
    uint32_t dummy = 0u;
    t->theta = (t->theta_max > _IQ(0.0)) ? clamp(theta0, t->theta_min, t->theta_max, &dummy)
                                         : _IQ(0.0);
    t->y_f = t->phi_f = _IQ(0.0);
    t->n_updates = 0u;
    t->sat_count = 0u;
    t->held = 1u;
    t->p = t->p0;
    t->div = 0u;
}

/* The scalar RLS update with forgetting (file comment). */
static void rls_update(tr_track_t *t)
{
    _iq phi = clamp(t->phi_f, -_IQ(TR_TRACK_PHI_MAX), _IQ(TR_TRACK_PHI_MAX), &t->sat_count);
    _iq den;
    _iq k;
    _iq e;

    if (_IQabs(phi) < t->phi_min) {
        t->held = 1u;   /* wind-up guard: no information, no forgetting */
        return;
    }
    t->held = 0u;
    /* P phi^2 <= 4 * 4 = 16; den in [0.9, 17] */
    den = t->lambda + _IQmpy(t->p, _IQmpy(phi, phi));
    /* |k| = P |phi| / (lambda + P phi^2) <= sqrt(P / lambda) / 2 <= 1.06 */
    k = _IQdiv(_IQmpy(t->p, phi), den);
    /* a-priori error: |y_f| <= 64, |phi theta| <= 2 * 30: < 128 */
    e = clamp(t->y_f - _IQmpy(phi, t->theta), -_IQ(8.0), _IQ(8.0), &t->sat_count);
    /* |k e| <= 8.5 */
    t->theta = clamp(t->theta + _IQrmpy(k, e), t->theta_min, t->theta_max, &t->sat_count);
    t->p = _IQdiv(t->p, den);
    if (t->p > t->p_max) {
        t->p = t->p_max;
    } else if (t->p < P_MIN) {
        t->p = P_MIN;
    } else {
        /* in range */
    }
    estim_count(&t->n_updates);
}

void tr_track_step(tr_track_t *t)
{
    uint32_t *sc = &t->sat_count;
    _iq wsl = clamp(t->w_sl, -_IQ(TR_TRACK_IN_WSL_MAX), _IQ(TR_TRACK_IN_WSL_MAX), sc);
    _iq pa = clamp(t->psi_alpha, -_IQ(TR_TRACK_IN_PSI_MAX), _IQ(TR_TRACK_IN_PSI_MAX), sc);
    _iq pb = clamp(t->psi_beta, -_IQ(TR_TRACK_IN_PSI_MAX), _IQ(TR_TRACK_IN_PSI_MAX), sc);
    _iq ia = clamp(t->i_alpha, -_IQ(TR_TRACK_IN_I_MAX), _IQ(TR_TRACK_IN_I_MAX), sc);
    _iq ib = clamp(t->i_beta, -_IQ(TR_TRACK_IN_I_MAX), _IQ(TR_TRACK_IN_I_MAX), sc);
    /* |psi.i|, |psi x i| <= 2 * 16 = 32; |y| <= 64 (y - y_f: < 128) */
    _iq dot = _IQmpy(pa, ia) + _IQmpy(pb, ib);
    _iq crs = _IQmpy(pa, ib) - _IQmpy(pb, ia);
    _iq y = _IQmpy(wsl, dot);

    /* same first-order low-pass on both sides; |input - state| < 128 */
    t->y_f += _IQrmpy(t->kf, y - t->y_f);
    t->phi_f += _IQrmpy(t->kf, crs - t->phi_f);
    if (t->enable == 0u) {
        t->div = 0u;
        return;
    }
    if (++t->div >= t->decim) {
        t->div = 0u;
        rls_update(t);
    }
}
