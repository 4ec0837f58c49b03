/**
 * @file hal_pwm_f2812.c
 * hal_pwm.h on EV-A (SPRU065).
 *
 * T1 counts 0 -> T1PR -> 0 (TMODE = 01, continuous up/down).  Full compare
 * units 1..3 with ACTRA = BOARD_ACTRA (PWM1/3/5 active high, PWM2/4/6
 * active low): in up/down mode an active-high output is high while
 * T1CNT > CMPRx, which is the convention of hal_pwm.h (d = (T1PR - CMPRx) /
 * T1PR).  CLD = 00: CMPRx reload at underflow, i.e. the next period.
 * The dead band (DBTCONA) delays each rising edge of the pair's outputs.
 *
 * PDPINTA (T1CTRIP/PDPINTA pin, active low): with its interrupt enabled
 * (EVAIMRA.PDPINTA = 1) the EV hardware puts PWM1..6 in high impedance and
 * clears FCOMPOE on a falling edge, without the CPU; the ISR only latches
 * the fault so that software cannot re-enable the outputs by accident.
 */
#include "DSP281x_Device.h"
#include "board_config.h"
#include "hal_pwm.h"
#include "pwm_f2812.h"

/* everything the control ISR calls runs from RAM (flash: 5 wait states) */
#pragma CODE_SECTION(hal_pwm_write, "ramfuncs")
#pragma CODE_SECTION(hal_pwm_enable, "ramfuncs")
#pragma CODE_SECTION(hal_pwm_disable, "ramfuncs")
#pragma CODE_SECTION(hal_pwm_tripped, "ramfuncs")
#pragma CODE_SECTION(hal_isr_overrun, "ramfuncs")
#pragma CODE_SECTION(pwm_f2812_period, "ramfuncs")
#pragma CODE_SECTION(hal_slow_isr_request, "ramfuncs")

/* T1CON (SPRU065, GP timer control register): FREE (bit 15) = 0 and SOFT
 * (bit 14) = 1: on an emulator halt T1 completes its current period and
 * stops at zero, chosen on purpose over running free: with the CPU halted
 * the current loop is open, and a free-running PWM would keep applying the
 * last duties to a motor whose back-EMF and current then nobody controls.
 * Stopped at T1CNT = 0, each phase's compare output holds its state below
 * the compare (upper switch off, lower on: the zero vector), which brakes a
 * turning motor through its own impedance; halt the debugger with the motor
 * at rest, or send $C,X first.  TMODE (12:11) = 01 continuous up/down,
 * TPS = 000 (HSPCLK/1), TCLKS10 = 00 internal clock, TECMPR = 0 (the T1
 * compare output is not used), TENABLE = 0 until pwm_f2812_start. */
#define T1CON_UPDOWN_SOFT  0x4800u
/* EVAIFRA: T1 underflow flag (write 1 to clear; hal_adc_read clears it) */
#define EVAIFRA_T1UFINT 0x0200u

static volatile uint16_t s_tripped;   /* 1 once PDPINTA fired, until re-enabled */
static uint16_t s_t1pr;

void pwm_f2812_init(uint16_t t1pr, uint16_t dbtcona)
{
    s_t1pr = t1pr;
    s_tripped = 0u;

    EvaRegs.T1CON.all = T1CON_UPDOWN_SOFT;   /* stopped: TENABLE = 0 */
    EvaRegs.T1PR = t1pr;
    EvaRegs.T1CNT = 0u;
    EvaRegs.T1CMPR = 0u;

    /* GPTCONA: T1TOADC = 01 (SOC on T1 underflow), TCMPOE = 0 (T1PWM pin
     * not used) */
    EvaRegs.GPTCONA.all = 0u;
    EvaRegs.GPTCONA.bit.T1TOADC = 1u;

    /* compares at 50 % until the drive writes its first values */
    EvaRegs.CMPR1 = (uint16_t)(t1pr / 2u);
    EvaRegs.CMPR2 = (uint16_t)(t1pr / 2u);
    EvaRegs.CMPR3 = (uint16_t)(t1pr / 2u);
    EvaRegs.ACTRA.all = BOARD_ACTRA;
    EvaRegs.DBTCONA.all = dbtcona;

    /* EXTCONA = 0: combined compare-output mode, in which FCOMPOE gates all
     * six outputs and PDPINTA acts on them together */
    EALLOW;
    EvaRegs.EXTCONA.all = 0u;
    EDIS;

    EvaRegs.COMCONA.all = 0u;
    EvaRegs.COMCONA.bit.CLD = 0u;        /* reload CMPRx at underflow */
    EvaRegs.COMCONA.bit.ACTRLD = 0u;     /* reload ACTRA at underflow */
    EvaRegs.COMCONA.bit.SVENABLE = 0u;   /* software SVPWM (svgen) */
    EvaRegs.COMCONA.bit.FCOMPOE = 0u;    /* outputs high-Z until enabled */
    EvaRegs.COMCONA.bit.CENABLE = 1u;

    /* PDPINTA: clear a stale flag (write 1), then unmask */
    EvaRegs.EVAIFRA.all = 0x0001u;
    EvaRegs.EVAIMRA.bit.PDPINTA = 1u;
}

void pwm_f2812_start(void)
{
    EvaRegs.T1CON.bit.TENABLE = 1u;
}

uint16_t pwm_f2812_period(void)
{
    return s_t1pr;
}

void pwm_f2812_trip(void)
{
    s_tripped = 1u;
    EvaRegs.COMCONA.bit.FCOMPOE = 0u;   /* already cleared by hardware */
    EvaRegs.EVAIFRA.all = 0x0001u;      /* PDPINTA flag: write 1 to clear */
}

void hal_pwm_write(const hal_pwm_compare_t *c)
{
    /* the drive clamps to [0, T1PR]; clamp again here because a compare
     * above T1PR would never match and leave a phase stuck (no SVPWM) */
    EvaRegs.CMPR1 = (c->cmpr[0] <= s_t1pr) ? c->cmpr[0] : s_t1pr;
    EvaRegs.CMPR2 = (c->cmpr[1] <= s_t1pr) ? c->cmpr[1] : s_t1pr;
    EvaRegs.CMPR3 = (c->cmpr[2] <= s_t1pr) ? c->cmpr[2] : s_t1pr;
}

void hal_pwm_enable(void)
{
    /* Called every period while the drive wants the bridge on.  A PDPINTA
     * edge clears FCOMPOE in hardware and sets EVAIFRA.PDPINTA (SPRU065,
     * "Power drive protection interrupt"); its ISR latches the trip only
     * after this non-interruptible ISR, so anything written here after the
     * edge stays on the pins until then.  Hence: no write at all while the
     * outputs are on (a read-modify-write of COMCONA every period could set
     * FCOMPOE again just after the hardware cleared it), and on the off-to-on
     * transition the flag checked again after the write. */
    if (s_tripped != 0u) {
        return;   /* latched: cleared only by the fault reset, line high */
    }
    if (EvaRegs.COMCONA.bit.FCOMPOE != 0u) {
        return;   /* on, and no edge since (an edge would have cleared it) */
    }
    /* never while the line is low (PDPINTASTATUS = 0), nor over an edge no
     * ISR has taken yet (the flag; left set for that ISR) */
    if (EvaRegs.COMCONA.bit.PDPINTASTATUS == 0u || EvaRegs.EVAIFRA.bit.PDPINTA != 0u) {
        s_tripped = 1u;
        return;
    }
    EvaRegs.COMCONA.bit.FCOMPOE = 1u;
    /* an edge between the checks and the write: the write may have undone
     * the hardware's clear, but the flag is set whatever FCOMPOE was */
    if (EvaRegs.EVAIFRA.bit.PDPINTA != 0u) {
        EvaRegs.COMCONA.bit.FCOMPOE = 0u;
        s_tripped = 1u;
    }
}

void hal_pwm_disable(void)
{
    EvaRegs.COMCONA.bit.FCOMPOE = 0u;
}

uint16_t hal_pwm_tripped(void)
{
    return s_tripped;
}

uint16_t hal_isr_overrun(void)
{
    /* the flag is set at every T1 underflow (masked or not) and was cleared
     * when this ISR read its samples: set again means the next period has
     * begun while the ISR still ran */
    return (uint16_t)((EvaRegs.EVAIFRA.all & EVAIFRA_T1UFINT) != 0u);
}

/* INT14 (CPU timer 2's vector, free without DSP/BIOS) forced in software:
 * IFR can be changed only by OR/AND IFR, which `IFR |=` compiles to
 * (SPRU514, "The cregister keyword"); the CPU serves it when the control
 * ISR returns, below INT1 in priority (firmware/isr.c: isr_slow). */
void hal_slow_isr_request(void)
{
    IFR |= M_INT14;
}

uint16_t pwm_f2812_clear_trip(void)
{
    if (EvaRegs.COMCONA.bit.PDPINTASTATUS != 0u) {
        s_tripped = 0u;
    }
    return s_tripped;
}
