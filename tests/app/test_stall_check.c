/* app_stall_check: the rotor checks (stall_check.h).
 *   count step (over windows of 4 periods): an encoder on a rotor at
 *   constant speed (with the quantisation of a real disc: the count is the
 *   floor of the angle) and one accelerating at the paper motor's largest
 *   acceleration pass at any speed; the count stream stopping at 3 or at 1
 *   count per period trips within two windows of the stop, at 0.5 (2
 *   counts per window, the limit) it does not; a 100-count jump trips.
 *   locked rotor: a residual that is the back-EMF of a rotation in the
 *   torque's direction (on the T axis, tau_r w |psi_e|) reads as turning
 *   above w_min and as locked below; one along the current vector (an Rs
 *   error) as locked whatever its size; one against the torque as locked.
 * Rig: 4000 counts per revolution, 15 kHz, 2 pole pairs; tau_r = 1.571 pu
 * (5 ms at 50 Hz), w_min 0.05 pu. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "stall_check.h"

#define TAU_R 1.5707963f
#define W_MIN 0.05f

static void init(stall_check_t *s)
{
    assert_int_equal(stall_check_init(s, 2, W_MIN, TAU_R), STALL_CHECK_OK);
}

/* A rotor whose position (counts, real) follows pos(k); the QEP count is
 * its floor.  Runs n periods, with the window test every 4th; returns the
 * period at which enc_fault came (n: never). */
static unsigned run_encoder(stall_check_t *s, double (*pos)(unsigned k, void *ctx), void *ctx,
                            unsigned n)
{
    unsigned k;
    for (k = 1u; k < n; k++) {
        const int32_t c = (int32_t)floor(pos(k, ctx));
        if ((k % 4u) == 0u) {
            stall_check_window_step(s, (uint16_t)(uint32_t)c, 1u);
        }
        if (s->enc_fault != 0u) {
            return k;
        }
    }
    return n;
}

typedef struct {
    double rate;        /* counts per period */
    double accel;       /* counts per period^2 */
    unsigned stop_at;   /* the count stops here (0: never) */
} rotor_t;

static double rotor_pos(unsigned k, void *ctx)
{
    const rotor_t *r = (const rotor_t *)ctx;
    const unsigned kk = (r->stop_at != 0u && k > r->stop_at) ? r->stop_at : k;
    return 0.37 + r->rate * (double)kk + 0.5 * r->accel * (double)kk * (double)kk;
}

static void test_count_step(void **state)
{
    stall_check_t s;
    unsigned k;
    (void)state;
    /* constant speeds from 0.3 to 20 counts per period, quantised: no trip */
    for (k = 0; k < 40u; k++) {
        rotor_t r = {0.3 + 0.5 * (double)k, 0.0, 0u};
        init(&s);
        assert_int_equal(run_encoder(&s, rotor_pos, &r, 4000u), 4000u);
    }
    /* the paper motor's largest acceleration, 0.0038 counts per period^2, from
     * standstill to 15 counts per period: no trip */
    {
        rotor_t r = {0.0, 0.0038, 0u};
        init(&s);
        assert_int_equal(run_encoder(&s, rotor_pos, &r, 3900u), 3900u);
    }
    /* the count stops at 3 counts per period: within two windows */
    {
        rotor_t r = {3.0, 0.0, 1001u};
        init(&s);
        k = run_encoder(&s, rotor_pos, &r, 2000u);
        print_message("stop at 3 counts/period: tripped %u periods after\n", k - 1001u);
        assert_true(k > 1001u && k <= 1001u + 8u);
    }
    /* at 1 count per period (4 counts against 2 + 1, the stop inside a
     * window: against the window before the last): within two windows */
    {
        rotor_t r = {1.0, 0.0, 1001u};
        init(&s);
        k = run_encoder(&s, rotor_pos, &r, 2000u);
        print_message("stop at 1 count/period: tripped %u periods after\n", k - 1001u);
        assert_true(k > 1001u && k <= 1001u + 8u);
    }
    /* at 0.5 count per period (2 per window): the limit, no trip */
    {
        rotor_t r = {0.5, 0.0, 1001u};
        init(&s);
        assert_int_equal(run_encoder(&s, rotor_pos, &r, 2000u), 2000u);
    }
    /* a jump of 100 counts */
    init(&s);
    stall_check_window_step(&s, 0u, 1u);
    stall_check_window_step(&s, 24u, 1u);
    stall_check_window_step(&s, 48u, 1u);
    assert_int_equal(s.enc_fault, 0u);
    stall_check_window_step(&s, 172u, 1u);
    assert_int_equal(s.enc_fault, 1u);
    /* inactive: re-primed, no judgement of the first windows after; and
     * through the 16-bit wrap */
    stall_check_reset(&s);
    stall_check_window_step(&s, 65530u, 0u);
    stall_check_window_step(&s, 40u, 1u);
    stall_check_window_step(&s, 64u, 1u);
    stall_check_window_step(&s, 88u, 1u);
    assert_int_equal(s.enc_fault, 0u);
}

/* The residual of a rotation at w (pu) in the torque's direction: r on the
 * T axis, tau_r w |psi_e| (frame at angle th). */
static uint16_t decide_turning(double w, double th, double i_m, double i_t, double psi_e,
                               double rs_err_tau)
{
    stall_check_t s;
    const double rt = (double)TAU_R * w * psi_e * ((i_t < 0.0) ? -1.0 : 1.0);
    /* plus an Rs error's residual along the current vector */
    const double rm2 = rs_err_tau * i_m, rt2 = rs_err_tau * i_t;
    const double rm = rm2, rtt = rt + rt2;
    const double ra = rm * cos(th) - rtt * sin(th), rb = rm * sin(th) + rtt * cos(th);
    init(&s);
    return stall_check_decide(&s, _IQ((float)ra), _IQ((float)rb), _IQ((float)sin(th)),
                              _IQ((float)cos(th)), _IQ((float)psi_e), _IQ((float)i_m),
                              _IQ((float)i_t));
}

static void test_locked_or_turning(void **state)
{
    unsigned k;
    (void)state;
    for (k = 0; k < 8u; k++) {
        const double th = 0.7 * (double)k;
        /* turning faster than w_min in the torque's direction: the encoder */
        assert_int_equal(decide_turning(2.0 * W_MIN, th, 0.33, 0.5, 0.265, 0.0), 0u);
        assert_int_equal(decide_turning(2.0 * W_MIN, th, 0.33, -0.5, 0.265, 0.0), 0u);
        /* slower: locked */
        assert_int_equal(decide_turning(0.5 * W_MIN, th, 0.33, 0.5, 0.265, 0.0), 1u);
        assert_int_equal(decide_turning(0.0, th, 0.33, 0.5, 0.265, 0.0), 1u);
        /* against the torque (the model predicts more than the motor does) */
        assert_int_equal(decide_turning(-3.0 * W_MIN, th, 0.33, 0.5, 0.265, 0.0), 1u);
        /* an Rs error 30 % of 0.6 pu, times tau_r, along the current: locked */
        assert_int_equal(decide_turning(0.0, th, 0.33, 0.5, 0.265, 0.3 * 0.6 * (double)TAU_R),
                         1u);
        assert_int_equal(decide_turning(0.0, th, 0.33, -0.5, 0.265, -0.3 * 0.6 * (double)TAU_R),
                         1u);
        /* and with it, a rotation above w_min still reads as turning */
        assert_int_equal(decide_turning(2.0 * W_MIN, th, 0.33, 0.5, 0.265,
                                        0.3 * 0.6 * (double)TAU_R), 0u);
    }
    {
        stall_check_t s;
        assert_int_equal(stall_check_init(&s, 0, W_MIN, TAU_R), STALL_CHECK_ERR_ARG);
        assert_int_equal(s.enc_fault, 1u);
        assert_int_equal(stall_check_init(&s, 2, 0.0f, TAU_R), STALL_CHECK_ERR_ARG);
        assert_int_equal(stall_check_init(&s, 2, W_MIN, 9.0f), STALL_CHECK_ERR_ARG);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_count_step),
        cmocka_unit_test(test_locked_or_turning),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
