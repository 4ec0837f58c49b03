/*
 * Overruns of the control ISR (isr_monitor.h): the host HAL's fake reports an
 * ISR that ran past its period (hal_isr_overrun, the F2812's T1 underflow
 * flag set again at the ISR's end).  One or two in a row are counted and
 * reported in telemetry, the drive runs on; ISR_MONITOR_LATCH_RUN in a row
 * latch FAULT_ISR_OVERRUN and turn the bridge off in that same ISR; a fault
 * reset re-arms the latch and keeps the count.  The slow ISR (drive_slow_isr,
 * the F2812's INT14 below the control ISR) found unfinished by the next
 * control ISR counts the same way.
 *
 * The drive runs closed loop on the paper motor (the simulator's plant and
 * the host HAL, as motor_sim) until it is accelerating, so that the bridge
 * is switching when the overruns come.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "drive_rig.h"
#include "isr_monitor.h"

#define PAPER MC_CONFIG_DIR "/paper_motor.ini"

typedef drive_rig_t loop_t;

static loop_t g_loop;

/* one ISR with the given overrun flag; the background at 1 kHz */
static void isr(loop_t *l, uint16_t overrun)
{
    drive_rig_sample(l);
    l->port.overrun = overrun;
    drive_isr(&l->drive);
    drive_slow_isr(&l->drive);
    if ((l->k % 15u) == 0u) {
        drive_background(&l->drive);
    }
    drive_rig_period(l);
}

static int setup(void **state)
{
    loop_t *l = &g_loop;
    (void)state;
    if (drive_rig_start(l, PAPER) != 0) {
        return -1;
    }
    /* to the acceleration (within 3 s: it starts at 2.02 s, after the
     * bridge's curve test), the bridge switching */
    while (l->drive.seq.state != ID_ACCELERATE && l->k < 45000u) {
        isr(l, 0u);
    }
    return (l->drive.seq.state == ID_ACCELERATE && l->port.outputs_enabled != 0u) ? 0 : -1;
}

/* One overrun, then two in a row: counted, reported, no fault, the bridge
 * switches on; the run counter restarts after a normal ISR. */
static void test_isolated_overruns_counted(void **state)
{
    loop_t *l = &g_loop;
    drive_telemetry_t t;
    (void)state;
    isr(l, 1u);
    assert_int_equal(l->drive.prot.ovr.count, 1);
    assert_int_equal(l->drive.prot.ovr.run, 1);
    isr(l, 0u);
    assert_int_equal(l->drive.prot.ovr.run, 0);
    isr(l, 1u);
    isr(l, 1u);
    assert_int_equal(l->drive.prot.ovr.run, ISR_MONITOR_LATCH_RUN - 1u);
    isr(l, 0u);
    drive_get_telemetry(&l->drive, &t);
    assert_int_equal(t.isr_overruns, 3);
    assert_int_equal(t.fault, FAULT_NONE);
    assert_int_equal(l->port.outputs_enabled, 1);
    assert_int_equal(l->drive.seq.state, ID_ACCELERATE);
}

/* The slow ISR unfinished when the next control ISR ends (on the F2812:
 * preempted by it, the period's work too long; here: one control ISR
 * without its slow ISR, then one with the task still marked running): an
 * overrun each, counted with the control ISR's own; the late task still
 * runs, once; no fault for two. */
static void test_slow_isr_late_counted(void **state)
{
    loop_t *l = &g_loop;
    const uint16_t before = l->drive.prot.ovr.count;
    (void)state;
    drive_rig_sample(l);
    l->port.overrun = 0u;
    drive_isr(&l->drive);            /* its slow ISR does not run */
    drive_rig_period(l);
    assert_int_equal(l->drive.prot.ovr.count, before);   /* nothing late yet */
    assert_int_equal(l->drive.sched.slow_due, 1);
    isr(l, 0u);                      /* finds it due: late; then both run */
    assert_int_equal(l->drive.prot.ovr.count, before + 1u);
    assert_int_equal(l->drive.sched.slow_due, 0);
    l->drive.sched.slow_busy = 1u;         /* as if preempted in the middle */
    isr(l, 0u);
    assert_int_equal(l->drive.prot.ovr.count, before + 2u);
    assert_int_equal(l->drive.sched.slow_busy, 0);
    isr(l, 0u);
    assert_int_equal(l->drive.prot.ovr.count, before + 2u);
    assert_int_equal(l->drive.prot.ovr.run, 0);
    assert_int_equal(l->drive.prot.trip.fault, FAULT_NONE);
    assert_int_equal(l->port.outputs_enabled, 1);
}

/* ISR_MONITOR_LATCH_RUN in a row: the fault is latched and the outputs are
 * off at the end of the ISR that saw the last one; they stay off; a reset
 * re-arms the latch (the count stays). */
static void test_consecutive_overruns_latch_fault(void **state)
{
    loop_t *l = &g_loop;
    uint16_t i;
    uint16_t before = l->drive.prot.ovr.count;
    (void)state;
    for (i = 0u; i + 1u < ISR_MONITOR_LATCH_RUN; i++) {
        isr(l, 1u);
        assert_int_equal(l->port.outputs_enabled, 1);
        assert_int_equal(l->drive.prot.trip.fault, FAULT_NONE);
    }
    isr(l, 1u);
    assert_int_equal(l->drive.prot.trip.fault, FAULT_ISR_OVERRUN);
    assert_int_equal(l->port.outputs_enabled, 0);
    assert_int_equal(l->drive.prot.ovr.count, before + ISR_MONITOR_LATCH_RUN);
    for (i = 0u; i < 100u; i++) {
        isr(l, 0u);
        assert_int_equal(l->port.outputs_enabled, 0);
    }
    assert_int_equal(l->drive.seq.state, ID_FAULT);
    assert_int_equal(l->drive.telemetry.fault, FAULT_ISR_OVERRUN);
    drive_command(&l->drive, DRIVE_CMD_RESET_FAULT);
    drive_background(&l->drive);
    isr(l, 0u);
    assert_int_equal(l->drive.prot.trip.fault, FAULT_NONE);
    assert_int_equal(l->drive.prot.ovr.fault, 0);
    assert_int_equal(l->drive.prot.ovr.count, before + ISR_MONITOR_LATCH_RUN);
}

/* The order of the ISR's HAL calls: the samples are read (and on the F2812
 * the ADC and the interrupt re-armed, hal_adc_f2812.c) before anything
 * else, the slow ISR is requested after the outputs, and the overrun is
 * checked after everything else. */
static void test_hal_call_order(void **state)
{
    loop_t *l = &g_loop;
    (void)state;
    l->port.n_calls = 0u;
    isr(l, 0u);
    assert_true(l->port.n_calls >= 3u);
    assert_int_equal(l->port.calls[0], HAL_HOST_ADC_READ);
    assert_int_equal(l->port.calls[l->port.n_calls - 2u], HAL_HOST_SLOW_REQUEST);
    assert_int_equal(l->port.calls[l->port.n_calls - 1u], HAL_HOST_ISR_OVERRUN);
}

/* The module alone: the counters saturate instead of wrapping. */
static void test_monitor_saturates(void **state)
{
    isr_monitor_t m;
    uint32_t i;
    (void)state;
    isr_monitor_init(&m);
    m.overrun = 1u;
    for (i = 0u; i < 70000u; i++) {
        isr_monitor_step(&m);
    }
    assert_int_equal(m.count, 0xFFFF);
    assert_int_equal(m.run, 0xFFFF);
    assert_int_equal(m.fault, 1);
    isr_monitor_reset(&m);
    assert_int_equal(m.fault, 0);
    assert_int_equal(m.count, 0xFFFF);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_isolated_overruns_counted),
        cmocka_unit_test(test_slow_isr_late_counted),
        cmocka_unit_test(test_consecutive_overruns_latch_fault),
        cmocka_unit_test(test_hal_call_order),
        cmocka_unit_test(test_monitor_saturates),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
