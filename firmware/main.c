/**
 * @file main.c
 * F2812 firmware entry: start-up sequence and the background loop.
 *
 *   reset -> boot ROM -> BEGIN (code_start.asm) -> _c_int00 -> main
 *   main:  clocks and watchdog, ramfuncs copy, flash wait states, pins,
 *          PIE, drive_init(board config), EV-A / ADC / QEP / SCI-A, the data
 *          log, ISRs, T1 start, then the background loop forever.
 *
 * The drive starts its identification sequence on a telemetry command ($C,S)
 * or the start button (GPIOB0, active low); everything else runs in
 * drive_isr (15 kHz, from the ADC end-of-sequence interrupt).  The portable
 * part of the background loop (command dispatch, frame timing) is bg_loop.c,
 * which the simulator's serial link (motor_sim --serial) runs too.
 */
#include "DSP281x_Device.h"
#include "adc_f2812.h"
#include "bg_loop.h"
#include "board_config.h"
#include "datalog.h"
#include "drive_types.h"
#include "f2812_timing.h"
#include "flash.h"
#include "gpio_mux.h"
#include "isr.h"
#include "pie.h"
#include "pwm_f2812.h"
#include "qep_f2812.h"
#include "sci_f2812.h"
#include "sysctrl.h"
#include "telemetry.h"

/* The application owns the drive.  The data log sits in its own RAM section
 * (`dlog`, linker/F2812_flash.cmd) at a fixed address for the CCS graph. */
static drive_t g_drive;
#pragma DATA_SECTION(g_dlog, "dlog")
static datalog_t g_dlog;
/* The background's own state (`bgdata`) is in H0's data part beside the data
 * log: L0/L1's data part keeps the state the ISR uses, M0/M1 the stack alone
 * (linker/F2812_flash.cmd, 30 % of every block spare). */
#pragma DATA_SECTION(g_bg, "bgdata")
static bg_loop_t g_bg;   /* telemetry rings, frame timer, button edge */

/* data log: every 2nd slow ISR of the log slot (1.875 kHz / 2 = 938 S/s,
 * DLOG_SIZE 128: 137 ms of history), trigger when i_T rises through 0.1 pu */
#define DLOG_PRESCALE    2u

static void halt_on_config_error(void)
{
    /* no PWM was ever enabled; the LED says why we stopped */
    hal_pwm_disable();
    gpio_fault_led(1u);
    for (;;) {
        /* halted: the watchdog is disabled during init, so it stays here */
    }
}

static void apply_command(tlm_cmd_t cmd)
{
    if (cmd == TLM_CMD_RESET_FAULT) {
        (void)pwm_f2812_clear_trip();   /* the board's latch, then the drive's */
    }
    bg_loop_apply(&g_drive, &g_dlog, cmd);
}

int main(void)
{
    f2812_timing_t tm;
    const drive_config_t *cfg = &g_board_config;

    sysctrl_init();
    flash_copy_ramfuncs();
    flash_init();
    gpio_mux_init();
    pie_init();

    if (f2812_timing_t1pr(&tm, (float)BOARD_HSPCLK_HZ, cfg->board.pwm_freq_Hz) != TIMING_OK
        || f2812_timing_deadband(&tm, (float)BOARD_HSPCLK_HZ, cfg->board.dead_time_s) != TIMING_OK
        || f2812_timing_brr(&tm, (float)BOARD_LSPCLK_HZ, (float)BOARD_SCI_BAUD) != TIMING_OK
        || drive_init(&g_drive, cfg) != 0) {
        halt_on_config_error();
    }
    (void)datalog_init(&g_dlog, DLOG_PRESCALE, _IQ(0.1));
    /* i_M, i_T, speed: +-2 pu (the default); Rr: +-0.25 pu (pu of Z_base) */
    (void)datalog_set_full_scale(&g_dlog, 3u, -2);
    bg_loop_init(&g_bg, BG_TLM_PERIOD_TICKS);

    pwm_f2812_init(tm.t1pr, tm.dbtcona);
    adc_f2812_init();
    qep_f2812_init();
    sci_f2812_init(tm.brr);

    /* the watchdog before the interrupts: a hang from here on (an
     * unexpected interrupt included, pie.c) resets the device */
    sysctrl_watchdog_enable();
    isr_install(&g_drive, &g_dlog);
    EINT;
    ERTM;
    pwm_f2812_start();          /* T1 runs: SOC, ADCINT, drive_isr at 15 kHz */

    for (;;) {
        drive_telemetry_t tl;
        uint16_t now = isr_ticks();
        uint16_t button = BOARD_BUTTON_PRESSED() ? 1u : 0u;

        drive_background(&g_drive);

        apply_command(bg_loop_button(&g_bg, button));

        apply_command(sci_f2812_poll(&g_bg.tlm));

        if (bg_loop_frame_due(&g_bg, now) != 0u) {
            bg_loop_send(&g_bg, &g_drive, isr_load_max(), &tl);
            gpio_fault_led((tl.fault != 0u || hal_pwm_tripped() != 0u) ? 1u : 0u);
        }

        sysctrl_watchdog_service();
    }
}
