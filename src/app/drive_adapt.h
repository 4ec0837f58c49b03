/* Private to src/app: parameter adaptation between passes, standstill Rs,
 * Rr/Tr tracking (issue 8).  See drive_adapt.c. */
#ifndef DRIVE_ADAPT_H
#define DRIVE_ADAPT_H

#include "drive_types.h"

/** Once, after the observer and the sequence are initialised (float).
 *  Returns 0, or 1 for a bad option (passes > 4, a flag > 1, a feature
 *  without orientation 1, tracker constants out of range). */
int16_t drive_adapt_init(drive_t *d, const drive_config_t *c, float Ts);

/** ISR, every period: the standstill lock-in on i_M (its injection into
 *  d->im_inject) during the magnetisation. */
void drive_adapt_fast(drive_t *d);

/** ISR, slot SPEED after the sequence step: standstill Rs at the end of the
 *  magnetisation, RLS restart per pass, the blend of a pass's model, the
 *  tracker. */
void drive_adapt_slow(drive_t *d);

/** Background, after an extraction at the end of a pass: post the result
 *  to the ISR (dropped if the mailbox is still full).  @p full: 1 for
 *  param_extract_step's set, 0 for param_extract_magnetic's (Lm, Lr only). */
void drive_adapt_post(drive_t *d, const param_extract_t *p, uint16_t full);

#endif /* DRIVE_ADAPT_H */
