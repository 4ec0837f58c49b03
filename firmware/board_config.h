/**
 * @file board_config.h
 * The board this firmware runs on: the F2812's pins and clocks here, and the
 * drive configuration g_board_config in board_config.c, which the build
 * generates from an INI file (firmware/CMakeLists.txt, -DDRIVE_CONFIG=;
 * default host_sim/config/paper_motor.ini: the paper's motor, method §6, on a
 * 60 V MOSFET bridge, 20 A Hall sensors, a 1000-line encoder) with the
 * simulator's parser and checks, so that the simulator and the target run the
 * same controller.
 */
#ifndef BOARD_CONFIG_H
#define BOARD_CONFIG_H

#include <stdint.h>
#include "drive_config.h"

/** OSCCLK: the crystal / oscillator on X1/X2 (XCLKIN). */
#define BOARD_OSCCLK_HZ        30000000UL
/** PLLCR.DIV: SYSCLKOUT = OSCCLK * DIV / 2 = 150 MHz (SPRU078: the PLL
 *  output is always divided by 2; DIV = 10 is the datasheet maximum). */
#define BOARD_PLLCR_DIV        10u
#define BOARD_SYSCLK_HZ        150000000UL
/** HISPCP = 0: HSPCLK = SYSCLKOUT (150 MHz) feeds EV-A and the ADC, so
 *  T1PR = 150 MHz / (2 * 15 kHz) = 5000. */
#define BOARD_HISPCP           0u
#define BOARD_HSPCLK_HZ        150000000UL
/** LOSPCP = 2: LSPCLK = SYSCLKOUT / 4 = 37.5 MHz (the reset value) for SCI-A. */
#define BOARD_LOSPCP           2u
#define BOARD_LSPCLK_HZ        37500000UL
/** SCI-A telemetry link. */
#define BOARD_SCI_BAUD         115200UL

/** Gate-driver polarity (ACTRA): upper switches active high, lower active
 *  low (complementary, the dead band inserted by DBTCONA).  An inverting
 *  gate driver needs the opposite; change it here only. */
#define BOARD_ACTRA            0x0666u

/** The start button: GPIOB0 (PWM7 pin, unused by EV-B here), active low. */
#define BOARD_BUTTON_PRESSED() (GpioDataRegs.GPBDAT.bit.GPIOB0 == 0u)
/** The fault LED: GPIOF14 (the XF pin), active low (gpio_fault_led drives
 *  the pin low to light it).  The pin is XPLLDIS during reset: low there
 *  disables the PLL (SPRS174, "PLL-based clock module"), so the LED and its
 *  resistor go from 3.3 V to the pin, never from the pin to ground
 *  (docs/board.md, board notes). */

/** The drive configuration: SI values, every per-unit constant follows
 *  (board_config.c, generated: board_config_gen). */
extern const drive_config_t g_board_config;

#endif /* BOARD_CONFIG_H */
