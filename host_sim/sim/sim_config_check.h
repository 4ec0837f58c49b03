/* Private to sim_config*.c: the checks after parsing (sim_config_check.c). */
#ifndef SIM_CONFIG_CHECK_H
#define SIM_CONFIG_CHECK_H

#include <stddef.h>

#include "sim_config.h"

/** printf into @p buf (at most @p len characters with the NUL). */
void sim_config_set_err(char *buf, size_t len, const char *fmt, ...);

/** The checks of a parsed configuration with its defaults applied, in this
 *  order: the informative ratings against each other; the drive side
 *  through the drive's table of limits, then drive_init itself (so that a
 *  file this accepts is one the firmware accepts); the simulated world
 *  against the drive (the bus it runs on, the motor it magnetises).
 *  Returns 0, or 1 with the key, its value and the limit in @p err, or
 *  SIM_CONFIG_ERR_UNLISTED (sim_config.h). */
int sim_config_cross_check(const sim_config_t *c, char *err, size_t len);

/** The same without the simulated world: the ratings and the drive side
 *  (sim_config_load_drive: board_config_gen, the co-simulation API). */
int sim_config_drive_check(const sim_config_t *c, char *err, size_t len);

#endif /* SIM_CONFIG_CHECK_H */
