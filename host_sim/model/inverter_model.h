/**
 * @file inverter_model.h
 * Two-level three-phase MOSFET bridge on a DC bus, averaged over one PWM
 * period (double precision, SI units, host only).
 *
 * Inputs per period: the three duties d_x in [0, 1] (upper-switch on
 * fraction, d = (T1PR - CMPRx)/T1PR as in include/hal_pwm.h; see
 * inverter_duty_from_cmpr) and the phase currents i_x (positive out of the
 * leg into the motor).
 *
 * Averaged pole voltage (leg output to the DC- rail), centre-aligned PWM with
 * dead time td inserted before every turn-on (the F2812 dead-band unit):
 * during td both switches are off and the current picks the diode, so for
 * i_x > 0 the lower diode holds the pole low and the upper turn-on delay
 * costs td of high time per period; for i_x < 0 the upper diode holds it
 * high and the lower turn-on delay adds td.  With s(i) the transition
 * function below:
 *
 *   d_eff = clamp(d - (td/Ts) (s(i_on) + s(i_off))/2, 0, 1)   for 0 < d < 1
 *   d_eff = d                                 for d = 0 or d = 1 (no edges)
 *   v_pole = d_eff Vdc - v_drop s(i_mid) - r_on i_mid
 *
 * Each of the two edges of a period costs or gains td/2 by the sign of the
 * current AT that edge: the upper switch is on around the middle of the
 * centre-aligned period, from (1 - d)/2 Ts to (1 + d)/2 Ts, and the current
 * there is extrapolated from the start-of-period current i0 and its change
 * over the previous period di:  i_on = i0 + di (1 - d)/2,
 * i_off = i0 + di (1 + d)/2, i_mid = i0 + di/2.  (The first period after
 * init takes di = 0.)  Evaluating the sign at the period start instead made
 * every zero crossing of the current half a period late, a phase error of
 * the dead-time voltage that the drive cannot compensate: it moved the
 * 15 kW motor's identified Rr by +1.7 points.
 *
 * i.e. for |i| above the band the pole loses Vdc td/Ts + v_drop when i > 0
 * and gains it when i < 0 (the conducting device, switch or diode, drops
 * v_drop + r_on |i| against the current).
 *
 * Transition near zero current: s(i) = clamp(i / i_band, -1, 1).  A small
 * current cannot swing the pole (device output capacitance, ~2 Coss Vdc of
 * charge) within the dead time, so the dead-time error shrinks towards zero
 * with the current; the linear ramp over |i| < i_band is the usual first
 * approximation of that (for Coss ~ 1 nF, Vdc = 54 V, td = 1 us the swing
 * completes within td above ~0.1 A, the default band).  Its slope
 * (Vdc td/Ts + v_drop)/i_band is a resistance per phase (11 ohm here, 195 ohm
 * on a 600 V bridge with 2 us) whose time constant against the motor's
 * sigma Ls can be shorter than Ts: a coupling that evaluates the period
 * explicitly then misbehaves in the transition, inverter_step_implicit
 * solves it (the plant's second pass).
 *
 * Floating star: the motor sees only the differential part,
 *   v_xn = v_pole_x - (v_pole_a + v_pole_b + v_pole_c)/3,
 * and (v_alpha, v_beta) = amplitude-invariant Clarke of v_xn.
 *
 * DC link: the upper device of leg x carries i_x for d_eff,x of the period,
 *   i_dc = sum_x d_eff,x i_x          (so Vdc i_dc = sum v_pole i + losses),
 *   Vdc = Vs + V_ripple sin(2 pi f_ripple t) - R_src i_dc,
 * evaluated at the middle of the period (the period average of the ripple to
 * O((2 pi f_ripple Ts)^2)).  Regenerated current raises Vdc through R_src
 * (the source is assumed to sink it; no brake chopper is modelled).
 *
 * Disabled outputs (FCOMPOE = 0) are not modelled here: use
 * motor_step_open() (motor_model.h), valid while the back-EMF is below Vdc.
 *
 * "Ideal" option: td = 0, no drop, no on-resistance, R_src = 0, no ripple:
 * v_pole = d Vdc exactly, for reference tests.
 */
#ifndef INVERTER_MODEL_H
#define INVERTER_MODEL_H

#include <stdint.h>

typedef struct {
    double vdc_V;          /* source voltage (no-load bus) */
    double r_source_ohm;   /* source + link resistance, >= 0 */
    double ripple_V;       /* ripple amplitude (peak), >= 0 */
    double ripple_Hz;      /* ripple frequency, >= 0 */
    double f_pwm_Hz;       /* PWM (= control) frequency */
    double dead_time_s;    /* td, >= 0 and < 1/(2 f_pwm) */
    double v_drop_V;       /* constant device drop, >= 0 */
    double r_on_ohm;       /* device on-resistance, >= 0 */
    double i_band_A;       /* dead-time transition band, > 0 */
    uint16_t ideal;        /* 1: td = 0, no drop, r_on = 0, R_src = 0, no ripple */
} inverter_params_t;

typedef enum {
    INV_OK = 0,
    INV_ERR_NULL,
    INV_ERR_VDC,           /* vdc_V not finite and > 0 */
    INV_ERR_RSOURCE,       /* r_source_ohm negative or not finite */
    INV_ERR_RIPPLE,        /* ripple_V or ripple_Hz negative or not finite */
    INV_ERR_FPWM,          /* f_pwm_Hz not finite and > 0 */
    INV_ERR_DEADTIME,      /* dead_time_s < 0 or >= half the period */
    INV_ERR_DROP,          /* v_drop_V negative or not finite */
    INV_ERR_RON,           /* r_on_ohm negative or not finite */
    INV_ERR_BAND           /* i_band_A not finite and > 0 */
} inverter_status_t;

typedef struct {
    /* parameters */
    inverter_params_t p;   /* as given (ideal applied in the derived values) */
    double Ts_s;           /* 1 / f_pwm */
    double td_frac;        /* td / Ts (0 if ideal) */
    double v_drop_V;       /* effective (0 if ideal) */
    double r_on_ohm;       /* effective (0 if ideal) */
    double r_source_ohm;   /* effective (0 if ideal) */
    double ripple_V;       /* effective (0 if ideal) */
    /* inputs (last step) */
    double t_s;            /* period start */
    double duty[3];
    double i_A[3];         /* period-start currents */
    uint16_t started;      /* i_A holds a previous period (for the slope) */
    double ripple_at_s;    /* the last mid-period time whose ripple was computed */
    double ripple_now_V;   /* that ripple (the implicit period's two passes share it) */
    /* outputs */
    double vdc_V;          /* bus voltage, period average */
    double i_dc_A;         /* DC-link current drawn from the bus, period average */
    double d_eff[3];       /* effective duties after dead time */
    double v_pole_V[3];    /* leg output to DC-, period average */
    double v_phase_V[3];   /* phase-to-neutral of the floating-star motor */
    double v_alpha_V, v_beta_V;
} inverter_t;

/** Realistic defaults for a ~60 V MOSFET bridge at 15 kHz: Vs = 54 V (the
 *  50-60 V bus method §6 asks for), R_src = 50 mohm, no ripple, td = 1 us,
 *  v_drop = 0.3 V, r_on = 10 mohm, i_band = 0.1 A, not ideal. */
void inverter_params_default(inverter_params_t *p);

/** Validate and derive; on error @p inv is left zeroed.  Outputs start at
 *  zero duty, zero current. */
inverter_status_t inverter_init(inverter_t *inv, const inverter_params_t *p);

/** One PWM period starting at @p t_s with duties @p duty (clamped to [0, 1])
 *  and phase currents @p i_abc_A (the motor's at the period start; the
 *  previous call's currents give the slope within the period). */
void inverter_step(inverter_t *inv, double t_s, const double duty[3],
                   const double i_abc_A[3]);

/** The same with the change of each phase current over this period given
 *  (@p di_A: end minus start, A), e.g. from a first pass of the motor over
 *  the period, so that the current at each switching edge is interpolated
 *  rather than extrapolated. */
void inverter_step_slope(inverter_t *inv, double t_s, const double duty[3],
                         const double i_abc_A[3], const double di_A[3]);

/**
 * The period solved implicitly: the edge currents consistent with the
 * voltage they produce.  Inside the transition the error is a resistance
 * E/b per pole (E = vdc td/Ts + v_drop); when (E/b) Ts / (sigma Ls) > 2 an
 * explicit evaluation (the slope of the last period, or of a first pass over
 * this one) overshoots from period to period and settles into a limit cycle
 * around every zero crossing, where a real bridge's error follows the
 * current within the period and the current settles.
 *
 * @p inv is as it was before the period (the state inverter_step started
 * from), @p di1_A the change of each phase current the motor made over the
 * period under the voltage of inverter_step (the explicit first pass), and
 * @p g_A_per_V the motor's phase-current change over one period per volt of
 * phase-to-neutral voltage (its stator transient: Ts / (sigma Ls) for
 * Ts << sigma Ls / R, see inverter_current_gain).  The motor is linear in
 * the voltage over a period, so the change under any other error is
 *   di = di1 - g P (e(di) - e(di_1st))      (P: the floating star's projection),
 * e the pole errors by their edge currents i0 + di (1 -+ d)/2; solved for di
 * by Newton's method with a halving line search (e is piecewise linear and
 * rises with the current, so the Jacobian I + g P |de/ddi| is regular), then
 * inverter_step_slope with that di.  Where every pole's currents stay outside
 * the transition band (and its duty unclamped) from di_1st to the solution,
 * e is affine there and the solution is taken in closed form (what Newton
 * reaches within its 1e-9 A after one step).  The bus is taken at its last
 * value in the solve only (the step itself evaluates it).  Returns the
 * iterations taken (0: di1 already consistent; 1: the closed form).
 */
uint16_t inverter_step_implicit(inverter_t *inv, double t_s, const double duty[3],
                                const double i_abc_A[3], const double di1_A[3],
                                double g_A_per_V);

/** A motor's phase-current change over @p Ts_s per volt of constant
 *  phase-to-neutral voltage at constant back-EMF: the stator transient
 *  sigma Ls di/dt = u - R i, R = Rs + Rr (Lm/Lr)^2 (the rotor's resistance as
 *  the stator sees it while the flux holds), g = (1 - e^(-Ts R/(sigma Ls)))/R. */
double inverter_current_gain(double Ts_s, double Rs_ohm, double Rr_ohm, double Lm_H,
                             double Lls_H, double Llr_H);

/** Instantaneous bus voltage at time @p t_s with DC-link current @p i_dc_A
 *  (e.g. for the ADC sample of the bus at the period start). */
double inverter_bus_voltage_V(const inverter_t *inv, double t_s, double i_dc_A);

/** Duty of a compare value, hal_pwm.h convention d = (T1PR - CMPR)/T1PR;
 *  CMPR > T1PR gives 0 (upper never on), T1PR = 0 gives 0. */
double inverter_duty_from_cmpr(uint16_t cmpr, uint16_t t1pr);

#endif /* INVERTER_MODEL_H */
