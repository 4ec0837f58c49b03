/* Park transform.  See park.h. */
#include "park.h"

#include <string.h>

void park_init(park_t *p)
{
    memset(p, 0, sizeof *p);
}

void park_step(park_t *p)
{
    /* Q24*Q24 -> Q24, truncated; each |product| <= 64, each sum <= 90.5 */
    p->ds = _IQmpy(p->alpha, p->cosine) + _IQmpy(p->beta, p->sine);
    p->qs = _IQmpy(p->beta, p->cosine) - _IQmpy(p->alpha, p->sine);
}
