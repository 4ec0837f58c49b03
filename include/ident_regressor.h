/**
 * @file ident_regressor.h
 * The regression signals of the identification (method §2, paper eqs. 3-7)
 * from one ISR sample, all through identical Butterworth filters (method §5).
 *
 * Per sample:
 *   1. rotate the stator voltage of the PWM period that just ended into M-T
 *      at the frame angle of the MIDDLE of that period (method §7 point 1:
 *      the voltage is constant in the stator frame over the period while the
 *      frame turns by ws*Ts; the start angle biased Rr by +12 %):
 *          u_M =  u_alpha cos + u_beta sin,   u_T = -u_alpha sin + u_beta cos
 *      done in two steps: each sample rotates u at the frame angle theta_k
 *      of its end (the Park transform's sin/cos, no new angle), and the
 *      filter step turns the window's mean back by half the window's mean
 *      step, R(pi f_base Ts ws_mean) (a small-angle series).  Exact when the
 *      frame speed is constant over the window; a speed that varies within
 *      it, ws_k = ws_mean + e_k with sum(e_k) = 0, leaves
 *      sum_k (R(pi f_base Ts e_k) - 1) u_k, whose first order cancels for a
 *      u constant over the window: what is left is of the order of
 *      (pi f_base Ts e)^2 |u|, below 1e-7 pu for the encoder's one-count
 *      jitter of the step.
 *   2. filter seven signals with seven identical bw_filter instances, each
 *      product as ONE signal (method §7 point 2: the filter commutes with
 *      the regression only if each term of it is filtered whole):
 *          i_M, i_T, u_M, u_T, ws*i_T, ws*i_M, wr
 *   3. form the left-hand sides (eq. 5, with the corrected + in row 2):
 *          y1 = d(i_M)f/dt - (ws i_T)f,   y2 = d(i_T)f/dt + (ws i_M)f
 *      and the regressor rows (eq. 3/7; K4's column is omega_r, method §2):
 *          row1 = [i_Mf, u_Mf, c, 0],   row2 = [i_Tf, u_Tf, 0, wr_f]
 *      (c, the third regressor, is chosen by the RLS: rls.h).
 *
 * Units: currents pu of I_base, voltages pu of V_base, speeds pu of w_base,
 * time in pu of 1/w_base, so y1, y2 are pu current per pu time and the
 * regression parameters are K1_pu = K1/w_base, K2_pu = K2 V_base/(I_base
 * w_base), K3_pu = K3/(I_base w_base), K4_pu = K4/I_base.
 *
 * Multi-rate (decim = 2^n samples per filter step, ident_regressor_init):
 * steps 1 and the products of step 2 run every sample and are summed
 * (ident_regressor_accumulate, in the 15 kHz ISR; the rotor speed's mean
 * over the window comes from the encoder count directly); every decim-th sample
 * ident_regressor_filter steps the filters, at Ts' = decim Ts, on the
 * means of the sums and forms y1, y2 and the rows.  The mean over decim
 * samples is the anti-alias stage: a boxcar whose nulls lie at multiples
 * of fs/decim, exactly the frequencies that the decimation would fold onto
 * the filters' 10 Hz band; and, applied to every signal alike (each
 * product formed per sample, then averaged), it is one more common linear
 * filter, so the regression stays exact (method §7 point 2).  With decim =
 * 1, ident_regressor_step = accumulate + filter, the paper's 15 kHz path.
 *
 * Period-mean form (ident_regressor_set_period_mean; the default is the
 * paper's rows above): the rows of tools/study/regression_bias.md §5.1, the
 * regression the data satisfy exactly over each PWM period, formed per
 * window from what the window sums already hold (the trapezoid telescopes):
 *   (a) u_bar = sinc(x) u, x the half step above: the period's exact mean
 *       voltage, not its mid-angle value (sinc x = 1 - x^2/6);
 *   (b) i_bar = trapezoid + K2^ c, c = j w_s u_bar Ts^2/12: the period's
 *       mean current (the ripple's curvature), the trapezoid's window mean
 *       = the samples' mean - (i_end - i_start) / 2N; w_s i_bar alike
 *       (- w_s (i_end - i_start)/2N + w_s K2^ c, the frame speed's jitter
 *       within the window times the current's step left out: second order;
 *       the products taken per sample instead moved no result, §10);
 *       K2^ the RLS's last K2 (input k2_hat) within [0.5, 2] of the
 *       nameplate's, else the nameplate's;
 *   (c) the rotor flux / Lm in the frame, m = (i_mr, 0) + Delta: ifo's
 *       current model (input imr) corrected by Delta, the flux the mean
 *       current makes beyond what the sampled current makes:
 *         Delta += kf_N (i_bar - i_sampled - Delta) - j dtheta_sl Delta
 *       per window (kf_N = 1 - exp(-N Ts/Tr), dtheta_sl the window's slip
 *       angle; mean of i_bar - i_sampled over the window = (i_end -
 *       i_start)/2N + K2^ c);
 *   (d) m per pu of the nameplate's i_M (m_n = m / i_M,nom, near 1: the
 *       columns as large as the constant form's), filtered in three more
 *       filters (m_M, m_T, w_r m_T), w_r m_M in place of w_r, y1, y2 from
 *       the derivative of the filtered i_bar:
 *         y1 = [i_Mf, u_Mf, m_Mf, -(wr m_T)f] [K1 K2 K3n K4n]
 *         y2 = [i_Tf, u_Tf, m_Tf,  (wr m_M)f] [K1 K2 K3n K4n]
 *       (rls.h RLS_FORM_FLUX; K3n, K4n = K3, K4 at the nameplate's i_M:
 *       K3n = K3 i_M,nom / i_M).
 * Why: at high w_e Ts on a small-leakage motor the flux follows the mean,
 * not the sampled current, by (w_e Ts)^2/(12 sigma) of i_M, and w_r Tr
 * amplifies that 0.2 % into several % of Rr and Tr (regression_bias.md §4).
 * Only for ifo's frame (the flux is ifo's model plus Delta).  Known limit:
 * the flux model takes the encoder count's angle, and the rotor's start
 * within its count (half a count at most) reaches Rr and Tr through w_r Tr
 * while the flux re-aligns (regression_bias.md §10).
 *
 * Scaling and overflow of ident_regressor_step: products truncated
 * (_IQmpy; their -1/2 LSB mean bias reaches the regression as an offset
 * below 1e-6 of its smallest term: ident_regressor.c); |sin|, |cos| <= 1
 * so |u_M|, |u_T| <= |u_alpha| + |u_beta|; every input is saturated to
 * +-7 pu before it is summed (bw_filter.h's input range), so a window's
 * sum stays below 56 pu, |filtered| < 7.7 and |y1|, |y2| < 16: no wrap in
 * Q24.  The window mean is rounded (estim_ldexp), exact for decim = 1.
 */
#ifndef IDENT_REGRESSOR_H
#define IDENT_REGRESSOR_H

#include <stdint.h>
#include "IQmathLib.h"
#include "bw_filter.h"

/* The period-mean form compiled in (1, the default) or out (0: a small
 * target without the RAM for its three filters and state, the 8 KB AVR
 * co-simulation; ident_regressor_set_period_mean then refuses). */
#ifndef IDENT_PERIOD_MEAN
#define IDENT_PERIOD_MEAN 1
#endif

typedef struct {
    /* inputs */
    _iq i_m, i_t;          /* Q24 pu: stator current in M-T, sampled now (angle theta_k) */
    _iq u_alpha, u_beta;   /* Q24 pu: stator voltage applied over the period that just ended */
    _iq sin_k, cos_k;      /* Q24: sin/cos of the frame angle theta_k at this sample */
    _iq ws;                /* Q24 pu: frame (synchronous) speed over the period that just
                              ended, (theta_k - theta_k-1) / (f_base Ts) */
    _iq wr;                /* Q24 pu: rotor electrical speed over the filter step's window
                              (the mean of the window's one-period speeds: with
                              decimation the QEP gives it directly, qep_speed.h) */
    /* outputs */
    _iq u_m, u_t;          /* Q24 pu: the voltage in M-T (unfiltered) */
    _iq y1, y2;            /* Q24 pu/pu time: left-hand sides, eq. 5 */
    _iq i_mf, u_mf;        /* Q24 pu: row 1 regressors */
    _iq i_tf, u_tf, wr_f;  /* Q24 pu: row 2 regressors */
    /* inputs of the period-mean form, set before ident_regressor_filter_a */
    _iq imr;               /* Q24 pu: ifo's magnetising current i_mr (its flux / Lm) */
    _iq k2_hat;            /* Q24 pu: the RLS's latest K2 (0: none yet) */
    /* outputs of the period-mean form (0 otherwise) */
    _iq m_mf, m_tf;        /* Q24: rows 1 / 2, K3 column: the filtered flux / (Lm i_M,nom) */
    _iq wm_tf;             /* Q24 pu: row 1, K4 column: -(w_r m_T)f */
    /* parameters */
    uint16_t decim_log2;   /* filter step every 2^decim_log2 samples (0..3) */
    uint16_t period_mean;  /* 1: the period-mean form (ident_regressor_set_period_mean) */
    _iq k_half;            /* Q24: pi f_base Ts, the half step (rad) per pu of frame speed */
    _iq k_im_nom;          /* Q24 pu: the nameplate's i_M (the period-mean form's flux unit) */
#if IDENT_PERIOD_MEAN
    _iq30 k_rip;           /* Q30: (w_base Ts)^2 / 12, c per pu of w_s u */
    _iq k_slip;            /* Q24: 2^decim_log2 w_base Ts, the window's angle per pu speed */
    _iq kf_win;            /* Q24: 1 - exp(-2^decim_log2 Ts / Tr) */
    _iq k2_nom, k2_lo, k2_hi;   /* Q24 pu: the nameplate's K2, and K2^'s range (x0.5, x2) */
    _iq k_inv_im;          /* Q24: 1 / k_im_nom: the flux columns are m / i_M,nom (near 1) */
    /* state of the period-mean form */
    _iq i0_m, i0_t;        /* Q24 pu: the last sample of the previous window */
    _iq dl_m, dl_t;        /* Q24 pu: Delta, |.| < 0.1 pu (clamped) */
#endif
    /* state: the sums of the decimation window (Q24, |.| < 8 x 7 pu: each
     * input saturated to +-BW_FILTER_U_MAX, at most 8 samples) */
    _iq s_im, s_it, s_um, s_ut, s_ws_it, s_ws_im, s_ws;
    /* the seven identical filters (only f_im and f_it compute their
     * .dy output; the other five leave it at 0: bw_filter_update) */
    bw_filter_t f_im, f_it, f_um, f_ut, f_ws_it, f_ws_im, f_wr;
#if IDENT_PERIOD_MEAN
    /* the period-mean form's three more (f_wr then filters w_r m_M) */
    bw_filter_t f_mm, f_mt, f_wmt;
#endif
} ident_regressor_t;

/** Largest decimation, log2 (8 samples: the sums stay inside Q24). */
#define IDENT_REGRESSOR_DECIM_LOG2_MAX 3u

/** Initialise the seven filters (bw_filter_init arguments, the filters at
 *  Ts_s 2^decim_log2) for a filter step every 2^decim_log2 samples of
 *  period Ts_s; returns the first error (the struct is then zeroed;
 *  decim_log2 > IDENT_REGRESSOR_DECIM_LOG2_MAX: BW_FILTER_ERR_TS). */
bw_filter_status_t ident_regressor_init(ident_regressor_t *r, float wc_rad_s,
                                        uint16_t n_pass, float Ts_s,
                                        float w_base_rad_s, uint16_t decim_log2);

/** ident_regressor_init's check of its arguments alone (no struct): its
 *  decimation, then bw_filter_check at the filters' step Ts_s 2^decim_log2.
 *  The configuration's table of limits calls it too (drive_limits.c).
 *  Float: init only. */
bw_filter_status_t ident_regressor_check(float wc_rad_s, uint16_t n_pass, float Ts_s,
                                         float w_base_rad_s, uint16_t decim_log2);

/** Switch to the period-mean form (file comment) for ifo's frame with the
 *  rotor time constant Tr_s, the nameplate's K2 in pu (k2_nom_pu =
 *  V_base / (sigma Ls I_base w_base)) and its magnetising current in pu
 *  (im_nom_pu); after ident_regressor_init, with the same Ts_s and w_base.
 *  Float, once.  Returns 0, or 1 (nothing changed) for Tr_s not above
 *  2^decim_log2 Ts_s, k2_nom_pu not in (0, 16) (the RLS's range) or
 *  im_nom_pu not in [0.05, 4). */
int16_t ident_regressor_set_period_mean(ident_regressor_t *r, float Tr_s, float k2_nom_pu,
                                        float im_nom_pu, float Ts_s, float w_base_rad_s);

/** Zero every filter state and sum (e.g. before a new identification run). */
void ident_regressor_reset(ident_regressor_t *r);

/* One input into its window sum: saturated as the filter would, so that
 * 8 of them stay below 56 pu (Q24). */
static inline _iq ident_in(_iq x)
{
    return _IQsat(x, _IQ(BW_FILTER_U_MAX), _IQ(-BW_FILTER_U_MAX));
}

/** Every sample: rotate u into M-T, form the products, add the six
 *  signals to the window sums (inputs saturated to +-BW_FILTER_U_MAX); the
 *  seventh, wr, is set as the window's mean before the filter step. */
static inline void ident_regressor_accumulate(ident_regressor_t *r)
{
    /* the frame speed within the filters' range: |ws i| <= 7 * 2.5 stays
     * inside Q24 (a larger ws is an angle jump, not a speed) */
    const _iq ws = ident_in(r->ws);
    /* Park rotation at theta_k (the half-period turn back to the middle of
     * the period follows per window, ident_regressor_filter);
     * Q24*Q24 -> Q24, |u| < 64 pu */
    r->u_m = _IQmpy(r->u_alpha, r->cos_k) + _IQmpy(r->u_beta, r->sin_k);
    r->u_t = _IQmpy(r->u_beta, r->cos_k) - _IQmpy(r->u_alpha, r->sin_k);

    r->s_im += ident_in(r->i_m);
    r->s_it += ident_in(r->i_t);
    r->s_um += ident_in(r->u_m);
    r->s_ut += ident_in(r->u_t);
    r->s_ws += ws;
    /* the products are filtered as single signals (method §7 point 2):
     * each formed per sample, then averaged (Q24*Q24 -> Q24) */
    r->s_ws_it += ident_in(_IQmpy(ws, r->i_t));
    r->s_ws_im += ident_in(_IQmpy(ws, r->i_m));
}

/** Every 2^decim_log2 samples, after that many accumulate calls: the
 *  window means (rounded) through the filters, y1, y2 and the regressors;
 *  the sums restart at 0.  = ident_regressor_filter_a, then _b. */
void ident_regressor_filter(ident_regressor_t *r);

/** The filter step in three parts, for three ISRs of the slow schedule:
 *  (a) the window means (the sums restart at 0: accumulate may run between
 *  the parts) and the i_M, i_T filters (with their derivatives); (b) the
 *  u_M, u_T and w_s i_T filters; (c) the w_s i_M and w_r filters, y1, y2
 *  and the regressors.  a, b, c = ident_regressor_filter, bit for bit. */
void ident_regressor_filter_a(ident_regressor_t *r);
void ident_regressor_filter_b(ident_regressor_t *r);
void ident_regressor_filter_c(ident_regressor_t *r);

/** accumulate + filter: one sample of the undecimated path (decim_log2 = 0). */
void ident_regressor_step(ident_regressor_t *r);

#endif /* IDENT_REGRESSOR_H */
