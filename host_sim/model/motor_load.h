/**
 * @file motor_load.h
 * Load-torque profiles for the motor model (SI, double, host only).
 *
 * Sign convention: the load torque T_L opposes positive rotation, i.e. the
 * mechanical equation of motor_model.h is
 *     J dw_m/dt = T_e - T_L(t, w_m) - B w_m.
 *
 *   LOAD_NONE          T_L = 0
 *   LOAD_CONSTANT      T_L = T0                      (active: a hoist; at
 *                      standstill it turns the rotor backwards if the motor
 *                      gives less than T0)
 *   LOAD_STEPS         T_L = T_k for t >= t_k (piecewise constant, t_k strictly
 *                      increasing, T_L = 0 before t_0): a list of time/torque
 *                      pairs, e.g. {(0.5 s, 0.3 N m), (1.5 s, 0.8 N m)}
 *   LOAD_PROPORTIONAL  T_L = k1 w_m                  (passive, like a DC
 *                      generator into a resistor)
 *   LOAD_FAN           T_L = k2 w_m |w_m|            (passive, fan/pump: the
 *                      torque grows with the speed squared and opposes motion)
 *
 * Every profile is a plain value (no pointers), so a load_t can be copied
 * into the motor and reconfigured at any time.
 */
#ifndef MOTOR_LOAD_H
#define MOTOR_LOAD_H

#include <stdint.h>

#define LOAD_MAX_STEPS 16u

typedef enum {
    LOAD_NONE = 0,
    LOAD_CONSTANT,
    LOAD_STEPS,
    LOAD_PROPORTIONAL,
    LOAD_FAN
} load_kind_t;

/** Status of the load_init_* functions; on error the load is LOAD_NONE. */
typedef enum {
    LOAD_OK = 0,
    LOAD_ERR_NULL,       /* null pointer argument */
    LOAD_ERR_TORQUE,     /* a torque is not finite */
    LOAD_ERR_COUNT,      /* n_steps == 0 or > LOAD_MAX_STEPS */
    LOAD_ERR_TIMES,      /* step times not finite or not strictly increasing */
    LOAD_ERR_COEFF,      /* k1 or k2 negative or not finite */
    LOAD_ERR_SPEED       /* fan reference speed not > 0 */
} load_status_t;

typedef struct {
    /* parameters */
    load_kind_t kind;
    double T0_Nm;                          /* LOAD_CONSTANT */
    double k1_Nm_s;                        /* LOAD_PROPORTIONAL: N m per rad/s */
    double k2_Nm_s2;                       /* LOAD_FAN: N m per (rad/s)^2 */
    uint16_t n_steps;                      /* LOAD_STEPS */
    double step_t_s[LOAD_MAX_STEPS];
    double step_T_Nm[LOAD_MAX_STEPS];
} load_t;

load_status_t load_init_none(load_t *l);
load_status_t load_init_constant(load_t *l, double T0_Nm);
/** @p t_s strictly increasing; T_L = T_Nm[k] from t_s[k] until t_s[k+1]. */
load_status_t load_init_steps(load_t *l, uint16_t n_steps, const double *t_s,
                              const double *T_Nm);
load_status_t load_init_proportional(load_t *l, double k1_Nm_s);
/** Fan: gives @p T_ref_Nm at mechanical speed @p w_ref_rad_s (k2 = T/w^2). */
load_status_t load_init_fan(load_t *l, double T_ref_Nm, double w_ref_rad_s);

/** Load torque at time @p t_s and mechanical speed @p w_m_rad_s. */
double load_torque_Nm(const load_t *l, double t_s, double w_m_rad_s);

#endif /* MOTOR_LOAD_H */
