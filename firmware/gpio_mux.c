/**
 * @file gpio_mux.c
 * Pin functions (SPRU078 "GPIO MUX"): 1 in a GPxMUX bit selects the
 * peripheral, 0 the GPIO; GPxDIR 1 = output.
 */
#include "DSP281x_Device.h"
#include "gpio_mux.h"

void gpio_mux_init(void)
{
    EALLOW;
    /* EV-A: the six PWM outputs and the two QEP inputs */
    GpioMuxRegs.GPAMUX.bit.PWM1_GPIOA0 = 1u;
    GpioMuxRegs.GPAMUX.bit.PWM2_GPIOA1 = 1u;
    GpioMuxRegs.GPAMUX.bit.PWM3_GPIOA2 = 1u;
    GpioMuxRegs.GPAMUX.bit.PWM4_GPIOA3 = 1u;
    GpioMuxRegs.GPAMUX.bit.PWM5_GPIOA4 = 1u;
    GpioMuxRegs.GPAMUX.bit.PWM6_GPIOA5 = 1u;
    GpioMuxRegs.GPAMUX.bit.CAP1Q1_GPIOA8 = 1u;
    GpioMuxRegs.GPAMUX.bit.CAP2Q2_GPIOA9 = 1u;
    /* Qualify the encoder inputs: QUALPRD = 1
     * (6 samples 2 SYSCLKOUT apart, 80 ns); rejects glitches, passes 1000 lines x 4 at 1400 r/min
     * (93 kHz edges, 10.7 us apart) with wide margin. */
    GpioMuxRegs.GPAQUAL.bit.QUALPRD = 1u;
    /* PDPINTA: the bridge's hardware fault line (active low) */
    GpioMuxRegs.GPDMUX.bit.T1CTRIP_PDPA_GPIOD0 = 1u;
    /* SCI-A */
    GpioMuxRegs.GPFMUX.bit.SCITXDA_GPIOF4 = 1u;
    GpioMuxRegs.GPFMUX.bit.SCIRXDA_GPIOF5 = 1u;
    /* start button on GPIOB0 (input) */
    GpioMuxRegs.GPBMUX.bit.PWM7_GPIOB0 = 0u;
    GpioMuxRegs.GPBDIR.bit.GPIOB0 = 0u;
    GpioMuxRegs.GPBQUAL.bit.QUALPRD = 0xFFu;  /* 6 samples 510 SYSCLKOUT apart: 20 us debounce */
    EDIS;
    /* the fault LED on GPIOF14 (the XF/XPLLDIS pin), active low
     * (board_config.h): its output latch high (LED off) before the pin
     * becomes an output, so that it never drives low in between; until
     * here it was an input (GPFMUX, GPFDIR reset to 0, SPRU078 "GPIO MUX")
     * held high by the board's pull-up */
    GpioDataRegs.GPFSET.bit.GPIOF14 = 1u;
    EALLOW;
    GpioMuxRegs.GPFMUX.bit.XF_GPIOF14 = 0u;
    GpioMuxRegs.GPFDIR.bit.GPIOF14 = 1u;
    EDIS;
}

void gpio_fault_led(uint16_t on)
{
    /* active low: the LED (and its resistor) from 3.3 V to the pin, so that
     * nothing pulls XPLLDIS low at reset (docs/board.md, board notes) */
    if (on != 0u) {
        GpioDataRegs.GPFCLEAR.bit.GPIOF14 = 1u;
    } else {
        GpioDataRegs.GPFSET.bit.GPIOF14 = 1u;
    }
}
