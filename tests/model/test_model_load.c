/**
 * @file test_model_load.c
 * Load-torque profiles (host_sim/model/motor_load.h): their values, their
 * validation, and the mechanical equation of the motor model against the
 * closed-form coast-down of an unexcited rotor (no flux, so T_e = 0):
 *   J dw/dt = -T_L(t, w) - B w.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "motor_model.h"
#include "model_check.h"

#define TS (1.0 / 15000.0)

static void test_profiles_values(void **state)
{
    load_t l;
    const double t[3] = {0.5, 1.0, 1.5};
    const double T[3] = {0.3, -0.2, 0.8};
    (void)state;
    assert_int_equal(load_init_none(&l), LOAD_OK);
    CHECK_ABS("none", load_torque_Nm(&l, 1.0, 100.0), 0.0, 0.0);
    assert_int_equal(load_init_constant(&l, 0.7), LOAD_OK);
    CHECK_ABS("constant, independent of w and t", load_torque_Nm(&l, 3.0, -50.0), 0.7, 0.0);
    assert_int_equal(load_init_steps(&l, 3u, t, T), LOAD_OK);
    CHECK_ABS("steps: before the first", load_torque_Nm(&l, 0.4999, 10.0), 0.0, 0.0);
    CHECK_ABS("steps: at the first time", load_torque_Nm(&l, 0.5, 10.0), 0.3, 0.0);
    CHECK_ABS("steps: second", load_torque_Nm(&l, 1.2, 10.0), -0.2, 0.0);
    CHECK_ABS("steps: last holds", load_torque_Nm(&l, 99.0, 10.0), 0.8, 0.0);
    assert_int_equal(load_init_proportional(&l, 2e-3), LOAD_OK);
    CHECK_REL("proportional: k1 w", load_torque_Nm(&l, 0.0, -120.0), -0.24, 1e-15);
    assert_int_equal(load_init_fan(&l, 0.5, 146.6), LOAD_OK);
    CHECK_REL("fan: T_ref at w_ref", load_torque_Nm(&l, 0.0, 146.6), 0.5, 1e-15);
    CHECK_REL("fan: quarter at half speed", load_torque_Nm(&l, 0.0, 73.3), 0.125, 1e-15);
    CHECK_REL("fan: opposes reverse motion", load_torque_Nm(&l, 0.0, -73.3), -0.125, 1e-15);
}

static void test_profiles_validation(void **state)
{
    load_t l;
    const double t_bad[2] = {1.0, 1.0};
    const double T2[2] = {0.1, 0.2};
    double tt[LOAD_MAX_STEPS + 1u], TT[LOAD_MAX_STEPS + 1u];
    uint16_t k;
    (void)state;
    for (k = 0u; k < LOAD_MAX_STEPS + 1u; k++) {
        tt[k] = (double)k;
        TT[k] = 0.0;
    }
    assert_int_equal(load_init_constant(&l, INFINITY), LOAD_ERR_TORQUE);
    assert_int_equal(l.kind, LOAD_NONE); /* a failed init leaves no load */
    assert_int_equal(load_init_steps(&l, 2u, t_bad, T2), LOAD_ERR_TIMES);
    assert_int_equal(load_init_steps(&l, 0u, tt, TT), LOAD_ERR_COUNT);
    assert_int_equal(load_init_steps(&l, (uint16_t)(LOAD_MAX_STEPS + 1u), tt, TT), LOAD_ERR_COUNT);
    assert_int_equal(load_init_steps(&l, LOAD_MAX_STEPS, tt, TT), LOAD_OK);
    assert_int_equal(load_init_steps(&l, 2u, NULL, T2), LOAD_ERR_NULL);
    assert_int_equal(load_init_proportional(&l, -1e-3), LOAD_ERR_COEFF);
    assert_int_equal(load_init_fan(&l, 0.5, 0.0), LOAD_ERR_SPEED);
    assert_int_equal(load_init_fan(&l, -0.5, 100.0), LOAD_ERR_COEFF);
    assert_int_equal(load_init_none(NULL), LOAD_ERR_NULL);
}

/* Coast-down with the stator unexcited (no voltage, no flux: T_e = 0).
 * RK4 at h = Ts/2 on these smooth scalar ODEs has a relative error of
 * ~(h/tau)^4 < 1e-12, so every bound is 1e-9 relative. */
static void coast(motor_t *m, int n_periods)
{
    int k;
    for (k = 0; k < n_periods; k++) {
        motor_step(m, 0.0, 0.0, TS, 2u);
    }
}

static void test_mechanics_constant(void **state)
{
    motor_t m;
    motor_params_t p;
    load_t l;
    double tau, w_ref, th_ref;
    (void)state;
    motor_params_default(&p);
    assert_int_equal(motor_init(&m, &p), MOTOR_OK);
    assert_int_equal(load_init_constant(&l, 0.2), LOAD_OK);
    motor_set_load(&m, &l);
    coast(&m, 3000); /* 0.2 s */
    /* w = -(T/B)(1 - e^{-t/tau}), tau = J/B; theta = -(T/B)(t - tau(1 - e^{-t/tau})) */
    tau = p.J_kgm2 / p.B_Nm_s;
    w_ref = -(0.2 / p.B_Nm_s) * (1.0 - exp(-m.t_s / tau));
    th_ref = -(0.2 / p.B_Nm_s) * (m.t_s - tau * (1.0 - exp(-m.t_s / tau)));
    CHECK_REL("constant load: w(0.2 s) (rad/s)", m.w_m_rad_s, w_ref, 1e-9);
    CHECK_REL("constant load: theta(0.2 s) (rad)", m.theta_m_rad, th_ref, 1e-9);
    CHECK_ABS("constant load: TL output (N m)", m.TL_Nm, 0.2, 0.0);
    CHECK_ABS("no flux: torque (N m)", m.Te_Nm, 0.0, 0.0);
}

static void test_mechanics_steps(void **state)
{
    motor_t m;
    motor_params_t p;
    load_t l;
    /* steps off the sub-step grid: RK4 samples the load at its stage
     * times, so a step inside a sub-step is seen up to one sub-step h early
     * or late: the speed error is at most sum |dT_k| h / J (the bound) */
    const double t[2] = {0.02013, 0.05007};
    const double T[2] = {0.1, -0.3};
    const double h = TS / 2.0;
    double w_ref, bound;
    (void)state;
    motor_params_default(&p);
    p.B_Nm_s = 0.0; /* pure inertia: w is the integral of -T_L / J */
    assert_int_equal(motor_init(&m, &p), MOTOR_OK);
    assert_int_equal(load_init_steps(&l, 2u, t, T), LOAD_OK);
    motor_set_load(&m, &l);
    coast(&m, 1500); /* 0.1 s */
    w_ref = -(0.1 * (t[1] - t[0]) + (-0.3) * (m.t_s - t[1])) / p.J_kgm2;
    bound = (0.1 + 0.4) * h / p.J_kgm2;
    CHECK_ABS("steps: w(0.1 s) = -int T_L / J (rad/s)", m.w_m_rad_s, w_ref, bound);
}

static void test_mechanics_proportional_and_fan(void **state)
{
    motor_t m;
    motor_params_t p;
    load_t l;
    const double w0 = 150.0;
    double w_ref;
    (void)state;
    motor_params_default(&p);
    p.B_Nm_s = 0.0;
    assert_int_equal(motor_init(&m, &p), MOTOR_OK);
    /* proportional: J dw/dt = -k1 w  ->  w = w0 e^{-k1 t / J} */
    assert_int_equal(load_init_proportional(&l, 5e-3), LOAD_OK);
    motor_set_load(&m, &l);
    motor_set_speed(&m, w0);
    coast(&m, 1500);
    w_ref = w0 * exp(-5e-3 * m.t_s / p.J_kgm2);
    CHECK_REL("proportional: w(0.1 s) (rad/s)", m.w_m_rad_s, w_ref, 1e-9);
    /* fan: J dw/dt = -k2 w|w|  ->  w = w0 / (1 + k2 w0 t / J) */
    assert_int_equal(motor_init(&m, &p), MOTOR_OK);
    assert_int_equal(load_init_fan(&l, 0.5, 146.6), LOAD_OK);
    motor_set_load(&m, &l);
    motor_set_speed(&m, w0);
    coast(&m, 1500);
    w_ref = w0 / (1.0 + l.k2_Nm_s2 * w0 * m.t_s / p.J_kgm2);
    CHECK_REL("fan: w(0.1 s) (rad/s)", m.w_m_rad_s, w_ref, 1e-9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_profiles_values),
        cmocka_unit_test(test_profiles_validation),
        cmocka_unit_test(test_mechanics_constant),
        cmocka_unit_test(test_mechanics_steps),
        cmocka_unit_test(test_mechanics_proportional_and_fan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
