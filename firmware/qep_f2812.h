/**
 * @file qep_f2812.h
 * EV-A QEP set-up on GP timer 2 (the HAL seam itself is hal_qep.h).
 */
#ifndef QEP_F2812_H
#define QEP_F2812_H

/** T2 in directional up/down mode clocked by the QEP decoder (x4 of
 *  CAP1/QEP1 and CAP2/QEP2), T2PR = 0xFFFF, free running. */
void qep_f2812_init(void);

#endif /* QEP_F2812_H */
