/**
 * @file isr.c
 * Interrupt glue.  The control ISR and everything it calls run from RAM
 * (`ramfuncs`): flash has 5 wait states at 150 MHz.
 *
 * The control ISR, in order:
 *   1. the data log of the signals the last ISR left (so that the overrun
 *      check below is the ISR's last action; every 2nd ISR it stores);
 *   2. drive_isr: hal_adc_read first, which reads this period's results
 *      and re-arms at once (sequencer reset, INT_SEQ1 cleared, PIE group 1
 *      acknowledged, the T1 underflow flag cleared; hal_adc_f2812.c), then
 *      the control, the compares, and last the overrun check
 *      (hal_isr_overrun: T1 underflowed again during this ISR);
 *   3. the ISR's duration for telemetry: the elapsed T1 ticks since the
 *      period start, or 0xFFFF once the ISR overran (T1CNT then describes
 *      the next period and would read short).
 *
 * Priorities: both ISRs are in PIE group 1; PDPINTA (1.1) wins over ADCINT
 * (1.6) when both are pending.  No nesting: the trip has already put the
 * outputs in high impedance in hardware, so its ISR can wait for the end of
 * a running control ISR.  An ADCINT that arrives while an overrunning ISR
 * still runs stays pending (PIE acknowledged at the top) and runs next.
 */
#include "DSP281x_Device.h"
#include "adc_f2812.h"
#include "drive.h"
#include "isr.h"
#include "pwm_f2812.h"

#pragma CODE_SECTION(isr_control, "ramfuncs")
#pragma CODE_SECTION(isr_elapsed, "ramfuncs")

static drive_t *s_drive;
static datalog_t *s_dlog;
static volatile uint16_t s_ticks;
static volatile uint16_t s_load_max;

/* Elapsed T1 ticks since the period start (T1 underflow): T1 counts up to
 * T1PR then down (GPTCONA.T1STAT = 1 while counting up). */
static uint16_t isr_elapsed(void)
{
    uint16_t cnt = EvaRegs.T1CNT;
    uint16_t pr = pwm_f2812_period();
    if (EvaRegs.GPTCONA.bit.T1STAT != 0u) {
        return cnt;
    }
    return (uint16_t)(2u * pr - cnt);
}

static interrupt void isr_control(void)
{
    uint16_t t;

    const uint16_t overran = drive_isr(s_drive);   /* hal_adc_read (re-arm) ... hal_isr_overrun */

    /* i_M, i_T, speed, Rr for a CCS graph (datalog.h), in the ISR of the
     * lightest slow slot (drive_log_due): the log's cost never adds to the
     * heaviest ISR */
    if (drive_log_due(s_drive) != 0u) {
        drive_get_log_signals(s_drive, s_dlog->in);
        datalog_step(s_dlog);
    }

    s_ticks++;
    t = (overran != 0u) ? 0xFFFFu : isr_elapsed();
    if (t > s_load_max) {
        s_load_max = t;
    }
}

static interrupt void isr_pdpinta(void)
{
    /* the bridge is already off (hardware); latch so that nothing turns it
     * back on until the fault is reset with the line high again.  The drive
     * sees hal_pwm_tripped() in its next period and latches its own fault. */
    pwm_f2812_trip();
    PieCtrlRegs.PIEACK.all = PIEACK_GROUP1;
}

void isr_install(drive_t *drive, datalog_t *dlog)
{
    /* COFF ABI: .ebss is not zeroed by _c_int00, so set every static here */
    s_drive = drive;
    s_dlog = dlog;
    s_ticks = 0u;
    s_load_max = 0u;
    EALLOW;
    PieVectTable.ADCINT = isr_control;
    PieVectTable.PDPINTA = isr_pdpinta;
    EDIS;
    PieCtrlRegs.PIEIER1.bit.INTx1 = 1u;   /* PDPINTA */
    PieCtrlRegs.PIEIER1.bit.INTx6 = 1u;   /* ADCINT */
    IER |= M_INT1;
}

uint16_t isr_ticks(void)
{
    return s_ticks;
}

uint16_t isr_load_max(void)
{
    uint16_t m = s_load_max;
    s_load_max = 0u;
    return m;
}
