/* base_values_init: the derived bases against values computed by hand, and
 * every error code.
 *
 * Hand computation for I_base = 10 A, V_base = 20 V, f_base = 50 Hz,
 * 2 pole pairs, Ts = 100 us:
 *   w_base   = 2 pi 50              = 314.159265358979 rad/s
 *   t_base   = 1 / w_base           = 3.18309886183791e-3 s
 *   Z_base   = 20 / 10              = 2 ohm
 *   L_base   = 2 / 314.159265       = 6.36619772367581e-3 H
 *   psi_base = 20 / 314.159265      = 6.36619772367581e-2 Wb
 *   T_base   = 1.5 * 2 * psi * 10   = 1.90985931710274 N m
 *   n_base   = 60 * 50 / 2          = 1500 r/min
 *   Ts_pu    = 1e-4 * 314.159265    = 3.14159265358979e-2
 * Bound: each derived value is at most three float operations on float
 * inputs (each rounding <= 2^-24 relative, 6e-8) plus the float constant
 * 2 pi: 4 roundings <= 2.4e-7 relative; asserted at 5e-7 relative. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "base_values.h"

#define REL_TOL 5e-7

static void assert_rel(double got, double want)
{
    double err = fabs(got - want) / fabs(want);
    if (!(err <= REL_TOL)) {
        print_error("got %.12g want %.12g rel err %.3g\n", got, want, err);
        fail();
    }
}

static void test_derived_bases(void **state)
{
    base_values_t b;
    (void)state;
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 2u, 1.0e-4f), BASE_OK);
    assert_true(b.I_base_A == 10.0f);
    assert_true(b.V_base_V == 20.0f);
    assert_true(b.f_base_Hz == 50.0f);
    assert_true(b.Ts_s == 1.0e-4f);
    assert_int_equal(b.pole_pairs, 2);
    assert_rel(b.w_base_rad_s, 314.159265358979);
    assert_rel(b.t_base_s, 3.18309886183791e-3);
    assert_rel(b.Z_base_ohm, 2.0);
    assert_rel(b.L_base_H, 6.36619772367581e-3);
    assert_rel(b.psi_base_Wb, 6.36619772367581e-2);
    assert_rel(b.T_base_Nm, 1.90985931710274);
    assert_rel(b.n_base_rpm, 1500.0);
    assert_rel(b.Ts_pu, 3.14159265358979e-2);
}

/* The paper's rig: 9 A rms motor on a 20 A sensor, 60 V bus (V_base =
 * 60/sqrt 3 = 34.6410161513775 V), 50 Hz, 2 pole pairs, 15 kHz.
 *   Z = 1.73205080756888 ohm, L = 5.51328895421792e-3 H,
 *   psi = 0.110265779084358 Wb, T = 6.61594674506150 N m,
 *   Ts_pu = 2 pi 50 / 15000 = 2.09439510239320e-2 */
static void test_paper_rig(void **state)
{
    base_values_t b;
    (void)state;
    assert_int_equal(base_values_init(&b, 20.0f, 34.6410161513775f, 50.0f, 2u, 1.0f / 15000.0f),
                     BASE_OK);
    assert_rel(b.Z_base_ohm, 1.73205080756888);
    assert_rel(b.L_base_H, 5.51328895421792e-3);
    assert_rel(b.psi_base_Wb, 0.110265779084358);
    assert_rel(b.T_base_Nm, 6.61594674506150);
    assert_rel(b.n_base_rpm, 1500.0);
    assert_rel(b.Ts_pu, 2.09439510239320e-2);
    /* the conversion helpers: Rs = 1.031 ohm -> 0.595248 pu; 1400 r/min -> 0.9333 pu */
    assert_rel(base_ohm_to_pu(&b, 1.031f), 1.031 / 1.73205080756888);
    assert_rel(base_H_to_pu(&b, 0.0092f), 0.0092 / 5.51328895421792e-3);
    assert_rel(base_rpm_to_pu(&b, 1400.0f), 1400.0 / 1500.0);
    assert_rel(base_Wb_to_pu(&b, 0.042f), 0.042 / 0.110265779084358);
    assert_rel(base_s_to_pu(&b, 0.01978f), 0.01978 / 3.18309886183791e-3);
}

/* On error the struct is zeroed (nothing half-initialised is usable). */
static void assert_zeroed(const base_values_t *b)
{
    assert_true(b->I_base_A == 0.0f && b->V_base_V == 0.0f && b->f_base_Hz == 0.0f);
    assert_true(b->w_base_rad_s == 0.0f && b->Z_base_ohm == 0.0f && b->Ts_pu == 0.0f);
    assert_int_equal(b->pole_pairs, 0);
}

static void test_error_codes(void **state)
{
    base_values_t b;
    (void)state;
    assert_int_equal(base_values_init(&b, 0.0f, 20.0f, 50.0f, 2u, 1e-4f), BASE_ERR_CURRENT);
    assert_zeroed(&b);
    assert_int_equal(base_values_init(&b, -1.0f, 20.0f, 50.0f, 2u, 1e-4f), BASE_ERR_CURRENT);
    assert_int_equal(base_values_init(&b, NAN, 20.0f, 50.0f, 2u, 1e-4f), BASE_ERR_CURRENT);
    assert_int_equal(base_values_init(&b, 10.0f, 0.0f, 50.0f, 2u, 1e-4f), BASE_ERR_VOLTAGE);
    assert_zeroed(&b);
    assert_int_equal(base_values_init(&b, 10.0f, NAN, 50.0f, 2u, 1e-4f), BASE_ERR_VOLTAGE);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 0.0f, 2u, 1e-4f), BASE_ERR_FREQUENCY);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, -50.0f, 2u, 1e-4f), BASE_ERR_FREQUENCY);
    assert_zeroed(&b);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 2u, 0.0f), BASE_ERR_PERIOD);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 2u, 0.0101f), BASE_ERR_PERIOD);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 2u, NAN), BASE_ERR_PERIOD);
    assert_zeroed(&b);
    /* the edge of the period range is accepted */
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 2u, 0.01f), BASE_OK);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 0u, 1e-4f), BASE_ERR_POLES);
    assert_zeroed(&b);
    /* the first offending argument is named */
    assert_int_equal(base_values_init(&b, 0.0f, 0.0f, 0.0f, 0u, 0.0f), BASE_ERR_CURRENT);
    assert_int_equal(base_values_init(&b, 10.0f, 0.0f, 0.0f, 0u, 0.0f), BASE_ERR_VOLTAGE);
    assert_int_equal(base_values_init(&b, 10.0f, 20.0f, 50.0f, 0u, 0.0f), BASE_ERR_PERIOD);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_derived_bases),
        cmocka_unit_test(test_paper_rig),
        cmocka_unit_test(test_error_codes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
