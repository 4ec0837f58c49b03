/* Private to src/app: what drive_init.c and drive_background.c share. */
#ifndef DRIVE_INTERNAL_H
#define DRIVE_INTERNAL_H

#include "drive_types.h"

/** (Re)start the RLS from d->ident_cfg: P(0) = p0 I, theta(0) = 0, the
 *  configured regressor form and forgetting.  Returns the rls_init status. */
rls_status_t drive_rls_start(drive_t *d);

#endif /* DRIVE_INTERNAL_H */
