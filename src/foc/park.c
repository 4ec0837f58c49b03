/* Park transform.  See park.h. */
#include "park.h"

#include <string.h>

void park_init(park_t *p)
{
    memset(p, 0, sizeof *p);
}
