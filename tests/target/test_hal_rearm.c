/* target_hal_rearm: the F2812 HAL's ISR-path register work, run on the host
 * against the shim's register declarations (tests/target/ti_shim: TI's
 * names and layout), the registers being plain memory here.
 *
 *  - hal_adc_read re-arms at the top of the ISR: it returns this period's
 *    results, then resets the sequencer (the next SOC starts at CONV00, so
 *    an overrun cannot shift the next conversion into RESULT4-7), clears
 *    INT_SEQ1, acknowledges PIE group 1 and clears the T1 underflow flag -
 *    and writes that flag with 1 in its own bit only (a read-modify-write
 *    would also clear a pending PDPINTA flag);
 *  - hal_isr_overrun reads that flag: set again = the ISR overran;
 *  - hal_slow_isr_request forces INT14 (IFR bit 13) and no other.
 * The drive-level order (hal_adc_read first, hal_isr_overrun last, in
 * drive_isr) is the host-HAL test in tests/fault/test_isr_overrun.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "DSP281x_Device.h"
#include "hal_adc.h"
#include "hal_pwm.h"

/* the registers, as memory */
volatile struct ADC_REGS AdcRegs;
volatile struct EVA_REGS EvaRegs;
volatile struct PIE_CTRL_REGS PieCtrlRegs;
volatile Uint16 IFR;
volatile Uint16 IER;

static void clear_regs(void)
{
    memset((void *)&AdcRegs, 0, sizeof AdcRegs);
    memset((void *)&EvaRegs, 0, sizeof EvaRegs);
    memset((void *)&PieCtrlRegs, 0, sizeof PieCtrlRegs);
}

static void test_read_then_rearm(void **state)
{
    hal_adc_sample_t s;
    (void)state;
    clear_regs();
    AdcRegs.ADCRESULT0 = 0x1230u;
    AdcRegs.ADCRESULT1 = 0x4560u;
    AdcRegs.ADCRESULT2 = 0x7890u;
    AdcRegs.ADCRESULT3 = 0xFFF0u;           /* B1: not connected, not read */
    hal_adc_read(&s);
    assert_int_equal(s.ia_raw, 0x1230u);
    assert_int_equal(s.ib_raw, 0x4560u);
    assert_int_equal(s.vdc_raw, 0x7890u);
    assert_int_equal(AdcRegs.ADCTRL2.bit.RST_SEQ1, 1u);
    assert_int_equal(AdcRegs.ADCST.bit.INT_SEQ1_CLR, 1u);
    assert_int_equal(PieCtrlRegs.PIEACK.all, 0x0001u);   /* group 1: ADCINT, PDPINTA */
    assert_int_equal(EvaRegs.EVAIFRA.all, 0x0200u);       /* T1UFINT only */
}

/* A pending PDPINTA flag (bit 0) must survive the underflow flag's clear:
 * the write carries T1UFINT alone (hardware: writing 0 leaves a flag). */
static void test_underflow_clear_spares_trip_flag(void **state)
{
    hal_adc_sample_t s;
    (void)state;
    clear_regs();
    EvaRegs.EVAIFRA.all = 0x0201u;   /* PDPINTA and T1UFINT pending */
    hal_adc_read(&s);
    /* on the device the 1 clears T1UFINT and the 0 leaves PDPINTA; here
     * the register is memory: the value written is what must be right */
    assert_int_equal(EvaRegs.EVAIFRA.all, 0x0200u);
}

static void test_overrun_flag(void **state)
{
    (void)state;
    clear_regs();
    assert_int_equal(hal_isr_overrun(), 0u);
    EvaRegs.EVAIFRA.bit.T1UFINT = 1u;   /* T1 underflowed again */
    assert_int_equal(hal_isr_overrun(), 1u);
    EvaRegs.EVAIFRA.all = 0x0001u;      /* only PDPINTA: not an overrun */
    assert_int_equal(hal_isr_overrun(), 0u);
}

static void test_slow_request_forces_int14(void **state)
{
    (void)state;
    IFR = 0x0001u;   /* INT1 pending (the next control ISR): must stay */
    hal_slow_isr_request();
    assert_int_equal(IFR, 0x2001u);   /* OR IFR,#M_INT14: bit 13 added */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_read_then_rearm),
        cmocka_unit_test(test_underflow_clear_spares_trip_flag),
        cmocka_unit_test(test_overrun_flag),
        cmocka_unit_test(test_slow_request_forces_int14),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
