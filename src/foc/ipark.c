/* Inverse Park transform.  See ipark.h. */
#include "ipark.h"

#include <string.h>

void ipark_init(ipark_t *p)
{
    memset(p, 0, sizeof *p);
}

void ipark_step(ipark_t *p)
{
    /* Q24*Q24 -> Q24, truncated; each |product| <= 64, each sum <= 90.5 */
    p->alpha = _IQmpy(p->ds, p->cosine) - _IQmpy(p->qs, p->sine);
    p->beta = _IQmpy(p->ds, p->sine) + _IQmpy(p->qs, p->cosine);
}
