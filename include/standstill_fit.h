/**
 * @file standstill_fit.h
 * The standstill sequence's parameters from its impedance points
 * (standstill_lf.h), by the project's RLS (rls.h, rls_update_row) on the
 * standstill model: the background's work (float allowed there; never in
 * an ISR).
 *
 * Model (method §1 at w_r = 0, the M axis of a fixed frame; inverse-Gamma
 * form, L_M = Lm^2/Lr, Tr = Lr/Rr):
 *     Z(jw) = Rs + jw sigma Ls + jw L_M / (1 + jw Tr)
 * With sigma Ls known (the 200 Hz lock-in, standstill_z.h: w Tr >> 1 there)
 * Z_r = Z - jw sigma Ls = R + j X_r satisfies Z_r (1 + jw Tr) = Rs + jw
 * (L_M + Tr Rs), i.e. two linear rows per point, in nu = w / w1:
 *     R   = Rs + (w1 Tr) (nu X_r)
 *     X_r = -(w1 Tr) (nu R) + 4 w1 (L_M + Tr Rs) (nu / 4)
 * theta = [Rs, w1 Tr, 4 w1 (L_M + Tr Rs), 0] (pu; the 4 keeps the regressor
 * nu / 4 <= 1 within the RLS's |phi| < 4).  Three points (nu = 1, 2, 4) give
 * six rows for three unknowns.  The RLS starts from P(0) = p0 I (1e4): after
 * the rows it holds the fit regularised by its prior,
 *     theta_N = (Phi' Phi + I / p0)^-1 Phi' y,   P_N = (Phi' Phi + I / p0)^-1,
 * pulled towards 0 by 1 / (1 + p0 lambda) along each eigendirection of
 * Phi' Phi: on the paper motor lambda_min = 1.5e-3 (the Tr column's first
 * rows, nu X_r / 4, are small where Rs >> X_r).  With the former p0 = 1e6
 * that pull was 7e-4 (Tr -0.08 %, Lm -0.07 %, a misfit floor of 4.5e-5).
 * The fit gives it back exactly: the batch fit theta* solves Phi' Phi
 * theta* = Phi' y = P_N^-1 theta_N, i.e. (I - P_N / p0) theta* = theta_N,
 * and (Phi' Phi)^-1 = (I - P_N / p0)^-1 P_N, a 3x3 solve (Cramer) whose
 * matrix has eigenvalues p0 lambda / (1 + p0 lambda) (15/16 at the paper
 * motor).  The smaller p0 keeps the RLS's own rounding small (from 1e6, P_N
 * was a difference of terms 1e6 times its size along the weak direction).
 * Then Tr = theta2 / w1, L_M = theta3 / (4 w1) - Tr Rs, Ls = sigma Ls + L_M,
 * and with the paper's Lr = Ls (method §4; Lls = Llr: what terminal
 * measurements cannot separate): Lr = Ls, Lm = sqrt(L_M Lr), Rr = Lr / Tr,
 * psi_r = Lm i_M (the magnetising current's reference).
 *
 * u_M leads i_M by half a fast period (standstill_lf.h): each U is turned
 * back by w Ts / 2 before the quotient.
 *
 * Confidence, as the rotating sequences' (ident_conf.h): the deterministic
 * bound sqrt(J e' P e) of each parameter, J the rows' squared misfit, P the
 * covariance (Phi' Phi)^-1 of the rows (the RLS's, the prior given back), e the
 * parameter's derivatives in theta: the largest change an error in the
 * rows as large as their misfit can cause.  It grows with the noise and
 * with any departure of the data from the model (saturation, skin effect,
 * the bridge's nonlinearity, a rotor that moved).  With six rows and three
 * unknowns it is sqrt 3 times the least-squares standard deviation (sd,
 * kept for the tests).  Plus, as the rotating sequences' drift figure, half
 * the difference of the same fit on each half alone (the repeatability),
 * and a floor for what neither shows, STANDSTILL_FIT_CONF_FLOOR: the
 * bridge's error along a phase whose current stays near zero (a resistance
 * the lock-in cannot tell from Rs) and the lead's last transient (measured
 * in the simulator: up to 0.2 % on Rs, on the shipped motors and the
 * family's 55 kW ones).
 * A figure above the limit refuses the set (drive_static.c).
 *
 * Not in the figure: a gain error of the current sensors.  A common one
 * scales every impedance (and every sequence's Rs, Lm, Lr) alike; a
 * mismatch between the two sensors moves the impedance along the held
 * axis by up to about its size, and at standstill nothing exposes it below
 * the sensor test's tolerance (the rotating sequences bound it from the
 * model check's negative sequence): docs/accuracy.md.
 */
#ifndef STANDSTILL_FIT_H
#define STANDSTILL_FIT_H

#include <stdint.h>
#include "rls.h"
#include "standstill_lf.h"

typedef enum {
    STANDSTILL_FIT_OK = 0,
    STANDSTILL_FIT_ERR_INPUT,    /* sigma Ls, i_M, w1 or a base not > 0 */
    STANDSTILL_FIT_ERR_CURRENT,  /* the test not done, or a current phasor too small to divide by */
    STANDSTILL_FIT_ERR_MODEL     /* Tr, L_M, Rs or Ls not > 0 from the fit */
} standstill_fit_status_t;

/* the parameters, in the order of ident_conf.h (IDENT_P_*) */
enum { SSFIT_RS = 0, SSFIT_RR, SSFIT_LM, SSFIT_LR, SSFIT_PSI, SSFIT_TR, SSFIT_NP };

typedef struct {
    float w1_pu;        /* the fundamental, pu of w_base */
    float half_ts_pu;   /* half the fast period, pu time (u's lead) */
    float sigma_ls_pu;  /* the 200 Hz lock-in's sigma Ls, pu of L_base */
    float im_pu;        /* i_M reference, pu: psi_r = Lm i_M */
} standstill_fit_in_t;

typedef struct {
    float p[SSFIT_NP];      /* Rs, Rr, Lm, Lr (pu), psi_r (pu), Tr (pu time) */
    float conf[SSFIT_NP];   /* relative confidence figures */
    float residual;         /* the fit's relative rms misfit */
    float spread[SSFIT_NP]; /* |p_A - p_B| / (2 p) */
    float sd[SSFIT_NP];     /* relative standard deviations from the fit */
    float r[STANDSTILL_LF_NH], x[STANDSTILL_LF_NH];   /* Z at nu = 1, 2, 4 (both halves), pu */
    uint16_t status;        /* standstill_fit_status_t */
} standstill_fit_t;

/** The bound per standard deviation: sqrt(rows - unknowns) = sqrt 3. */
#define STANDSTILL_FIT_K_SD 1.7320508f
/** Added to every figure (relative): the systematic errors the fit's
 *  residual does not show (file comment). */
#define STANDSTILL_FIT_CONF_FLOOR 0.003f

/** The whole fit from a finished test's sums (@p z->done), on @p work: an
 *  RLS instance it initialises and runs (the drive lends its own, idle at
 *  standstill: no second one on the background's stack). */
standstill_fit_status_t standstill_fit(standstill_fit_t *f, const standstill_lf_t *z,
                                       const standstill_fit_in_t *in, rls_t *work);

#endif /* STANDSTILL_FIT_H */
