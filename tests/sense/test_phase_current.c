/* phase_current: raw ADC -> pu scaling, ic, offset calibration (accepted,
 * rejected, window edge), rail flags and argument checks, against
 * i = polarity * gain * (raw - offset) / 32768 evaluated in double. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "IQmathLib.h"
#include "phase_current.h"

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
#else
static double to_d(_iq x) { return (double)x; }
#endif
#define LSB 5.9604644775390625e-8   /* 2^-24 */

static void assert_near(double got, double want, double tol, const char *what, uint32_t raw)
{
    if (!(fabs(got - want) <= tol)) {
        print_error("%s raw=%u: got %.10f want %.10f err %.3g LSB\n", what, (unsigned)raw, got,
                    want, (got - want) / LSB);
        fail();
    }
}

/* Unit gain, nominal offset: every ADC code from 0 to 4095 (raw 0..0xFFF0)
 * gives (raw - 32768)/32768 exactly: the count * 2^-15 is exact in Q24 and
 * in float (an integer below 2^16 times a power of two) and the product by
 * a gain of exactly 1.0 is exact.  Bound 0 LSB.  ic = -ia - ib exactly. */
static void test_scaling_unit_gain(void **state)
{
    phase_current_t pc;
    uint32_t code;
    (void)state;

    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
    for (code = 0u; code < 4096u; code++) {
        uint16_t raw = (uint16_t)(code << 4);
        uint16_t raw_b = (uint16_t)((4095u - code) << 4);
        pc.ia_raw = raw;
        pc.ib_raw = raw_b;
        phase_current_step(&pc);
        assert_near(to_d(pc.ia), ((double)raw - 32768.0) / 32768.0, 0.0, "ia", raw);
        assert_near(to_d(pc.ib), ((double)raw_b - 32768.0) / 32768.0, 0.0, "ib", raw_b);
        assert_true(pc.ic == -pc.ia - pc.ib);
    }
    /* spot values: full negative scale -1 pu, +1 pu - 16 counts */
    pc.ia_raw = 0u;
    pc.ib_raw = 0xFFF0u;
    phase_current_step(&pc);
    assert_true(to_d(pc.ia) == -1.0);
    assert_true(to_d(pc.ib) == 65520.0 / 32768.0 - 1.0);
}

/* Gain correction 1.05 / 0.97, reversed polarity, offsets 33000 / 32500.
 * Bound 3 LSB: the gain is truncated to Q24 (< 1 LSB relative to 1.0, times
 * |x| < 1.1 pu: < 1.1 LSB), the product truncated (< 1 LSB); float: gain
 * and product each rounded to 24 bits (< 0.5 ulp of values < 2: < 2 LSB). */
static void test_scaling_gain_polarity_offset(void **state)
{
    phase_current_t pc;
    uint32_t code;
    (void)state;

    assert_int_equal(phase_current_init(&pc, 1.05f, 0.97f, -1, 0.05f), PHASE_CURRENT_OK);
    pc.offset_a = 33000u;
    pc.offset_b = 32500u;
    for (code = 0u; code < 4096u; code += 3u) {
        uint16_t raw = (uint16_t)(code << 4);
        pc.ia_raw = raw;
        pc.ib_raw = raw;
        phase_current_step(&pc);
        assert_near(to_d(pc.ia), -1.05 * ((double)raw - 33000.0) / 32768.0, 3.0 * LSB, "ia", raw);
        assert_near(to_d(pc.ib), -0.97 * ((double)raw - 32500.0) / 32768.0, 3.0 * LSB, "ib", raw);
        /* ic from the outputs, exact */
        assert_true(pc.ic == -pc.ia - pc.ib);
    }
}

/* Calibration over 1024 samples of a deterministic ripple (triangle of
 * +-5 codes, i.e. +-80 raw counts, as ADC noise) around 33000.3 (phase a)
 * and 32100.6 (phase b): the offset must be the rounded mean of exactly
 * what was fed (integer arithmetic: exact), and a reading of offset + 1000
 * then gives 1000/32768 pu exactly (gain 1). */
static void test_calibration_accepted(void **state)
{
    phase_current_t pc;
    uint32_t k;
    uint64_t sum_a = 0u, sum_b = 0u;
    phase_current_cal_t st = PHASE_CURRENT_CAL_IDLE;
    (void)state;

    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_step(&pc), PHASE_CURRENT_CAL_IDLE);
    assert_int_equal(phase_current_cal_design(&pc, 1024u), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_start(&pc, 1024u), PHASE_CURRENT_OK);
    for (k = 0u; k < 1024u; k++) {
        int32_t tri = (int32_t)(k % 11u) - 5;   /* -5..5 codes */
        /* 12-bit codes, left-justified; the +k%3 keeps the mean off an integer */
        pc.ia_raw = (uint16_t)(((2062 + tri) << 4) + (int32_t)(k % 3u) * 4);
        pc.ib_raw = (uint16_t)(((2006 - tri) << 4) + (int32_t)(k % 5u) * 4);
        sum_a += pc.ia_raw;
        sum_b += pc.ib_raw;
        st = phase_current_cal_step(&pc);
        if (k < 1023u) {
            assert_int_equal(st, PHASE_CURRENT_CAL_BUSY);
        }
    }
    assert_int_equal(st, PHASE_CURRENT_CAL_DONE);
    assert_int_equal(pc.cal_fault, 0);
    assert_int_equal(pc.offset_a, (uint16_t)floor((double)sum_a / 1024.0 + 0.5));
    assert_int_equal(pc.offset_b, (uint16_t)floor((double)sum_b / 1024.0 + 0.5));
    /* finished: further calls report idle and change nothing */
    assert_int_equal(phase_current_cal_step(&pc), PHASE_CURRENT_CAL_IDLE);

    pc.ia_raw = (uint16_t)(pc.offset_a + 1000u);
    pc.ib_raw = (uint16_t)(pc.offset_b - 1000u);
    phase_current_step(&pc);
    assert_true(to_d(pc.ia) == 1000.0 / 32768.0);
    assert_true(to_d(pc.ib) == -1000.0 / 32768.0);
    assert_true(to_d(pc.ic) == 0.0);
}

/* Window 5 % = 3277 counts: a phase-b mean of 32768 + 4000 is rejected
 * (nominal offset kept, fault bit B), phase a (32768 - 3277, on the edge)
 * accepted.  Then the exact edge +3278 rejected. */
static void test_calibration_rejected(void **state)
{
    phase_current_t pc;
    uint32_t k;
    (void)state;

    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
    assert_int_equal(pc.offset_window, 3277);   /* 0.05 * 65536 = 3276.8, rounded */
    assert_int_equal(phase_current_cal_design(&pc, 16u), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_start(&pc, 16u), PHASE_CURRENT_OK);
    for (k = 0u; k < 16u; k++) {
        pc.ia_raw = (uint16_t)(32768u - 3277u);
        pc.ib_raw = (uint16_t)(32768u + 4000u);
        (void)phase_current_cal_step(&pc);
    }
    assert_int_equal(pc.cal_left, 0);
    assert_int_equal(pc.cal_fault, PHASE_CURRENT_PHASE_B);
    assert_int_equal(pc.offset_a, 32768u - 3277u);
    assert_int_equal(pc.offset_b, PHASE_CURRENT_OFFSET_NOMINAL);

    assert_int_equal(phase_current_cal_design(&pc, 4u), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_start(&pc, 4u), PHASE_CURRENT_OK);
    assert_int_equal(pc.cal_fault, 0);
    for (k = 0u; k < 4u; k++) {
        pc.ia_raw = (uint16_t)(32768u + 3278u);
        pc.ib_raw = (uint16_t)(32768u + 3277u);
        if (k < 3u) {
            assert_int_equal(phase_current_cal_step(&pc), PHASE_CURRENT_CAL_BUSY);
        } else {
            assert_int_equal(phase_current_cal_step(&pc), PHASE_CURRENT_CAL_REJECTED);
        }
    }
    assert_int_equal(pc.cal_fault, PHASE_CURRENT_PHASE_A);
    assert_int_equal(pc.offset_a, PHASE_CURRENT_OFFSET_NOMINAL);
    assert_int_equal(pc.offset_b, 32768u + 3277u);

    /* a dead sensor (reading 0) is rejected for both phases, and flags the rail */
    assert_int_equal(phase_current_cal_design(&pc, 2u), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_start(&pc, 2u), PHASE_CURRENT_OK);
    pc.ia_raw = 0u;
    pc.ib_raw = 0xFFF0u;
    (void)phase_current_cal_step(&pc);
    assert_int_equal(pc.rail, PHASE_CURRENT_PHASE_A | PHASE_CURRENT_PHASE_B);
    assert_int_equal(phase_current_cal_step(&pc), PHASE_CURRENT_CAL_REJECTED);
    assert_int_equal(pc.cal_fault, PHASE_CURRENT_PHASE_A | PHASE_CURRENT_PHASE_B);

    assert_int_equal(phase_current_cal_start(&pc, 0u), PHASE_CURRENT_ERR_SAMPLES);
    assert_int_equal(phase_current_cal_step(&pc), PHASE_CURRENT_CAL_IDLE);
}

/* The accumulator cannot wrap: the most samples a design takes, 32768, at the top rail. */
static void test_calibration_long(void **state)
{
    phase_current_t pc;
    uint32_t k;
    phase_current_cal_t st = PHASE_CURRENT_CAL_BUSY;
    (void)state;
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.25f), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_design(&pc, 32768u), PHASE_CURRENT_OK);
    assert_int_equal(phase_current_cal_start(&pc, 32768u), PHASE_CURRENT_OK);
    for (k = 0u; k < 32768u; k++) {
        pc.ia_raw = 0xFFF0u;
        pc.ib_raw = 32768u + 16384u;   /* exactly on the 25 % window */
        st = phase_current_cal_step(&pc);
    }
    assert_int_equal(st, PHASE_CURRENT_CAL_REJECTED);
    assert_int_equal(pc.cal_fault, PHASE_CURRENT_PHASE_A);
    assert_int_equal(pc.offset_b, 32768u + 16384u);
}

static void test_rail_flags(void **state)
{
    phase_current_t pc;
    (void)state;
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
    pc.ia_raw = 0u;      pc.ib_raw = 32768u;  phase_current_step(&pc);
    assert_int_equal(pc.rail, PHASE_CURRENT_PHASE_A);
    pc.ia_raw = 16u;     pc.ib_raw = 0xFFF0u; phase_current_step(&pc);
    assert_int_equal(pc.rail, PHASE_CURRENT_PHASE_B);
    pc.ia_raw = 0xFFFFu; pc.ib_raw = 0u;      phase_current_step(&pc);
    assert_int_equal(pc.rail, PHASE_CURRENT_PHASE_A | PHASE_CURRENT_PHASE_B);
    pc.ia_raw = 0xFFE0u; pc.ib_raw = 16u;     phase_current_step(&pc);
    assert_int_equal(pc.rail, 0);
}

/* The branch-free rail bits against their definition (a reading of 0 or of
 * RAIL_HIGH and above), every raw value of each phase with the other at
 * mid-scale and at each rail. */
static void test_rail_bits_exhaustive(void **state)
{
    static const uint16_t other[] = { 32768u, 0u, PHASE_CURRENT_RAIL_HIGH, 0xFFFFu, 1u };
    uint32_t raw;
    size_t j;
    (void)state;
    for (j = 0; j < sizeof other / sizeof other[0]; j++) {
        const uint16_t o = other[j];
        const uint16_t o_rail = (uint16_t)((o == 0u || o >= PHASE_CURRENT_RAIL_HIGH) ? 1u : 0u);
        for (raw = 0u; raw <= 0xFFFFu; raw++) {
            const uint16_t r = (uint16_t)raw;
            const uint16_t at = (uint16_t)((r == 0u || r >= PHASE_CURRENT_RAIL_HIGH) ? 1u : 0u);
            assert_int_equal(phase_current_rail_bits(r, o),
                             (at ? PHASE_CURRENT_PHASE_A : 0u) | (o_rail ? PHASE_CURRENT_PHASE_B : 0u));
            assert_int_equal(phase_current_rail_bits(o, r),
                             (o_rail ? PHASE_CURRENT_PHASE_A : 0u) | (at ? PHASE_CURRENT_PHASE_B : 0u));
        }
    }
}

static void test_init_errors(void **state)
{
    phase_current_t pc;
    (void)state;
    assert_int_equal(phase_current_init(&pc, 0.79f, 1.0f, 1, 0.05f), PHASE_CURRENT_ERR_GAIN);
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.26f, 1, 0.05f), PHASE_CURRENT_ERR_GAIN);
    assert_int_equal(phase_current_init(&pc, NAN, 1.0f, 1, 0.05f), PHASE_CURRENT_ERR_GAIN);
    assert_int_equal(phase_current_init(&pc, 1.0f, -1.0f, 1, 0.05f), PHASE_CURRENT_ERR_GAIN);
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 0, 0.05f), PHASE_CURRENT_ERR_POLARITY);
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 2, 0.05f), PHASE_CURRENT_ERR_POLARITY);
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.0f), PHASE_CURRENT_ERR_WINDOW);
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.26f), PHASE_CURRENT_ERR_WINDOW);
    assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, NAN), PHASE_CURRENT_ERR_WINDOW);
    /* range edges accepted */
    assert_int_equal(phase_current_init(&pc, 0.8f, 1.25f, -1, 0.25f), PHASE_CURRENT_OK);
    assert_int_equal(pc.offset_window, 16384);
}

/* The calibration's mean as a multiply and a shift (phase_current_cal_design)
 * is the rounded division's result, bit for bit: for the drive's counts
 * (1050 at 15 kHz, 560 at 8 kHz, 2800 at 40 kHz) and others, at every sum
 * next to a multiple of n over the whole range (the points where a floor
 * changes: an off-by-one there would show) and at the extremes; and a
 * calibration of 1050 samples loads the same offsets with it as without. */
static void test_calibration_mean_by_multiply(void **state)
{
    static const uint16_t counts[] = {2u, 3u, 7u, 560u, 1024u, 1050u, 2800u, 32767u, 32768u};
    unsigned i;
    (void)state;
    for (i = 0u; i < sizeof counts / sizeof counts[0]; i++) {
        const uint16_t n = counts[i];
        phase_current_t pc;
        uint32_t q;
        assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
        assert_int_equal(phase_current_cal_design(&pc, n), PHASE_CURRENT_OK);
        assert_true(pc.cal_recip != 0u && pc.cal_recip_n == n);
        for (q = 0u; q <= 65535u; q += (q < 64u || q > 65470u) ? 1u : 97u) {
            int d;
            for (d = -1; d <= 1; d++) {
                const int64_t x = (int64_t)q * n + d;
                const uint64_t x_max = (uint64_t)65535u * n + (n >> 1);
                if (x < 0 || (uint64_t)x > x_max) {
                    continue;
                }
                /* as the ISR computes it: the high word, then a 32-bit shift */
                assert_int_equal((uint32_t)(((uint64_t)x * pc.cal_recip) >> 32) >> pc.cal_rshift,
                                 (uint64_t)x / n);
            }
        }
    }
    {
        /* 65535 samples: the multiplier would not fit 32 bits, the mean divides */
        phase_current_t pc;
        assert_int_equal(phase_current_init(&pc, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
        assert_int_equal(phase_current_cal_design(&pc, 65535u), PHASE_CURRENT_ERR_SAMPLES);
        assert_int_equal(pc.cal_recip, 0u);
        assert_int_equal(phase_current_cal_design(&pc, 0u), PHASE_CURRENT_ERR_SAMPLES);
        assert_int_equal(phase_current_cal_design(&pc, 1u), PHASE_CURRENT_ERR_SAMPLES);
    }
    {
        /* a whole calibration of 1050 samples: the division's means; and a
         * count the design did not make is refused, nothing started */
        phase_current_t a;
        uint32_t k, sum_a = 0u, sum_b = 0u;
        assert_int_equal(phase_current_init(&a, 1.0f, 1.0f, 1, 0.05f), PHASE_CURRENT_OK);
        assert_int_equal(phase_current_cal_design(&a, 1050u), PHASE_CURRENT_OK);
        assert_int_equal(phase_current_cal_start(&a, 1000u), PHASE_CURRENT_ERR_SAMPLES);
        assert_int_equal(a.cal_left, 0u);
        assert_int_equal(phase_current_cal_start(&a, 1050u), PHASE_CURRENT_OK);
        for (k = 0u; k < 1050u; k++) {
            a.ia_raw = (uint16_t)(32768u + 700u + (k % 13u) * 37u);
            a.ib_raw = (uint16_t)(32768u - 900u + (k % 7u) * 51u);
            sum_a += a.ia_raw;
            sum_b += a.ib_raw;
            (void)phase_current_cal_step(&a);
        }
        assert_int_equal(a.offset_a, (sum_a + 525u) / 1050u);
        assert_int_equal(a.offset_b, (sum_b + 525u) / 1050u);
        assert_int_equal(a.cal_fault, 0u);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scaling_unit_gain),
        cmocka_unit_test(test_scaling_gain_polarity_offset),
        cmocka_unit_test(test_calibration_accepted),
        cmocka_unit_test(test_calibration_rejected),
        cmocka_unit_test(test_calibration_long),
        cmocka_unit_test(test_calibration_mean_by_multiply),
        cmocka_unit_test(test_rail_flags),
        cmocka_unit_test(test_rail_bits_exhaustive),
        cmocka_unit_test(test_init_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
