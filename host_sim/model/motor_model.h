/**
 * @file motor_model.h
 * Induction motor, full fifth-order model in the stationary alpha-beta frame
 * (double precision, SI units, host only).
 *
 * States: stator flux linkage psi_s = (psi_sa, psi_sb), rotor flux linkage
 * psi_r = (psi_ra, psi_rb) referred to the stator, mechanical speed w_m and
 * (as a sixth integrator) the unwrapped mechanical angle theta_m.  Linear
 * magnetics, no iron loss, squirrel-cage (shorted) rotor.  With
 * Ls = Lm + Lls, Lr = Lm + Llr, D = Ls Lr - Lm^2 and w_e = p w_m:
 *
 *   i_s = (Lr psi_s - Lm psi_r) / D      i_r = (Ls psi_r - Lm psi_s) / D
 *   dpsi_s/dt = u_s - Rs i_s
 *   dpsi_r/dt = -Rr i_r + j w_e psi_r           (j: rotation by +90 deg)
 *   T_e = 1.5 p (psi_sa i_sb - psi_sb i_sa)
 *   J dw_m/dt = T_e - T_L(t, w_m) - B w_m       (motor_load.h)
 *   dtheta_m/dt = w_m
 *
 * This is the stationary-frame form of the model of method §1 (paper
 * eq. 2 is the same machine written in the rotor-flux frame).  The Clarke
 * transform is amplitude invariant (x_alpha = x_a, as TI's CLARKE): a
 * balanced set of phase peak amplitude X is a space vector of length X;
 * hence the factor 1.5 in torque and power.
 *
 * Integration: classical RK4, n_sub equal sub-steps per call, the stator
 * voltage held constant over the call (an averaged inverter applies one
 * voltage per PWM period, constant in the stator frame).  For the paper's
 * motor the fastest electrical time constant is about
 * sigma Ls / (Rs + Rr Ls/Lr) = 3.2 ms and the fastest rotation w_e ~ 300
 * rad/s, so dt = 66.7 us (|lambda| dt < 0.03) with n_sub = 1..4 is deep
 * inside RK4's stability region; the model_motor convergence test measures
 * the error.
 *
 * Timing (F2812): the ADC samples at the start of a period.  The outputs
 * always describe the state at the end of the last step, i.e. at the start
 * of the next period: read them, then step the period.
 *
 * Speed lock: motor_lock_speed(m, 1) holds w_m at its present value (an
 * infinite inertia, as a dynamometer would): used to test the electrical
 * part against the steady-state equivalent circuit.
 *
 * Open stator: motor_step_open() integrates with the three phase currents
 * forced to zero (PWM outputs disabled and the back-EMF below the bus, so
 * no freewheel diode conducts).  The stator current is taken to decay
 * instantly (in reality ~ sigma Ls I / Vdc ~ 1 ms through the diodes); the
 * rotor flux then decays with Tr.  The terminal voltage (back-EMF) is
 * reported in u_alpha_V/u_beta_V.
 */
#ifndef MOTOR_MODEL_H
#define MOTOR_MODEL_H

#include <stdint.h>
#include "motor_load.h"

/** Machine and mechanical parameters (SI). */
typedef struct {
    double Rs_ohm;      /* stator resistance */
    double Rr_ohm;      /* rotor resistance referred to the stator */
    double Lm_H;        /* magnetising inductance */
    double Lls_H;       /* stator leakage inductance (Ls = Lm + Lls) */
    double Llr_H;       /* rotor leakage inductance  (Lr = Lm + Llr) */
    uint16_t pole_pairs;
    double J_kgm2;      /* rotor + load inertia */
    double B_Nm_s;      /* viscous friction, N m per rad/s (>= 0) */
} motor_params_t;

/** Status of motor_init: names the first bad parameter. */
typedef enum {
    MOTOR_OK = 0,
    MOTOR_ERR_NULL,     /* null pointer */
    MOTOR_ERR_RS,       /* Rs not finite and > 0 */
    MOTOR_ERR_RR,       /* Rr not finite and > 0 */
    MOTOR_ERR_LM,       /* Lm not finite and > 0 */
    MOTOR_ERR_LLS,      /* Lls not finite and > 0 */
    MOTOR_ERR_LLR,      /* Llr not finite and > 0 */
    MOTOR_ERR_POLES,    /* pole_pairs == 0 */
    MOTOR_ERR_J,        /* J not finite and > 0 (use motor_lock_speed for J = inf) */
    MOTOR_ERR_B         /* B not finite and >= 0 */
} motor_status_t;

typedef struct {
    /* parameters (copied and derived by motor_init) */
    motor_params_t p;
    double Ls_H, Lr_H;     /* self-inductances */
    double D_H2;           /* Ls Lr - Lm^2 (> 0 since the leakages are > 0) */
    double Lr_D, Lm_D;     /* Lr / D, Lm / D (the stator current's gains, 1/H) */
    double J_inv;          /* 1 / J */
    /* inputs (the last ones applied) */
    double u_alpha_V, u_beta_V;  /* stator voltage; in open mode the back-EMF */
    load_t load;                 /* load profile (motor_set_load) */
    /* outputs (state at the end of the last step) */
    double t_s;                      /* simulated time */
    double i_alpha_A, i_beta_A;      /* stator current space vector */
    double ia_A, ib_A, ic_A;         /* phase currents (sum exactly 0) */
    double i_r_alpha_A, i_r_beta_A;  /* rotor current referred to the stator */
    double psi_s_alpha_Wb, psi_s_beta_Wb;
    double psi_r_alpha_Wb, psi_r_beta_Wb;
    double Te_Nm;                    /* electromagnetic torque */
    double TL_Nm;                    /* load torque (profile, not friction) */
    double w_m_rad_s;                /* mechanical speed */
    double w_e_rad_s;                /* electrical speed p w_m */
    double n_rpm;                    /* mechanical speed, r/min */
    double theta_m_rad;              /* mechanical angle, unwrapped */
    double theta_m_wrapped_rad;      /* mechanical angle in [0, 2 pi) */
    double theta_e_wrapped_rad;      /* electrical angle p theta_m in [0, 2 pi) */
    /* state */
    double x[6];           /* psi_sa, psi_sb, psi_ra, psi_rb, w_m, theta_m */
    uint16_t speed_locked; /* 1: dw_m/dt = 0 */
    uint16_t open;         /* 1 while the last step was motor_step_open */
    /* motor_step_exact's transition over half a step (a pure function of
     * w_e, the step and the resistances, which a caller may change between
     * steps (a warming rotor): recomputed when any differs) */
    double ex_we, ex_dt;   /* what it was computed for (ex_dt 0: none yet) */
    double ex_Rs, ex_Rr;
    double ex_phi[8];      /* 2x2 complex exp(M dt/2), row-major, re/im */
    double ex_gam[4];      /* 2x1 complex: its response to a unit stator voltage */
    double ex_emu_mod;     /* |e^(tr M dt/4)| (a function of dt and the resistances) */
    double ex_open[2];     /* open stator: exp((-Rr/Lr + j w_e) dt) */
    double ex_open_we, ex_open_dt, ex_open_Rr;
} motor_t;

/** What motor_restore() needs to put a motor back where it was (the state,
 *  time, voltage and stator mode; its load and speed lock are left as they
 *  are, the outputs recomputed): a period redone from its start. */
typedef struct {
    double x[6];
    double t_s;
    double u_alpha_V, u_beta_V;
    uint16_t open;
} motor_state_t;

void motor_save(const motor_t *m, motor_state_t *s);
void motor_restore(motor_t *m, const motor_state_t *s);

/** The paper's motor (method §6): Rs = 1.031, Rr = 0.465 ohm, Lm = 6.4 mH,
 *  Lls = Llr = 2.8 mH (Ls = Lr = 9.2 mH), 2 pole pairs; J = 5e-4 kg m^2
 *  (typical rotor of a 250 W 4-pole motor), B = 1e-4 N m s (15 mN m of
 *  friction at 1400 r/min).  With this J, 1 N m of net torque reaches
 *  1400 r/min (146.6 rad/s) in J w / T = 73 ms: a start that takes ~1 s
 *  (method §7: 0.7 s) is set by the speed-reference ramp, not by inertia.
 *  For an inertia-limited 1 s start at 1 N m use J = 6.8e-3 kg m^2. */
void motor_params_default(motor_params_t *p);

/** Validate @p p, derive constants, zero the state (standstill, no flux,
 *  t = 0, load none, speed free).  On error @p m is left zeroed. */
motor_status_t motor_init(motor_t *m, const motor_params_t *p);

/** Copy a load profile into the motor. */
void motor_set_load(motor_t *m, const load_t *l);
/** The same for a constant load torque @p T_Nm (what load_init_constant
 *  makes), without copying a whole profile. */
void motor_set_load_constant(motor_t *m, double T_Nm);
/** Set the mechanical speed state (e.g. to start a test at speed). */
void motor_set_speed(motor_t *m, double w_m_rad_s);
/** Set the unwrapped mechanical angle. */
void motor_set_angle(motor_t *m, double theta_m_rad);
/** 1: hold the speed at its present value (infinite inertia); 0: free. */
void motor_lock_speed(motor_t *m, uint16_t locked);

/** Advance by @p dt_s with the stator voltage (u_alpha, u_beta) held
 *  constant, in @p n_sub RK4 sub-steps (0 is taken as 1); dt_s <= 0 or not
 *  finite: no-op.  Outputs are refreshed at the end. */
void motor_step(motor_t *m, double u_alpha_V, double u_beta_V, double dt_s,
                uint16_t n_sub);
/** The same from phase-to-neutral voltages (their zero-sequence part, which
 *  drives no current in a floating star, is dropped). */
void motor_step_abc(motor_t *m, double ua_V, double ub_V, double uc_V,
                    double dt_s, uint16_t n_sub);
/** Advance with the stator open (all phase currents zero); see the file
 *  comment.  Entering this mode sets psi_s = (Lm/Lr) psi_r (i_s = 0). */
void motor_step_open(motor_t *m, double dt_s, uint16_t n_sub);

/**
 * One step of @p dt_s with the stator voltage held, the electrical part
 * integrated exactly (the plant's integrator; motor_step's RK4 is its
 * reference).  Over a step the electrical equations are linear at a given
 * speed: with psi_s, psi_r as complex numbers,
 *   d/dt (psi_s, psi_r) = M (psi_s, psi_r) + (u, 0),
 *   M = [ -Rs Lr/D   Rs Lm/D ; Rr Lm/D   -Rr Ls/D + j w_e ],
 * whose transition over half the step, exp(M dt/2) (closed form for 2x2),
 * and response to u are computed once for a w_e (again only when w_e or
 * dt_s differ from the last call's).  The speed the electrical part sees is
 * the mid-step speed predicted from the start (w_m + dt/2 dw_m/dt): second
 * order in the speed's change over the step.  The mechanics, with the
 * torque at the start, the middle and the end of the step, by classical
 * RK4 (the torque a given forcing).  Needs dt_s well inside the mechanical
 * time constant (the torque's slope against speed is taken explicitly: the
 * plant checks tau_m >= its period, else uses motor_step).
 */
void motor_step_exact(motor_t *m, double u_alpha_V, double u_beta_V, double dt_s);
/** The stator current (alpha, beta) motor_step_exact(m, u, dt_s) would end
 *  at, without stepping (the same transition: a later motor_step_exact of
 *  the same state and dt_s reuses it). */
void motor_predict_current(motor_t *m, double u_alpha_V, double u_beta_V, double dt_s,
                           double *i_alpha_A, double *i_beta_A);
/** motor_step_open with the rotor flux's decay and turn integrated exactly
 *  (dpsi_r/dt = (-Rr/Lr + j w_e) psi_r at the predicted mid-step speed),
 *  the mechanics as motor_step_exact. */
void motor_step_open_exact(motor_t *m, double dt_s);

/**
 * The fastest time constants of the model, which the integration step must
 * resolve (RK4 diverges on a mode with step/tau above 2.785):
 *   electrical: the fast root of the stator-rotor RL network at standstill,
 *     det(R + s L) = 0: D s^2 + (Rs Lr + Rr Ls) s + Rs Rr = 0, D = Ls Lr - Lm^2;
 *   mechanical: J over the slope of the net torque against the rotor speed:
 *     a rotor flux psi_r makes 1.5 p^2 psi_r^2 / Rr N m per mechanical rad/s
 *     of slip near synchronism (the induction motor is a damper of that
 *     strength), plus B, plus the load's own slope @p dTL_dw_Nm_s.
 * @p psi_r_Wb: the largest rotor flux the run sets up.
 */
void motor_time_constants(const motor_params_t *p, double psi_r_Wb, double dTL_dw_Nm_s,
                          double *tau_e_s, double *tau_m_s);

/** Rotor flux (d, q) in a frame at electrical angle @p theta_rad: d along
 *  the frame axis, q 90 deg ahead.  For a controller frame on the rotor
 *  flux, q/d is the orientation error (tan of the angle error). */
void motor_rotor_flux_dq(const motor_t *m, double theta_rad, double *psi_d_Wb,
                         double *psi_q_Wb);

#endif /* MOTOR_MODEL_H */
