/* Encoder plausibility check.  See encoder_check.h. */
#include "encoder_check.h"

#include <math.h>
#include <string.h>

/* counts per sample at speed_max: mechanical rev/s * counts/rev * Ts */
static float encoder_jump(float Ts_s, float speed_max_pu, float f_base_Hz,
                          uint16_t encoder_lines, uint16_t pole_pairs)
{
    return speed_max_pu * f_base_Hz / (float)pole_pairs * 4.0f * (float)encoder_lines * Ts_s;
}

encoder_check_status_t encoder_check_args_ok(float Ts_s, float frozen_s, float i_t_min_pu,
                                             float speed_max_pu, float f_base_Hz,
                                             uint16_t encoder_lines, uint16_t pole_pairs)
{
    float frozen_n, jump;
    if (!(Ts_s > 0.0f) || !(frozen_s > 0.0f) || !(i_t_min_pu > 0.0f) || !(i_t_min_pu < 2.0f) ||
        !(speed_max_pu > 0.0f) || !(f_base_Hz > 0.0f) || encoder_lines == 0u ||
        pole_pairs == 0u) {
        return ENCODER_CHECK_ERR_ARG;
    }
    frozen_n = frozen_s / Ts_s;
    if (!(frozen_n >= 1.0f) || !(frozen_n <= 65535.0f)) {
        return ENCODER_CHECK_ERR_ARG;
    }
    jump = encoder_jump(Ts_s, speed_max_pu, f_base_Hz, encoder_lines, pole_pairs);
    if (!(jump >= 2.0f) || !(jump <= 16384.0f)) {
        return ENCODER_CHECK_ERR_RESOLUTION;
    }
    return ENCODER_CHECK_OK;
}

encoder_check_status_t encoder_check_init(encoder_check_t *e, float Ts_s, float frozen_s,
                                          float i_t_min_pu, float speed_max_pu,
                                          float f_base_Hz, uint16_t encoder_lines,
                                          uint16_t pole_pairs)
{
    encoder_check_status_t st;
    memset(e, 0, sizeof *e);
    e->fault = 1u;
    st = encoder_check_args_ok(Ts_s, frozen_s, i_t_min_pu, speed_max_pu, f_base_Hz,
                               encoder_lines, pole_pairs);
    if (st != ENCODER_CHECK_OK) {
        return st;
    }
    e->frozen_max = (uint16_t)(frozen_s / Ts_s + 0.5f);
    e->jump_max =
        (int32_t)ceilf(encoder_jump(Ts_s, speed_max_pu, f_base_Hz, encoder_lines, pole_pairs));
    e->i_t_min = _IQ(i_t_min_pu);
    e->fault = 0u;
    return ENCODER_CHECK_OK;
}

void encoder_check_reset(encoder_check_t *e)
{
    e->fault = 0u;
    e->cause = 0u;
    e->frozen = 0u;
    e->prev_count = e->count;
}

int16_t encoder_check_set_rate(encoder_check_t *e, uint16_t calls_per_step)
{
    uint16_t n;
    if (calls_per_step == 0u) {
        return 1;
    }
    n = (uint16_t)((e->frozen_max + calls_per_step / 2u) / calls_per_step);
    e->frozen_max = (n == 0u) ? 1u : n;
    e->frozen = 0u;
    return 0;
}
