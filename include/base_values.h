/**
 * @file base_values.h
 * Per-unit base values: the one place where SI quantities meet per unit.
 *
 * Every per-unit (pu) signal in the core is an _iq (Q GLOBAL_Q, Q24 by
 * default: range [-128, 128), resolution 6.0e-8 pu).  The bases:
 *
 *   I_base_A      peak phase current that is 1.0 pu (the current sensors'
 *                 full scale, as TI's BASE_CURRENT)
 *   V_base_V      peak phase voltage that is 1.0 pu (the nominal DC bus over
 *                 sqrt(3): the largest phase voltage linear SVPWM gives)
 *   f_base_Hz     electrical frequency that is 1.0 pu (rated frequency)
 *   w_base_rad_s  = 2 pi f_base: electrical angular speed that is 1.0 pu
 *   t_base_s      = 1 / w_base: the pu unit of time, so that d/dt in pu is
 *                 d/dt in SI times 1/w_base
 *   Z_base_ohm    = V_base / I_base
 *   L_base_H      = Z_base / w_base
 *   psi_base_Wb   = V_base / w_base
 *   T_base_Nm     = 1.5 * pole_pairs * psi_base * I_base
 *   n_base_rpm    = 60 f_base / pole_pairs: mechanical speed of 1.0 pu
 *
 * Angles are pu of one electrical revolution (0..1), as TI's _IQsinPU.
 * Computed once, at initialisation, in float (never in the ISR path).
 */
#ifndef BASE_VALUES_H
#define BASE_VALUES_H

#include <stdint.h>

typedef struct {
    /* parameters (SI, set by base_values_init) */
    float I_base_A;
    float V_base_V;
    float f_base_Hz;
    float Ts_s;          /* ISR / sampling period */
    uint16_t pole_pairs;
    /* derived (SI) */
    float w_base_rad_s;
    float t_base_s;
    float Z_base_ohm;
    float L_base_H;
    float psi_base_Wb;
    float T_base_Nm;
    float n_base_rpm;
    float Ts_pu;         /* Ts / t_base: the sample period in pu time */
} base_values_t;

/** Status codes of base_values_init. */
typedef enum {
    BASE_OK = 0,
    BASE_ERR_CURRENT,    /* I_base_A not > 0 */
    BASE_ERR_VOLTAGE,    /* V_base_V not > 0 */
    BASE_ERR_FREQUENCY,  /* f_base_Hz not > 0 */
    BASE_ERR_PERIOD,     /* Ts_s not in (0, 0.01] */
    BASE_ERR_POLES       /* pole_pairs == 0 */
} base_status_t;

/** Fill @p b from SI ratings.  On error @p b is left zeroed and the first
 *  offending argument is named by the status. */
base_status_t base_values_init(base_values_t *b, float I_base_A, float V_base_V,
                               float f_base_Hz, uint16_t pole_pairs, float Ts_s);

/* SI <-> pu conversions for initialisation and telemetry (float, not ISR). */
static inline float base_ohm_to_pu(const base_values_t *b, float r)  { return r / b->Z_base_ohm; }
static inline float base_H_to_pu(const base_values_t *b, float l)    { return l / b->L_base_H; }
static inline float base_s_to_pu(const base_values_t *b, float t)    { return t / b->t_base_s; }
static inline float base_Wb_to_pu(const base_values_t *b, float p)   { return p / b->psi_base_Wb; }
static inline float base_rpm_to_pu(const base_values_t *b, float n)  { return n / b->n_base_rpm; }

#endif /* BASE_VALUES_H */
