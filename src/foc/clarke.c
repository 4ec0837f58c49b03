/* Clarke transform, amplitude invariant, balanced three-wire.  See clarke.h. */
#include "clarke.h"
#include "foc_const.h"

#include <string.h>

void clarke_init(clarke_t *c)
{
    memset(c, 0, sizeof *c);
}

void clarke_step(clarke_t *c)
{
    c->alpha = c->as;
    /* beta = (as + 2 bs)/sqrt(3), as two products so that no sum of inputs
     * is formed before scaling down (|as| + 2|bs| would exceed 128 for
     * inputs above 42.7 pu).  Q24*Q30 -> Q24 each, truncated. */
    c->beta = _IQmpyIQX(c->as, GLOBAL_Q, FOC_ONE_BY_SQRT3_Q30, 30)
            + _IQmpyIQX(c->bs, GLOBAL_Q, FOC_TWO_BY_SQRT3_Q30, 30);
}
