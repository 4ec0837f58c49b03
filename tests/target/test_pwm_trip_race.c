/* target_pwm_trip_race: hal_pwm_enable against a PDPINTA edge at any point
 * of its register work (firmware/hal_pwm_f2812.c through tests/target/
 * reg_seam.h: every EvaRegs access of the HAL is a call of reg_seam_eva()).
 *
 * The hardware (SPRU065, "Power drive protection"): a falling edge on
 * PDPINTA clears COMCONA.FCOMPOE (PWM1-6 to high impedance) and sets the
 * flag EVAIFRA.PDPINTA, without the CPU; PDPINTASTATUS follows the line.
 * The control ISR is not interruptible, so the PDPINTA ISR (which latches
 * the trip) runs only after it: whatever hal_pwm_enable writes after the
 * edge stays on the pins until then.  An edge between its status read and
 * its write of FCOMPOE = 1 must leave the outputs off.
 *
 * For every access k of an undisturbed call (and after the last), from both
 * starting states (outputs off: the enabling period; on: every later
 * period), with the line held low or only pulsed: the edge is applied just
 * before access k; after the call FCOMPOE must be 0, and once the PDPINTA
 * ISR has run (pwm_f2812_trip) the trip is latched and the next enable
 * keeps the outputs off. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#define REG_SEAM_NO_MACROS
#include "reg_seam.h"
#include "hal_pwm.h"
#include "pwm_f2812.h"

/* the HAL's registers, as memory; the HAL reaches them through the seam */
static volatile struct EVA_REGS s_eva;
volatile Uint16 IFR;
volatile Uint16 IER;

enum { FAULT_HELD = 0, FAULT_PULSE = 1 };

static uint16_t s_calls;      /* EvaRegs accesses since the arming */
static uint16_t s_edge_at;    /* the edge comes before this access (0xFFFF: never) */
static uint16_t s_kind;       /* FAULT_HELD or FAULT_PULSE */
static uint16_t s_edged;

/* the EV's reaction to a falling edge on PDPINTA (its interrupt enabled) */
static void pdpinta_edge(uint16_t kind)
{
    s_eva.COMCONA.bit.FCOMPOE = 0u;
    s_eva.EVAIFRA.bit.PDPINTA = 1u;
    /* the line: still low, or a pulse already over */
    s_eva.COMCONA.bit.PDPINTASTATUS = (kind == FAULT_PULSE) ? 1u : 0u;
    s_edged = 1u;
}

volatile struct EVA_REGS *reg_seam_eva(void)
{
    if (s_calls == s_edge_at) {
        pdpinta_edge(s_kind);
    }
    s_calls++;
    return &s_eva;
}

/* registers as after pwm_f2812_init with the line high, the HAL's latch
 * clear, the outputs on or off; no edge armed */
static void setup(uint16_t outputs_on)
{
    memset((void *)&s_eva, 0, sizeof s_eva);
    s_eva.COMCONA.bit.CENABLE = 1u;
    s_eva.COMCONA.bit.PDPINTASTATUS = 1u;
    s_eva.EVAIMRA.bit.PDPINTA = 1u;
    s_edge_at = 0xFFFFu;
    s_edged = 0u;
    assert_int_equal(pwm_f2812_clear_trip(), 0u);
    s_eva.COMCONA.bit.FCOMPOE = (outputs_on != 0u) ? 1u : 0u;
    s_calls = 0u;
}

/* EvaRegs accesses of one undisturbed hal_pwm_enable */
static uint16_t accesses_of_enable(uint16_t outputs_on)
{
    setup(outputs_on);
    hal_pwm_enable();
    return s_calls;
}

static void test_enable_without_fault(void **state)
{
    (void)state;
    setup(0u);
    hal_pwm_enable();
    assert_int_equal(s_eva.COMCONA.bit.FCOMPOE, 1u);
    assert_int_equal(hal_pwm_tripped(), 0u);
    hal_pwm_enable();                       /* the next period: stays on */
    assert_int_equal(s_eva.COMCONA.bit.FCOMPOE, 1u);
    assert_int_equal(hal_pwm_tripped(), 0u);
    assert_int_equal(s_eva.COMCONA.bit.CENABLE, 1u);   /* nothing else touched */
}

/* a trip already there: the line low, or a flag no ISR has taken yet */
static void test_enable_refused_over_a_pending_trip(void **state)
{
    (void)state;
    setup(0u);
    s_eva.COMCONA.bit.PDPINTASTATUS = 0u;
    hal_pwm_enable();
    assert_int_equal(s_eva.COMCONA.bit.FCOMPOE, 0u);
    assert_int_equal(hal_pwm_tripped(), 1u);

    setup(0u);
    s_eva.EVAIFRA.bit.PDPINTA = 1u;          /* a pulse that came and went */
    hal_pwm_enable();
    assert_int_equal(s_eva.COMCONA.bit.FCOMPOE, 0u);
    assert_int_equal(hal_pwm_tripped(), 1u);
    assert_int_equal(s_eva.EVAIFRA.bit.PDPINTA, 1u);   /* left for the PDPINTA ISR */
}

static void edge_sweep(uint16_t outputs_on, uint16_t kind)
{
    const uint16_t n = accesses_of_enable(outputs_on);
    uint16_t k;

    assert_true(n >= 1u);
    for (k = 0u; k <= n; k++) {
        setup(outputs_on);
        s_kind = kind;
        s_edge_at = k;
        hal_pwm_enable();
        if (s_edged == 0u) {
            pdpinta_edge(kind);              /* after the call: hardware alone */
        }
        /* the outputs are off as the edge left them, whatever was written */
        if (s_eva.COMCONA.bit.FCOMPOE != 0u) {
            fail_msg("outputs %s, fault %s, edge before access %u of %u: FCOMPOE = 1",
                     outputs_on ? "on" : "off", kind == FAULT_PULSE ? "pulsed" : "held",
                     (unsigned)k, (unsigned)n);
        }
        assert_int_equal(s_eva.EVAIFRA.bit.PDPINTA, 1u);
        /* the PDPINTA ISR runs after the control ISR: latched, and the next
         * period's enable keeps the outputs off even with the line high */
        pwm_f2812_trip();
        assert_int_equal(hal_pwm_tripped(), 1u);
        /* its write-1-to-clear of the flag (memory here: the value written
         * is what must be right), then the flag as the hardware leaves it */
        assert_int_equal(s_eva.EVAIFRA.all, 0x0001u);
        s_eva.EVAIFRA.all = 0u;
        s_eva.COMCONA.bit.PDPINTASTATUS = 1u;
        hal_pwm_enable();
        assert_int_equal(s_eva.COMCONA.bit.FCOMPOE, 0u);
    }
}

static void test_edge_while_enabling_held(void **state)
{
    (void)state;
    edge_sweep(0u, FAULT_HELD);
}

static void test_edge_while_enabling_pulse(void **state)
{
    (void)state;
    edge_sweep(0u, FAULT_PULSE);
}

static void test_edge_while_on_held(void **state)
{
    (void)state;
    edge_sweep(1u, FAULT_HELD);
}

static void test_edge_while_on_pulse(void **state)
{
    (void)state;
    edge_sweep(1u, FAULT_PULSE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_enable_without_fault),
        cmocka_unit_test(test_enable_refused_over_a_pending_trip),
        cmocka_unit_test(test_edge_while_enabling_held),
        cmocka_unit_test(test_edge_while_enabling_pulse),
        cmocka_unit_test(test_edge_while_on_held),
        cmocka_unit_test(test_edge_while_on_pulse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
