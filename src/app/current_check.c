/* Current-feedback plausibility.  See current_check.h. */
#include "current_check.h"

#include <math.h>
#include <string.h>

current_check_status_t current_check_init(current_check_t *c, float Ts_s, float tau_s,
                                          float e_max_pu)
{
    memset(c, 0, sizeof *c);
    c->fault = 1u;
    if (!(Ts_s > 0.0f) || !(tau_s >= Ts_s) || !(e_max_pu > 0.0f) || !(e_max_pu < 4.0f)) {
        return CURRENT_CHECK_ERR_ARG;
    }
    c->k_filt = _IQ(1.0f - expf(-Ts_s / tau_s));
    c->e_max = _IQ(e_max_pu);
    c->fault = 0u;
    return CURRENT_CHECK_OK;
}

void current_check_reset(current_check_t *c)
{
    c->e_f = _IQ(0.0);
    c->limited = 0u;
    c->fault = 0u;
}
