/**
 * @file hal_qep.h
 * HAL seam: the quadrature-encoder position counter (EV-A QEP on GP timer 2).
 *
 * T2 counts up/down on both edges of both channels (x4), free-running over
 * 0..0xFFFF (T2PR = 0xFFFF), so the speed calculation takes differences
 * modulo 2^16.
 */
#ifndef HAL_QEP_H
#define HAL_QEP_H

#include <stdint.h>

/** T2CNT now. */
uint16_t hal_qep_read_count(void);

#endif /* HAL_QEP_H */
