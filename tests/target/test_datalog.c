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

/* every channel at full scale 8 pu: one sample of the ramp (1/1024 pu)
 * is 4 LSB of the 16-bit Q15 sample, exact */
static void scale8(datalog_t *d)
{
    uint16_t c;
    for (c = 0u; c < DLOG_CHANNELS; c++) {
        assert_int_equal(datalog_set_full_scale(d, c, 3), 0);
    }
}

/* channel c at call k: _IQ(k / 1024) + c (exact in Q24 and in float) */
static void feed(datalog_t *d, int32_t k)
{
    uint16_t c;
    for (c = 0u; c < DLOG_CHANNELS; c++) {
        d->in[c] = _IQmpyI32(_IQ(0.0009765625), k) + _IQmpyI32(_IQ(1.0), (int32_t)c);
    }
    datalog_step(d);
}

/* the ramp's sample index of a stored value (full scale 8 pu: v / 4) */
static int32_t sample_of(int16_t v)
{
    return (int32_t)v / 4;
}

static void test_free_running_wraps(void **state)
{
    int32_t k;
    const int32_t n = (int32_t)DLOG_SIZE;
    (void)state;
    assert_int_equal(datalog_init(&s_d, 1u, _IQ(0.0)), 0);
    scale8(&s_d);
    for (k = 0; k < n + 44; k++) {
        feed(&s_d, k);
    }
    /* n + 44 writes into n slots: slot i holds sample n + i for i < 44, the
     * first pass's sample from slot 44 on */
    assert_int_equal(s_d.state, DLOG_FREE);
    assert_int_equal(s_d.idx, 44);
    assert_int_equal(sample_of(s_d.buf[0][0]), n);
    assert_int_equal(sample_of(s_d.buf[0][43]), n + 43);
    assert_int_equal(sample_of(s_d.buf[0][44]), 44);
    assert_int_equal(sample_of((int16_t)(s_d.buf[3][44] - 3 * 4096)), 44);
}

static void test_trigger_centres_the_capture(void **state)
{
    int32_t k, i;
    const int32_t half = (int32_t)(DLOG_SIZE / 2u);
    (void)state;
    /* prescale 2, trigger when channel 0 rises through sample 600 / 1024 */
    assert_int_equal(datalog_init(&s_d, 2u, _IQmpyI32(_IQ(0.0009765625), 600)), 0);
    scale8(&s_d);
    for (k = 0; k < 100; k++) {
        feed(&s_d, k);
    }
    datalog_arm(&s_d);
    for (k = 100; k < 2000 && s_d.state != DLOG_DONE; k++) {
        feed(&s_d, k);
    }
    assert_int_equal(s_d.state, DLOG_DONE);
    /* writes happen at odd k (skip reaches 2 on the 2nd call); the first
     * write >= 600 is k = 601; then DLOG_SIZE/2 more writes: last k = 601 + 2*half */
    assert_int_equal(k, 601 + 2 * half + 1);
    for (i = 0; i < (int32_t)DLOG_SIZE; i++) {
        uint16_t slot = (uint16_t)((s_d.first + (uint16_t)i) % DLOG_SIZE);
        /* oldest first: half - 1 writes before the trigger, the trigger, half after */
        assert_int_equal(sample_of(s_d.buf[0][slot]), 601 + 2 * (i - (half - 1)));
    }
    /* frozen: more input changes nothing */
    feed(&s_d, 5000);
    assert_int_equal(sample_of(s_d.buf[0][s_d.first]), 601 - 2 * (half - 1));
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

static void test_sixteen_bits_saturate(void **state)
{
    (void)state;
    /* 16-bit samples: 4 x DLOG_SIZE words, not twice that */
    assert_int_equal(sizeof s_d.buf, DLOG_CHANNELS * DLOG_SIZE * sizeof(int16_t));
    assert_int_equal(datalog_init(&s_d, 1u, _IQ(0.5)), 0);
    assert_int_equal(s_d.fs_exp[2], DLOG_FS_EXP_DEFAULT);
    /* default full scale 2 pu: 1 pu -> 16384, -2 pu -> -32768, beyond -> saturated */
    s_d.in[0] = _IQ(1.0);
    s_d.in[1] = _IQ(-2.0);
    s_d.in[2] = _IQ(2.5);
    s_d.in[3] = _IQ(-7.0);
    datalog_step(&s_d);
    assert_int_equal(s_d.buf[0][0], 16384);
    assert_int_equal(s_d.buf[1][0], -32768);
    assert_int_equal(s_d.buf[2][0], 32767);
    assert_int_equal(s_d.buf[3][0], -32768);
    /* full scale 0.25 pu (Rr): 0.1 pu -> 13107 (floor of 13107.2) */
    assert_int_equal(datalog_set_full_scale(&s_d, 3u, -2), 0);
    s_d.in[3] = _IQ(0.1);
    datalog_step(&s_d);
    assert_int_equal(s_d.buf[3][1], 13107);
#if MATH_TYPE == IQ_MATH
    /* negative values floor toward -infinity, as an arithmetic shift (one
     * Q24 LSB below zero: the IQ build's raw words) */
    assert_int_equal(datalog_q15(-1, (uint16_t)(GLOBAL_Q - 15 + 1)), -1);
    assert_int_equal(datalog_q15(0, (uint16_t)(GLOBAL_Q - 15 + 1)), 0);
#endif
    /* bad channel or exponent: refused */
    assert_int_equal(datalog_set_full_scale(&s_d, DLOG_CHANNELS, 0), 1);
    assert_int_equal(datalog_set_full_scale(&s_d, 0u, DLOG_FS_EXP_MAX + 1), 1);
    assert_int_equal(datalog_set_full_scale(&s_d, 0u, DLOG_FS_EXP_MIN - 1), 1);
    assert_int_equal(s_d.fs_exp[0], DLOG_FS_EXP_DEFAULT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_free_running_wraps),
        cmocka_unit_test(test_trigger_centres_the_capture),
        cmocka_unit_test(test_no_trigger_on_falling),
        cmocka_unit_test(test_sixteen_bits_saturate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
