/* firmware/gpio_mux.c and firmware/sysctrl.c themselves, with their
 * register accesses through the seam of reg_seam.h (target_board_io). */
#include "reg_seam.h"
#include "gpio_mux.c"
#include "sysctrl.c"
