/* Model-based current plausibility.  See current_model_check.h. */
#include "current_model_check.h"

#include <math.h>
#include <string.h>

cmc_status_t current_model_check_init(current_model_check_t *c, float Ts_s, uint16_t slots,
                                      float w_base_rad_s, float tau_r_s, float tau_seq_s,
                                      float r_max_pu, float k_neg, float d_max_pu,
                                      float ws_min_pu)
{
    float Tw;
    memset(c, 0, sizeof *c);
    c->fault = 1u;
    if (!(Ts_s > 0.0f) || slots < 1u || slots > CMC_N_MAX || !(w_base_rad_s > 0.0f)) {
        return CMC_ERR_ARG;
    }
    Tw = Ts_s * (float)slots;
    if (!(tau_r_s >= Tw) || !(tau_seq_s >= Tw) || !(r_max_pu > 0.0f) || !(r_max_pu < 1.0f) ||
        !(k_neg > 0.0f) || !(k_neg < 1.0f) || !(d_max_pu > 0.0f) || !(d_max_pu < 1.0f) ||
        !(ws_min_pu > 0.0f) || !(ws_min_pu < 4.0f) || !(Ts_s * w_base_rad_s < 0.05f) ||
        !(d_max_pu * tau_r_s * w_base_rad_s < 1.0f)) {
        return CMC_ERR_ARG;
    }
    c->ts = _IQ(Ts_s * w_base_rad_s);
    c->lambda = _IQ(expf(-Tw / tau_r_s));
    /* the sequence low-passes step every second window (sequences()) */
    c->k_seq = _IQ(1.0f - expf(-2.0f * Tw / tau_seq_s));
    c->r_max = _IQ(r_max_pu);
    c->k_neg = _IQ(k_neg);
    c->d_max_tau = _IQ(d_max_pu * tau_r_s * w_base_rad_s);   /* < 1: (Rs d_max tau)^2 < 16 */
    c->ws_min = _IQ(ws_min_pu);
    {
        const float wt = ws_min_pu * tau_seq_s * w_base_rad_s;   /* pu speed x pu time */
        c->k_qneg = _IQ(fminf(CMC_Q_LEAK / (2.0f * wt), 1.0f));
        c->k_qdc = _IQ(fminf(CMC_Q_LEAK / wt, 1.0f));
    }
    c->seq_settle = (uint16_t)fminf(3.0f * tau_seq_s / Tw + 0.5f, 60000.0f);
    c->fault = 0u;
    return CMC_OK;
}

cmc_status_t current_model_check_set_bridge(current_model_check_t *c, float e_pole_pu,
                                            float k_bridge, float tau_r_s, float w_base_rad_s)
{
    const float a = k_bridge * e_pole_pu * tau_r_s * w_base_rad_s;
    if (!(a >= 0.0f) || !(a <= CMC_BRIDGE_ALLOW_MAX)) {
        return CMC_ERR_ARG;   /* also NaN; the allowance kept */
    }
    c->bridge_allow = _IQ(a);
    return CMC_OK;
}

static void clear_state(current_model_check_t *c)
{
    c->r_alpha = c->r_beta = _IQ(0.0);
    c->neg_alpha = c->neg_beta = _IQ(0.0);
    c->dc_alpha = c->dc_beta = _IQ(0.0);
    c->pos_d = c->pos_q = _IQ(0.0);
    c->r2 = c->neg2 = c->dc2 = c->q2 = _IQ(0.0);
    c->lag_d = c->lag_q = _IQ(0.0);
    c->primed = 0u;
    c->at_speed = 0u;
    c->model_n = 0u;
    c->phase = 0u;
    c->seq_due = 0u;
    c->slow = 0u;
}

void current_model_check_reset(current_model_check_t *c)
{
    clear_state(c);
    c->fault = 0u;
    c->cause = 0u;
}

/* One component of v (pu flux, see the header): |each term| < 32 pu. */
static _iq mismatch(const current_model_check_t *c, _iq su, _iq i, _iq i_prev, _iq psi,
                    _iq psi_prev, _iq rs_ts_n_half)
{
    return _IQmpy(c->ts, su)                               /* |su| <= 32, ts < 0.05 */
           - _IQmpy(rs_ts_n_half, i + i_prev)              /* <= 4 x 0.05 x 8 / 2 x 8 */
           - (psi - psi_prev)                              /* <= 8 */
           - _IQmpy(c->sigma_ls, i - i_prev);              /* <= 4 x 8 */
}

/* x += k (target - x), truncated: the low-passes' -1/2 LSB bias per step
 * over k (k >= 0.005) is below 1e-5 pu, far below every level; |target - x|
 * < 12 pu, the product < 12. */
static _iq low_pass(_iq x, _iq target, _iq k)
{
    return x + _IQmpy(k, target - x);
}

/* The sequence tests, split over two windows so that no call carries both
 * halves (current_model_check.h: cost): phase 0 follows the positive
 * sequence, phase 1 takes it off and judges the rest.  On the last
 * residual's window: r, the level thr, the currents, Rs, sigma Ls and the
 * angle as current_model_check_residual left them. */
static void sequences(current_model_check_t *c)
{
    const _iq cs = c->cos_t, sn = c->sin_t;
    const _iq r_a = c->r_alpha, r_b = c->r_beta, thr = c->thr;
    const _iq i_a = c->i_alpha_prev, i_b = c->i_beta_prev;
    const _iq rs = c->rs, sls = c->sigma_ls;
    if (c->phase == 0u) {
        /* the positive sequence (a model error: the fundamental): r e^{-j theta}
         * low-passed; taken off below, so that the other low-passes do not
         * have to reject a large one (the 15 kW motor with the believed Lm
         * 30 % low: |r| 30 A at 0.44 pu, whose leakage alone read as a 4.6 A
         * offset) */
        const _iq e_d = _IQmpy(r_a, cs) + _IQmpy(r_b, sn) - c->pos_d;   /* |.| < 8 */
        const _iq e_q = _IQmpy(r_b, cs) - _IQmpy(r_a, sn) - c->pos_q;
        c->pos_d += _IQmpy(c->k_seq, e_d);
        c->pos_q += _IQmpy(c->k_seq, e_q);
        /* what the positive sequence has not followed, low-passed in its own
         * frame: a model's transient (slow there) stays, a sensor's negative
         * sequence (2 w_e there) and offset (w_e) are filtered out: the size
         * of what leaks into the other low-passes (CMC_Q_LEAK) */
        c->lag_d = low_pass(c->lag_d, e_d, c->k_seq);   /* |.| < 8: |e| < 8 */
        c->lag_q = low_pass(c->lag_q, e_q, c->k_seq);
        c->phase = 1u;
        return;
    }
    c->phase = 0u;
    {
        /* r - pos (|.| < 8: |r| <= 4, |pos| <= 4) */
        const _iq q_a = r_a - (_IQmpy(c->pos_d, cs) - _IQmpy(c->pos_q, sn));
        const _iq q_b = r_b - (_IQmpy(c->pos_d, sn) + _IQmpy(c->pos_q, cs));
        if (c->model_n >= c->seq_settle) {
            /* MISMATCH on what the positive sequence's phasor has not
             * followed (it lags by tau_seq): a model error of the back-EMF
             * is a slow positive sequence, a sensor that fails is a step;
             * so without r_allow_emf (|q| saturated to 4: the square < 32,
             * the level's < 36).  At any speed once the positive sequence
             * has followed for 3 tau_seq (at standstill it is the DC, a
             * model error there a slow one too): below the sequence gate
             * the back-EMF allowance is the only other test's, and it grows
             * with a frame speed that the failing sensor corrupts (phase b
             * lost 0.2 s into a 0.75 kW motor's first acceleration, at
             * 0.19 pu: the comparator cut the bridge first) */
            const _iq qa = _IQsat(q_a, _IQ(4.0), _IQ(-4.0));
            const _iq qb = _IQsat(q_b, _IQ(4.0), _IQ(-4.0));
            c->q2 = _IQmpy(qa, qa) + _IQmpy(qb, qb);
            if (c->q2 > _IQmpy(thr, thr)) {
                c->fault = 1u;
                c->cause |= CMC_MISMATCH;
            }
        }
        if (c->slow != 0u) {
            return;   /* UNBALANCE and OFFSET wait for the speed gate */
        }
        /* (r - pos) e^{+j theta}: the negative sequence at DC; r - pos: the
         * DC (an offset) */
        c->neg_alpha = low_pass(c->neg_alpha, _IQmpy(q_a, cs) - _IQmpy(q_b, sn), c->k_seq);
        c->neg_beta = low_pass(c->neg_beta, _IQmpy(q_a, sn) + _IQmpy(q_b, cs), c->k_seq);
        c->dc_alpha = low_pass(c->dc_alpha, q_a, c->k_seq);
        c->dc_beta = low_pass(c->dc_beta, q_b, c->k_seq);
    }
    c->neg2 = _IQmpy(c->neg_alpha, c->neg_alpha) + _IQmpy(c->neg_beta, c->neg_beta);
    c->dc2 = _IQmpy(c->dc_alpha, c->dc_alpha) + _IQmpy(c->dc_beta, c->dc_beta);
    if (c->at_speed >= c->seq_settle && c->model_n >= c->seq_settle) {
        /* the levels, each plus what the low-passes let through of the
         * positive sequence, CMC_LEAK of its L1 size (between 1 and sqrt(2)
         * |pos|; |pos| <= 4: leak < 0.5): sigma Ls k_neg |i| (kn saturated
         * to 1, |i|^2 < 10 with the currents within 2.2 pu: n2 < 10) and
         * Rs d_max tau_r (< 4); both plus the bridge's allowance (< 0.5,
         * current_model_check_set_bridge): kd < 5, kd^2 < 25 */
        const _iq leak = _IQmpy(_IQ(CMC_LEAK), _IQabs(c->pos_d) + _IQabs(c->pos_q));
        /* the positive sequence's lag, its L1 size (between 1 and sqrt(2) of
         * the magnitude, as the leak's; |lag| < 8 each: < 16) */
        const _iq lag = _IQabs(c->lag_d) + _IQabs(c->lag_q);
        const _iq leak_neg = leak + c->bridge_allow;   /* < 0.5 + 0.5 */
        const _iq kn = _IQsat(_IQmpy(sls, c->k_neg), _IQ(1.0), 0);
        /* + what the transients leak, the lag times the low-passes' gain at
         * the gate (CMC_Q_LEAK; k_q <= 1): < 16 each; the sums below 4 + 1 +
         * 16, saturated to 11 (their squares < 128) */
        const _iq leak_nq = _IQsat(leak_neg + _IQmpy(lag, c->k_qneg), _IQ(11.0), 0);
        const _iq kd = _IQsat(_IQmpy(rs, c->d_max_tau) + leak_neg + _IQmpy(lag, c->k_qdc),
                              _IQ(11.0), 0);
        const _iq n2 = _IQmpy(_IQmpy(kn, kn), _IQmpy(i_a, i_a) + _IQmpy(i_b, i_b));
        /* kept for the caller's margins (the tests compare with these) */
        c->neg_level2 = n2 + _IQmpy(leak_nq, leak_nq);
        c->dc_level2 = _IQmpy(kd, kd);
        if (c->neg2 > c->neg_level2) {
            c->fault = 1u;
            c->cause |= CMC_UNBALANCE;
        }
        if (c->dc2 > c->dc_level2) {
            c->fault = 1u;
            c->cause |= CMC_OFFSET;
        }
    }
}

void current_model_check_residual(current_model_check_t *c)
{
    /* the Clarke currents are within 2.2 pu (the phase sensors' range,
     * phase_current.h), Rs and sigma Ls within [0, 4] pu (their sources:
     * drive_init, flux_obs_set_*): only the flux, whose model may hold more
     * (flux_obs.h: up to 60 pu), is saturated */
    const _iq i_a = c->i_alpha, i_b = c->i_beta;
    const _iq p_a = _IQsat(c->psi_alpha, _IQ(CMC_IN_MAX), _IQ(-CMC_IN_MAX));
    const _iq p_b = _IQsat(c->psi_beta, _IQ(CMC_IN_MAX), _IQ(-CMC_IN_MAX));
    const _iq rs = c->rs, sls = c->sigma_ls;
    const uint16_t n = c->n;
    /* every condition a 0/1 value, combined without a branch each */
    const uint16_t window_ok = (uint16_t)((uint16_t)(c->n_off == 0u) & (uint16_t)(n >= 1u) &
                                          (uint16_t)(n <= CMC_N_MAX));
    const _iq su_a = c->su_alpha, su_b = c->su_beta;
    const uint16_t rebase = c->rebase;

    c->su_alpha = c->su_beta = _IQ(0.0);
    c->n = 0u;
    c->n_off = 0u;
    c->rebase = 0u;
    if ((uint16_t)(c->active & window_ok & c->primed) == 0u) {
        /* re-armed: the next window starts from this sample */
        clear_state(c);
        c->primed = (uint16_t)(c->active != 0u);
    } else if (rebase != 0u) {
        /* the model stepped in this window: its flux step is not the
         * motor's; the residual only decays (|r| <= 4: no overflow) and the
         * next window starts from this sample.  The sequence tests run on:
         * a pass's blend is 0.1 s of small steps, which their low-passes
         * follow (CMC_Q_LEAK), and a sensor failing in it must still be
         * found (a restart at each step left a gain error injected in the
         * wrong-nameplate paper motor's SETTLE unseen through REFINE, the
         * observer's frame collapsed: STALL instead of CURRENT_SENSOR) */
        c->r_alpha = _IQmpy(c->lambda, c->r_alpha);
        c->r_beta = _IQmpy(c->lambda, c->r_beta);
        /* the tests of r - pos wait for the positive sequence to follow the
         * new model's error (r - pos is that error's step: a blend on the
         * family's 4 kW 2-pole with a nameplate 30 % off latched the fast
         * MISMATCH in 76 of 144 healthy runs; the 15 kW 6-pole's RUN, whose
         * first sets blend the last pass's model and hand the frame over,
         * OFFSET 0.1 s into it), and UNBALANCE and OFFSET start afresh */
        c->model_n = 0u;
        c->neg_alpha = c->neg_beta = _IQ(0.0);
        c->dc_alpha = c->dc_beta = _IQ(0.0);
        c->lag_d = c->lag_q = _IQ(0.0);
    } else {
        _iq r_a, r_b, thr, thr_all;
        /* Rs n Ts / 2 (Q24; <= 4 x 8 x 0.05 / 2 = 0.8) */
        const _iq k_rs = _IQmpyI32(_IQmpy(rs, c->ts), (int32_t)n) / 2;
        r_a = c->r_alpha + mismatch(c, su_a, i_a, c->i_alpha_prev, p_a, c->psi_alpha_prev, k_rs);
        r_b = c->r_beta + mismatch(c, su_b, i_b, c->i_beta_prev, p_b, c->psi_beta_prev, k_rs);
        /* saturated before the leak (|r| + |v| < 68 fits; lambda < 1 keeps
         * the product inside the bound) */
        r_a = _IQmpy(c->lambda, _IQsat(r_a, _IQ(CMC_R_MAX), _IQ(-CMC_R_MAX)));
        r_b = _IQmpy(c->lambda, _IQsat(r_b, _IQ(CMC_R_MAX), _IQ(-CMC_R_MAX)));
        c->r_alpha = r_a;
        c->r_beta = r_b;
        c->r2 = _IQmpy(r_a, r_a) + _IQmpy(r_b, r_b);            /* < 32 */
        /* the level with what the caller cannot rule out (r_allow, r_allow_emf
         * within [0, 2] by the caller's contract): thr < 4 + 2, thr_all < 8,
         * its square < 64 */
        thr = _IQmpy(sls, c->r_max) + c->r_allow;
        c->thr = thr;
        thr_all = thr + c->r_allow_emf;
        if (c->r2 > _IQmpy(thr_all, thr_all)) {
            c->fault = 1u;
            c->cause |= CMC_MISMATCH;
        }
        /* the sequence tests' halves (current_model_check_half, phase
         * c->phase): the positive sequence at any speed; the negative one
         * and the DC while the frame turns fast enough for the low-passes
         * to separate DC, w_e and 2 w_e */
        c->seq_due = 1u;
        c->slow = (uint16_t)(_IQabs(c->ws) <= c->ws_min);
        if (c->slow != 0u) {
            /* too slow: DC, w_e and 2 w_e too close; UNBALANCE and OFFSET
             * start again at speed (their low-passes and settling count;
             * the positive sequence and the test of what it has not
             * followed run on at any speed) */
            c->neg_alpha = c->neg_beta = _IQ(0.0);
            c->dc_alpha = c->dc_beta = _IQ(0.0);
            c->neg2 = c->dc2 = _IQ(0.0);
            c->at_speed = 0u;
        }
    }
    c->i_alpha_prev = i_a;
    c->i_beta_prev = i_b;
    c->psi_alpha_prev = p_a;
    c->psi_beta_prev = p_b;
}

void current_model_check_half(current_model_check_t *c, uint16_t phase)
{
    if ((uint16_t)(c->seq_due & (uint16_t)(c->phase == phase)) == 0u) {
        return;
    }
    c->seq_due = 0u;
    sequences(c);
    if (c->at_speed < c->seq_settle && c->slow == 0u) {
        c->at_speed++;
    }
    if (c->model_n < c->seq_settle) {
        c->model_n++;
    }
}

void current_model_check_step(current_model_check_t *c)
{
    current_model_check_residual(c);
    current_model_check_half(c, c->phase);
}
