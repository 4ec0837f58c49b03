/**
 * @file bw_filter.h
 * Second-order Butterworth low-pass solved by improved Euler (method §5,
 * paper eqs. 11-18): gives the filtered signal AND its time derivative, so
 * that the regression (method §2) needs no differencing.
 *
 *   H(s) = Wc^2 / (s^2 + sqrt(2) Wc s + Wc^2)                  (eq. 12, b0 = 1)
 *   x1' = x2,  x2' = -Wc^2 x1 - sqrt(2) Wc x2 + Wc^2 u         (eqs. 13-14)
 *   predictor x_p = x(k-1) + h f(x(k-1), u(k))                 (eqs. 15-16)
 *   corrector x   = x(k-1) + h/2 [f(x(k-1), u(k)) + f(x_p, u(k))],
 *                   applied N times, x_p <- latest x            (eqs. 17-18)
 *
 * with h = Ts in pu time (h = Ts * w_base), Wc in pu (Wc / w_base), so the
 * derivative output is d/dt_pu = (1/w_base) d/dt.
 *
 * Scaled coordinates.  The state is s = [x1, z2] with z2 = x2 / Wc_pu (the
 * derivative divided by the cut-off): both components then have the range of
 * the signal itself, independent of Wc.  In these coordinates
 *     f = Wc_pu * Fn * (s - [u, 0]),   Fn = [0 1; -1 -sqrt(2)],
 * so the scheme depends on a = Wc * Ts (dimensionless) and N only.
 *
 * The N-pass map.  The filter is linear time-invariant, so the N corrector
 * passes are one fixed affine map.  With d = s(k-1) - [u(k), 0] (deviation
 * from the equilibrium of u(k)), M = (a/2) Fn and the predictor increment
 * delta0 = a Fn d, each pass gives delta_j = a Fn d + M delta_(j-1), hence
 *     s(k) = s(k-1) + D d,    D = (I + M + ... + M^N) a Fn.
 * bw_filter_init computes D once (Horner, in float).  Written as an
 * increment on the deviation, the map has two exact properties the plain
 * form x(k) = A x(k-1) + B u(k) loses in rounded arithmetic: the DC gain is
 * exactly 1 (d = 0, z2 = 0 is a fixed point to the bit), and D's small
 * entries are computed and stored with full relative precision (A11 = 1 -
 * 9e-6 would keep only 17 significant bits of its distance to 1).
 * bw_filter_step uses the map (4 IQmath multiplies and a rounded
 * Q27 -> Q26 change of format, + 1 for dy); bw_filter_step_npass runs the
 * literal predictor + N corrector passes (7 + 5N multiplies) as the
 * reference the map is tested against.
 *
 * Fixed point (IQ_MATH).  State s in Q27 (range +-16, LSB 7.5e-9 pu = 1/8
 * LSB of Q24).  The input is saturated to +-BW_FILTER_U_MAX = 7 pu; the
 * discrete filter's l1 gain (sum of |impulse response|) is < 1.09 for x1
 * and < 1.0 for z2 (Butterworth step overshoot 4.3 %), so |x1| < 7.7 and
 * |z2| < 7, and the deviation |x1 - u| < 14.7 stays inside Q27.  Products
 * are rounded (round half up, bit for bit _IQ30rmpy, computed as the
 * truncating _IQ29mpy one bit finer + a rounding shift, which costs 5
 * cycles + 2 ALU operations on the C28x instead of the 22-cycle _IQrmpy
 * library call): truncation would bias every
 * update by -1/2 LSB, and the filter integrates its increments; with the DC
 * gain of the filter from the increment to x1 (about 1/a + sqrt(2)/a = 580
 * at a = 4.2e-3) that is a steady bias of ~600 LSB Q27 = 70 LSB Q24; with
 * rounding the bias is zero and the rounding noise ~0.5 LSB Q24 rms.
 * Coefficients in Q30 (relative resolution 2.5e-7 for |D| ~ a).
 * Dead band: a rounded increment a*w vanishes for |w| < 1/(2a) LSB, so a
 * settling state stops within |x1 - u| <= 290 LSB27 = 37 LSB24 (2.2e-6 pu)
 * of the equilibrium (at a = 4.19e-3; tests/estim measure 35); it is
 * symmetric (zero mean) with rounding, one-sided (-51 LSB24) with
 * truncation.  A wider state would need 64-bit arithmetic.
 *
 * Scaling and overflow of bw_filter_step: input saturated (bounded as
 * above, so no internal sum can overflow); outputs y = x1 in Q24 (the 3
 * extra state bits floor-shifted off: -7/16 LSB Q24, not accumulated) and
 * dy = Wc_pu * z2 in Q24 (_IQmpyIQX, truncated, <= 1 LSB).
 */
#ifndef BW_FILTER_H
#define BW_FILTER_H

#include <stdint.h>
#include "IQmathLib.h"
#include "iq_rmpy.h"

/** Input saturation (pu): keeps the Q27 state in range (see above). */
#define BW_FILTER_U_MAX 7.0f
/** Largest a = Wc * Ts accepted (the corrector iteration converges for
 *  a/2 * |eig(Fn)| = a/2 < 1; 0.3 keeps it a fast contraction and bounds
 *  |D12|, |D21| <= a, which the one-bit-finer rounded products of
 *  bw_filter_step need: |D21 (d + c2 z2)| < 25 a < 8).  A cut-off of 700 Hz
 *  at 15 kHz; the paper's is a = 4.2e-3. */
#define BW_FILTER_A_MAX 0.3f
/** Largest number of corrector passes accepted. */
#define BW_FILTER_N_MAX 50u

/** The largest corner, pu of w_base: Wc Ts stays small enough for the
 *  improved Euler's D (bw_filter_init). */
#define BW_FILTER_WC_MAX_PU 4.0f

typedef enum {
    BW_FILTER_OK = 0,
    BW_FILTER_ERR_WC,      /* Wc not > 0, or Wc/w_base >= 4 (Q29 range) */
    BW_FILTER_ERR_TS,      /* Ts not in (0, 0.01] s */
    BW_FILTER_ERR_N,       /* N not in 1..BW_FILTER_N_MAX */
    BW_FILTER_ERR_BASE,    /* w_base not > 0 */
    BW_FILTER_ERR_STEP     /* Wc * Ts > BW_FILTER_A_MAX */
} bw_filter_status_t;

typedef struct {
    /* inputs */
    _iq u;            /* Q24 pu: the signal, sample k */
    /* parameters (bw_filter_init) */
    _iq30 c1;         /* Q30: D11 / D12 ~ -a/2: row 1 = D12 (z2 + c1 d) */
    _iq30 d12;        /* Q30: D12 ~ a */
    _iq29 c2;         /* Q29: D22 / D21 ~ sqrt(2): row 2 = D21 (d + c2 z2) */
    _iq30 d21;        /* Q30: D21 ~ -a */
    _iq30 a;          /* Q30: a = Wc Ts = h Wc_pu (N-pass reference) */
    _iq30 a_half;     /* Q30: a / 2 (N-pass reference) */
    _iq29 wc_pu;      /* Q29: Wc / w_base, turns z2 into d/dt_pu */
    uint16_t n_pass;  /* N corrector passes (N-pass reference) */
    /* outputs */
    _iq y;            /* Q24 pu: filtered signal */
    _iq dy;           /* Q24 pu per pu time: its derivative d/dt_pu */
    /* state */
    _iq27 x1;         /* Q27: filtered signal */
    _iq27 z2;         /* Q27: derivative / Wc_pu */
} bw_filter_t;

/** bw_filter_init's check of its arguments alone (no struct), the status it
 *  would return: _BASE, _WC (Wc not in (0, BW_FILTER_WC_MAX_PU w_base)),
 *  _TS, _N, _STEP (Wc Ts above BW_FILTER_A_MAX), in that order.  Float:
 *  init only. */
bw_filter_status_t bw_filter_check(float wc_rad_s, uint16_t n_pass, float Ts_s,
                                   float w_base_rad_s);

/**
 * Compute the map from Wc (rad/s), N, Ts (s) and the speed base w_base
 * (rad/s); zero the state.  Float, once, not in the ISR.  On error the
 * filter is left zeroed (its step then outputs 0).
 */
bw_filter_status_t bw_filter_init(bw_filter_t *f, float wc_rad_s, uint16_t n_pass,
                                  float Ts_s, float w_base_rad_s);

/** Set the state to the equilibrium of a constant input y0 (Q24 pu):
 *  x1 = y0, derivative 0.  Avoids the start-up transient. */
void bw_filter_reset(bw_filter_t *f, _iq y0);

/** bw_filter_step without the derivative output: state and y only (dy is
 *  left as it was).  For the filters whose derivative nobody reads. */
static inline void bw_filter_update(bw_filter_t *f)
{
    _iq u = _IQsat(f->u, _IQ(BW_FILTER_U_MAX), _IQ(-BW_FILTER_U_MAX));
    _iq27 d = f->x1 - _IQtoIQ27(u);            /* Q27 deviation from equilibrium */
    _iq27 z = f->z2;
    /* row 1: D11 d + D12 z = D12 (z + (D11/D12) d); D11 = -a^2/2 + ... is
     * 500x smaller than D12 and would keep only 14 bits in Q30. */
    _iq27 w = z + iq_round_half(_IQ29mpy(d, f->c1));   /* Q27*Q30 -> Q28 -> Q27 rounded */
    _iq27 dx1 = iq_round_half(_IQ29mpy(w, f->d12));    /* Q27*Q30 -> Q28 -> Q27 rounded */
    /* row 2: D21 (d + (D22/D21) z), |d + c2 z| < 14.7 + 1.42*7 < 25: the
     * sum is formed in Q26 (range 32) */
    _iq26 v = iq_round_half(d)                          /* Q27 -> Q26 rounded */
            + iq_round_half(_IQ29mpy(z, f->c2));        /* Q27*Q29 -> Q27 -> Q26 rounded */
    _iq27 dz2 = iq_round_half(_IQ28mpy(v, f->d21));    /* Q26*Q30 -> Q28 -> Q27 rounded */
    f->x1 = f->x1 + dx1;
    f->z2 = z + dz2;
    f->y = _IQ27toIQ(f->x1);
}

/** One sample with the precomputed map (the ISR path): 4 multiplies and
 *  a rounded format change, + 1 multiply for dy.  Each row is one small coefficient times one sum,
 *      x1 += D12 (z2 + c1 d),   z2 += D21 (d + c2 z2),
 *  so each increment is rounded once (the dead band, below, is then
 *  |d + c2 z2| <= 1/(2|D21|) and |z2 + c1 d| <= 1/(2 D12) LSB27).  Scaling/overflow: see the file comment. */
static inline void bw_filter_step(bw_filter_t *f)
{
    bw_filter_update(f);
    f->dy = _IQmpyIQX(f->z2, 27, f->wc_pu, 29);   /* Q27*Q29 -> Q24 */
}

/** One sample by the literal predictor + N corrector passes (eqs. 15-18,
 *  method §5): the reference for bw_filter_step.  Same state, inputs and
 *  outputs; intermediate f values in Q26 (range +-32 covers |f| < 25).
 *  Not for the ISR (7 + 5N multiplies). */
void bw_filter_step_npass(bw_filter_t *f);

#endif /* BW_FILTER_H */
