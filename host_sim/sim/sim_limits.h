/**
 * @file sim_limits.h
 * The drive's limits (include/drive_limits.h) in words, on the host: the
 * message for a failed limit, what each derived limit is and which keys
 * make it, and the list for `motor_sim --keys`.  The numbers and the checks
 * are the core's; only the text is here (it stays off the target).
 */
#ifndef SIM_LIMITS_H
#define SIM_LIMITS_H

#include <stddef.h>
#include <stdio.h>

#include "drive_limits.h"

/** "key 'K' = V unit is outside [lo, hi] unit: why" for @p f (a failed
 *  limit of drive_config_check). */
void sim_limit_message(char *buf, size_t len, const drive_limit_fail_t *f);
/** The same with the value as the file gave it (a double the float of the
 *  failure may not hold, e.g. 1e-320). */
void sim_limit_message_value(char *buf, size_t len, const drive_limit_fail_t *f, double value);

/** What derived limit @p which (drive_derived_limit_t) is; "" if none. */
const char *sim_limit_why(unsigned which);

/** The range of limit @p l as "[lo, hi]" (open ends with parentheses). */
void sim_limit_range(char *buf, size_t len, float lo, float hi, unsigned open);

/** Print the derived limits, one a line (for --keys). */
void sim_limits_print(FILE *f);

#endif /* SIM_LIMITS_H */
