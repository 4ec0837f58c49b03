/* Clarke transform, amplitude invariant, balanced three-wire.  See clarke.h. */
#include "clarke.h"
#include "foc_const.h"

#include <string.h>

void clarke_init(clarke_t *c)
{
    memset(c, 0, sizeof *c);
}
