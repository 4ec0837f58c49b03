/* Per-unit bases, computed once from SI ratings.  See base_values.h. */
#include "base_values.h"

#include <string.h>

#define BASE_TWO_PI 6.28318530717958647692f

base_status_t base_values_init(base_values_t *b, float I_base_A, float V_base_V,
                               float f_base_Hz, uint16_t pole_pairs, float Ts_s)
{
    memset(b, 0, sizeof *b);
    /* "!(x > 0)" also rejects NaN */
    if (!(I_base_A > 0.0f)) { return BASE_ERR_CURRENT; }
    if (!(V_base_V > 0.0f)) { return BASE_ERR_VOLTAGE; }
    if (!(f_base_Hz > 0.0f)) { return BASE_ERR_FREQUENCY; }
    if (!(Ts_s > 0.0f) || Ts_s > 0.01f) { return BASE_ERR_PERIOD; }
    if (pole_pairs == 0u) { return BASE_ERR_POLES; }

    b->I_base_A = I_base_A;
    b->V_base_V = V_base_V;
    b->f_base_Hz = f_base_Hz;
    b->Ts_s = Ts_s;
    b->pole_pairs = pole_pairs;
    b->w_base_rad_s = BASE_TWO_PI * f_base_Hz;
    b->t_base_s = 1.0f / b->w_base_rad_s;
    b->Z_base_ohm = V_base_V / I_base_A;
    b->L_base_H = b->Z_base_ohm / b->w_base_rad_s;
    b->psi_base_Wb = V_base_V / b->w_base_rad_s;
    b->T_base_Nm = 1.5f * (float)pole_pairs * b->psi_base_Wb * I_base_A;
    b->n_base_rpm = 60.0f * f_base_Hz / (float)pole_pairs;
    b->Ts_pu = Ts_s / b->t_base_s;
    return BASE_OK;
}
