/**
 * @file isr.c
 * Interrupt glue.  Both ISRs and everything they call run from RAM (flash
 * has 5 wait states at 150 MHz): the control ISR's code in `ramfuncs`
 * (L0/L1), what only the slow ISR calls in `ramfuncs_slow` (H0); except
 * the ISR path's flash set, which runs only in CALIBRATE, once per state
 * change or after a fault decision (tools/bench_size.py FLASH_ROOTS; its
 * flash cycles are in tools/bench_isr.py's model).
 *
 * Two ISRs per PWM period, at two priorities (a multi-rate schedule,
 * drive_step.c / drive_slow.c):
 *
 * The control ISR (ADCINT, PIE 1.6; not interruptible), in order:
 *   1. drive_isr: hal_adc_read first, which reads this period's results
 *      and re-arms at once (sequencer reset, INT_SEQ1 cleared, PIE group 1
 *      acknowledged, the T1 underflow flag cleared; hal_adc_f2812.c), then
 *      the fast path (sensing, protections, voltage model, current loops,
 *      orientation, modulation), the compares, the slow ISR's request
 *      (hal_slow_isr_request: INT14 forced), and last the overrun check
 *      (hal_isr_overrun: T1 underflowed again during this ISR; or the last
 *      slow ISR had not finished);
 *   2. its end time in the period, for the load figure.
 *
 * The slow ISR (INT14, software-forced, served when the control ISR
 * returns): the slot's slow task (drive_slow_isr: speed loop, the
 * regression's filters, the sequence, the observer, the model-based
 * checks: one of eight per period), then the data log in the log slot.
 * It re-enables interrupts with IER reduced to INT1, so that the next
 * control ISR preempts it (software-prioritised nesting: the CPU saved IER
 * on entry and restores it at IRET, SPRU430 "Interrupt handling"): the
 * current loop's deadline depends on the control ISR alone, whatever the
 * slow task costs.  The slow task must end before the next control ISR
 * ends (drive_isr counts it an overrun otherwise); normally it ends long
 * before the next period starts (tools/bench_isr.py: the period's worst).
 * Its end time in the period is the load figure: the period's busy time.
 *
 * Priorities: PDPINTA (1.1) wins over ADCINT (1.6) when both are pending,
 * both over INT14.  No nesting in the control ISR: the trip has already
 * put the outputs in high impedance in hardware, so its ISR can wait for
 * the end of a running control ISR.  An ADCINT that arrives while an
 * overrunning ISR still runs stays pending (PIE acknowledged at the top)
 * and runs next.
 */
#include "DSP281x_Device.h"
#include "adc_f2812.h"
#include "drive.h"
#include "isr.h"
#include "pwm_f2812.h"

#pragma CODE_SECTION(isr_control, "ramfuncs")
#pragma CODE_SECTION(isr_elapsed, "ramfuncs")
#pragma CODE_SECTION(isr_slow, "ramfuncs_slow")

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

    s_ticks++;
    t = (overran != 0u) ? 0xFFFFu : isr_elapsed();
    if (t > s_load_max) {
        s_load_max = t;
    }
}

static interrupt void isr_slow(void)
{
    uint16_t t;

    IER = M_INT1;   /* the control ISR (and PDPINTA) may preempt the slow task */
    EINT;
    drive_slow_isr(s_drive);
    /* i_M, i_T, speed, Rr for a CCS graph (datalog.h), after the slow task
     * of one of the lightest slots (drive_log_due) */
    if (drive_log_due(s_drive) != 0u) {
        drive_get_log_signals(s_drive, s_dlog->in);
        datalog_step(s_dlog);
    }
    DINT;
    /* the period's busy time: this ends after its control ISR (a slow ISR
     * that ran into the next period is an overrun, counted by drive_isr) */
    t = isr_elapsed();
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
    PieVectTable.TINT2 = isr_slow;   /* INT14: forced by hal_slow_isr_request */
    EDIS;
    PieCtrlRegs.PIEIER1.bit.INTx1 = 1u;   /* PDPINTA */
    PieCtrlRegs.PIEIER1.bit.INTx6 = 1u;   /* ADCINT */
    IER |= M_INT1 | M_INT14;
}

uint16_t isr_ticks(void)
{
    return s_ticks;
}

uint16_t isr_load_max(void)
{
    uint16_t m;
    /* read and clear as one: an ISR between the two would raise the maximum
     * and see it cleared unread (the worst period of the frame lost).  The
     * background calls this with interrupts enabled; the section delays an
     * ISR by a few cycles at most. */
    DINT;
    m = s_load_max;
    s_load_max = 0u;
    EINT;
    return m;
}
