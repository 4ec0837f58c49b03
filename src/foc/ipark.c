/* Inverse Park transform.  See ipark.h. */
#include "ipark.h"

#include <string.h>

void ipark_init(ipark_t *p)
{
    memset(p, 0, sizeof *p);
}
