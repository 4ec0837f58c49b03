/* firmware/hal_pwm_f2812.c itself, with its register accesses through the
 * seam of reg_seam.h (target_pwm_trip_race); a file of its own so that the
 * other tests compile the HAL unchanged. */
#include "reg_seam.h"
#include "hal_pwm_f2812.c"
