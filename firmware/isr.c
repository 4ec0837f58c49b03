/**
 * @file isr.c
 * Interrupt glue.  The control ISR runs from RAM (`ramfuncs`): flash has 5
 * wait states at 150 MHz and the ISR has 10000 cycles per period.
 *
 * Priorities: both ISRs are in PIE group 1; PDPINTA (1.1) wins over ADCINT
 * (1.6) when both are pending.  No nesting: the trip has already put the
 * outputs in high impedance in hardware, so its ISR can wait for the end of
 * a running control ISR.
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
    drive_telemetry_t tl;

    drive_isr(s_drive);    /* hal_adc_read + drive_step + hal_pwm_write */

    /* data log: the signals a CCS graph needs to watch the identification */
    drive_get_telemetry(s_drive, &tl);
    s_dlog->in[0] = tl.i_m;
    s_dlog->in[1] = tl.i_t;
    s_dlog->in[2] = tl.speed;
    s_dlog->in[3] = tl.Rr;
    datalog_step(s_dlog);

    s_ticks++;
    adc_f2812_ack();
    PieCtrlRegs.PIEACK.all = PIEACK_GROUP1;

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
