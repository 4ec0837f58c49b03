/**
 * @file motor_load.c
 * Load-torque profiles; see motor_load.h.
 */
#include "motor_load.h"

#include <math.h>
#include <string.h>

load_status_t load_init_none(load_t *l)
{
    if (l == NULL) {
        return LOAD_ERR_NULL;
    }
    memset(l, 0, sizeof(*l));
    l->kind = LOAD_NONE;
    return LOAD_OK;
}

load_status_t load_init_constant(load_t *l, double T0_Nm)
{
    if (l == NULL) {
        return LOAD_ERR_NULL;
    }
    (void)load_init_none(l);
    if (!isfinite(T0_Nm)) {
        return LOAD_ERR_TORQUE;
    }
    l->kind = LOAD_CONSTANT;
    l->T0_Nm = T0_Nm;
    return LOAD_OK;
}

load_status_t load_init_steps(load_t *l, uint16_t n_steps, const double *t_s,
                              const double *T_Nm)
{
    uint16_t k;

    if (l == NULL) {
        return LOAD_ERR_NULL;
    }
    (void)load_init_none(l);
    if ((t_s == NULL) || (T_Nm == NULL)) {
        return LOAD_ERR_NULL;
    }
    if ((n_steps == 0u) || (n_steps > LOAD_MAX_STEPS)) {
        return LOAD_ERR_COUNT;
    }
    for (k = 0u; k < n_steps; k++) {
        if (!isfinite(t_s[k]) || ((k > 0u) && !(t_s[k] > t_s[k - 1u]))) {
            return LOAD_ERR_TIMES;
        }
        if (!isfinite(T_Nm[k])) {
            return LOAD_ERR_TORQUE;
        }
    }
    for (k = 0u; k < n_steps; k++) {
        l->step_t_s[k] = t_s[k];
        l->step_T_Nm[k] = T_Nm[k];
    }
    l->n_steps = n_steps;
    l->kind = LOAD_STEPS;
    return LOAD_OK;
}

load_status_t load_init_proportional(load_t *l, double k1_Nm_s)
{
    if (l == NULL) {
        return LOAD_ERR_NULL;
    }
    (void)load_init_none(l);
    if (!isfinite(k1_Nm_s) || (k1_Nm_s < 0.0)) {
        return LOAD_ERR_COEFF;
    }
    l->kind = LOAD_PROPORTIONAL;
    l->k1_Nm_s = k1_Nm_s;
    return LOAD_OK;
}

load_status_t load_init_fan(load_t *l, double T_ref_Nm, double w_ref_rad_s)
{
    if (l == NULL) {
        return LOAD_ERR_NULL;
    }
    (void)load_init_none(l);
    if (!isfinite(w_ref_rad_s) || !(w_ref_rad_s > 0.0)) {
        return LOAD_ERR_SPEED;
    }
    if (!isfinite(T_ref_Nm) || (T_ref_Nm < 0.0)) {
        return LOAD_ERR_COEFF;
    }
    l->kind = LOAD_FAN;
    l->k2_Nm_s2 = T_ref_Nm / (w_ref_rad_s * w_ref_rad_s);
    return LOAD_OK;
}

double load_torque_Nm(const load_t *l, double t_s, double w_m_rad_s)
{
    double T = 0.0;
    uint16_t k;

    switch (l->kind) {
    case LOAD_CONSTANT:
        T = l->T0_Nm;
        break;
    case LOAD_STEPS:
        /* last step whose time has come; n_steps <= 16, a linear scan is
         * cheaper than anything cleverer */
        for (k = 0u; k < l->n_steps; k++) {
            if (t_s >= l->step_t_s[k]) {
                T = l->step_T_Nm[k];
            }
        }
        break;
    case LOAD_PROPORTIONAL:
        T = l->k1_Nm_s * w_m_rad_s;
        break;
    case LOAD_FAN:
        T = l->k2_Nm_s2 * w_m_rad_s * fabs(w_m_rad_s);
        break;
    case LOAD_NONE:
    default:
        T = 0.0;
        break;
    }
    return T;
}
