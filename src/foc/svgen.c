/* Space-vector PWM by min-max zero-sequence injection.  See svgen.h. */
#include "svgen.h"
#include "foc_const.h"

#include <string.h>

svgen_status_t svgen_init(svgen_t *s, uint16_t t1pr)
{
    memset(s, 0, sizeof *s);
    if (t1pr == 0u) {
        return SVGEN_ERR_PERIOD;
    }
    s->t1pr = t1pr;
    s->t1pr_x2 = 2 * (int32_t)t1pr;
    s->vdc_min = _IQ(SVGEN_VDC_MIN_PU);
    s->da = _IQ(0.5);
    s->db = _IQ(0.5);
    s->dc = _IQ(0.5);
    s->cmpr[0] = svgen_compare(s, s->da);
    s->cmpr[1] = s->cmpr[0];
    s->cmpr[2] = s->cmpr[0];
    return SVGEN_OK;
}

