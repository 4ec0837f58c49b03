/**
 * @file gpio_mux.h
 * Pin functions of the F2812 (SPRU078 "GPIO MUX").
 */
#ifndef GPIO_MUX_H
#define GPIO_MUX_H

#include <stdint.h>

/** PWM1..6, CAP1/QEP1, CAP2/QEP2, T1CTRIP/PDPINTA, SCITXDA/SCIRXDA as
 *  peripheral pins; GPIOB0 (button) input; GPIOF14 (fault LED) output. */
void gpio_mux_init(void);
/** The fault LED (GPIOF14, active low: 1 drives the pin low). */
void gpio_fault_led(uint16_t on);

#endif /* GPIO_MUX_H */
