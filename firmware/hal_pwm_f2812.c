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

#pragma CODE_SECTION(hal_pwm_write, "ramfuncs")
#pragma CODE_SECTION(hal_pwm_tripped, "ramfuncs")
#pragma CODE_SECTION(pwm_f2812_period, "ramfuncs")

/* T1CON: TMODE = 01 up/down, TPS = 000 (HSPCLK/1), TENABLE, TCLKS10 = 00
 * internal clock, TECMPR = 0 (T1 compare output not used), FREE = 1:
 * on an emulator halt T1 runs on (the bridge must not freeze mid-period
 * with a switch on). */
#define T1CON_UPDOWN_FREE  0x4800u

static volatile uint16_t s_tripped;   /* 1 once PDPINTA fired, until re-enabled */
static uint16_t s_t1pr;

void pwm_f2812_init(uint16_t t1pr, uint16_t dbtcona)
{
    s_t1pr = t1pr;
    s_tripped = 0u;

    EvaRegs.T1CON.all = T1CON_UPDOWN_FREE;   /* stopped: TENABLE = 0 */
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
    /* never over a latched trip, nor while the fault line is still low
     * (PDPINTASTATUS = 0): the latch is cleared only when the line is high */
    if (EvaRegs.COMCONA.bit.PDPINTASTATUS == 0u) {
        s_tripped = 1u;
        return;
    }
    if (s_tripped != 0u) {
        return;
    }
    EvaRegs.COMCONA.bit.FCOMPOE = 1u;
}

void hal_pwm_disable(void)
{
    EvaRegs.COMCONA.bit.FCOMPOE = 0u;
}

uint16_t hal_pwm_tripped(void)
{
    return s_tripped;
}

uint16_t pwm_f2812_clear_trip(void)
{
    if (EvaRegs.COMCONA.bit.PDPINTASTATUS != 0u) {
        s_tripped = 0u;
    }
    return s_tripped;
}
