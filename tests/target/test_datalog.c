/* target_datalog: the triggered circular log against the expected sample
 * indices (the input is a known ramp, so every stored value names the
 * sample it came from: exact, no tolerance). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>

#include "datalog.h"

static datalog_t s_d;

/* channel c at call k: _IQ(k / 1024) + c (exact in Q24 and in float) */
static void feed(datalog_t *d, int32_t k)
{
    uint16_t c;
    for (c = 0u; c < DLOG_CHANNELS; c++) {
        d->in[c] = _IQmpyI32(_IQ(0.0009765625), k) + _IQmpyI32(_IQ(1.0), (int32_t)c);
    }
    datalog_step(d);
}

static int32_t sample_of(_iq v)
{
    return (int32_t)(_IQtoF(v) * 1024.0f + 0.5f);
}

static void test_free_running_wraps(void **state)
{
    int32_t k;
    (void)state;
    assert_int_equal(datalog_init(&s_d, 1u, _IQ(0.0)), 0);
    for (k = 0; k < 300; k++) {
        feed(&s_d, k);
    }
    /* 300 writes into 256 slots: slot i holds sample 256 + i for i < 44 */
    assert_int_equal(s_d.state, DLOG_FREE);
    assert_int_equal(s_d.idx, 300 - 256);
    assert_int_equal(sample_of(s_d.buf[0][0]), 256);
    assert_int_equal(sample_of(s_d.buf[0][43]), 299);
    assert_int_equal(sample_of(s_d.buf[0][44]), 44);
    assert_int_equal(sample_of(s_d.buf[3][44] - _IQ(3.0)), 44);
}

static void test_trigger_centres_the_capture(void **state)
{
    int32_t k, i;
    (void)state;
    /* prescale 2, trigger when channel 0 rises through sample 600 / 1024 */
    assert_int_equal(datalog_init(&s_d, 2u, _IQmpyI32(_IQ(0.0009765625), 600)), 0);
    for (k = 0; k < 100; k++) {
        feed(&s_d, k);
    }
    datalog_arm(&s_d);
    for (k = 100; k < 2000 && s_d.state != DLOG_DONE; k++) {
        feed(&s_d, k);
    }
    assert_int_equal(s_d.state, DLOG_DONE);
    /* writes happen at odd k (skip reaches 2 on the 2nd call); the first
     * write >= 600 is k = 601; then 128 more writes: last k = 601 + 2*128 */
    assert_int_equal(k, 601 + 2 * 128 + 1);
    for (i = 0; i < (int32_t)DLOG_SIZE; i++) {
        uint16_t slot = (uint16_t)((s_d.first + (uint16_t)i) % DLOG_SIZE);
        /* oldest first: 127 writes before the trigger, the trigger, 128 after */
        assert_int_equal(sample_of(s_d.buf[0][slot]), 601 + 2 * (i - 127));
    }
    /* frozen: more input changes nothing */
    feed(&s_d, 5000);
    assert_int_equal(sample_of(s_d.buf[0][s_d.first]), 601 - 2 * 127);
}

static void test_no_trigger_on_falling(void **state)
{
    int32_t k;
    (void)state;
    assert_int_equal(datalog_init(&s_d, 1u, _IQ(0.5)), 0);
    feed(&s_d, 1000);        /* above the level before arming */
    datalog_arm(&s_d);
    for (k = 999; k > 0; k--) {
        feed(&s_d, k);       /* falling through 0.5: no trigger */
    }
    assert_int_equal(s_d.state, DLOG_ARMED);
    assert_int_equal(datalog_init(&s_d, 0u, _IQ(0.5)), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_free_running_wraps),
        cmocka_unit_test(test_trigger_centres_the_capture),
        cmocka_unit_test(test_no_trigger_on_falling),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
