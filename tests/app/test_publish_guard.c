/* app_publish_guard: a set published within the window before a fault is
 * withdrawn (the newest checkpoint at least a window older than the
 * fault put back, or nothing published), one published before it is
 * kept; the reason and the count are recorded; a pending extraction
 * published after the fault latched is withdrawn in the same pass; the
 * fault reset re-arms.  Time in slow-task ticks, window 100 ticks, one
 * background pass every 4 ticks (as 1 kHz against 3.75 kHz). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "publish_guard.h"

static publish_set_t set_of(double rr)
{
    publish_set_t s;
    memset(&s, 0, sizeof s);
    s.Rs = _IQ(0.6);
    s.Rr = _IQ((float)rr);
    s.Lm = _IQ(1.1);
    s.Lr = _IQ(1.6);
    s.psi_r = _IQ(0.4);
    s.Tr = _IQ(6.2);
    s.valid = 1u;
    return s;
}

/* Runs ticks [t0, t1): the ISR's tick with @p fault from tick t_fault on,
 * a background pass every 4 ticks with the telemetry's set @p tel, which
 * @p publish(t) may change.  Returns the number of withdrawals seen. */
static unsigned run(publish_guard_t *g, publish_set_t *tel, unsigned t0, unsigned t1,
                    unsigned t_fault, uint16_t fault, double (*rr_of)(unsigned t))
{
    unsigned t, n = 0;
    for (t = t0; t < t1; t++) {
        publish_guard_tick(g, (t >= t_fault) ? fault : 0u);
        if ((t % 4u) == 0u) {
            if (rr_of != NULL && t < t_fault) {
                const double rr = rr_of(t);
                if (rr > 0.0) {
                    *tel = set_of(rr);
                }
            }
            n += publish_guard_pass(g, tel);
        }
    }
    return n;
}

/* A tracker that publishes every pass: Rr 0.25 + t / 1e5 (a slow drift) */
static double tracking(unsigned t) { return 0.25 + (double)t * 1e-5; }

static void test_tracking_then_fault(void **state)
{
    publish_guard_t g;
    publish_set_t tel;
    (void)state;
    memset(&tel, 0, sizeof tel);
    assert_int_equal(publish_guard_init(&g, 100u), 0);
    assert_int_equal(run(&g, &tel, 0u, 1000u, 1000u, 0u, tracking), 0u);
    /* the fault at 1000: everything published from 900 on is suspect; the
     * newest checkpoint at or before 900 is put back: checkpoints every 50
     * ticks, at multiples of 4 (the passes): 852 .. 900 */
    assert_int_equal(run(&g, &tel, 1000u, 1100u, 1000u, 4u, tracking), 1u);
    {
        const double rr = (double)_IQtoF(tel.Rr);
        const double t_cp = (rr - 0.25) / 1e-5;
        print_message("withdrawn: Rr back to the set of tick %.0f (fault at 1000, window 100)\n",
                      t_cp);
        assert_true(t_cp <= 900.5 && t_cp >= 850.0 - 0.5);
    }
    assert_int_equal(tel.valid, 1u);
    assert_int_equal(g.reason, 4u);
    assert_int_equal(g.withdrawn, 1u);
    /* judged once: later passes leave it */
    assert_int_equal(run(&g, &tel, 1100u, 1300u, 1000u, 4u, NULL), 0u);
}

/* One extraction published at t_pub, nothing before: withdrawn to nothing
 * if the fault comes within the window, kept if after it. */
static unsigned g_t_pub;
static double once(unsigned t) { return (t == g_t_pub) ? 0.47 : -1.0; }

static void test_extraction(void **state)
{
    publish_guard_t g;
    publish_set_t tel;
    (void)state;
    g_t_pub = 400u;
    memset(&tel, 0, sizeof tel);
    assert_int_equal(publish_guard_init(&g, 100u), 0);
    assert_int_equal(run(&g, &tel, 0u, 480u, 480u, 0u, once), 0u);
    assert_int_equal(run(&g, &tel, 480u, 520u, 480u, 9u, once), 1u);   /* 80 ticks after */
    assert_int_equal(tel.valid, 0u);
    assert_int_equal(g.reason, 9u);
    /* re-armed: a new run publishes at 1000, a fault 120 ticks later keeps it */
    publish_guard_rearm(&g);
    g_t_pub = 1000u;
    assert_int_equal(run(&g, &tel, 520u, 1120u, 1120u, 0u, once), 0u);
    assert_int_equal(run(&g, &tel, 1120u, 1200u, 1120u, 2u, once), 0u);
    assert_int_equal(tel.valid, 1u);
    assert_true(tel.Rr == _IQ(0.47f));
}

/* An extraction published after the fault latched (it was pending when
 * the fault came): withdrawn in the same pass. */
static void test_published_after_fault(void **state)
{
    publish_guard_t g;
    publish_set_t tel;
    (void)state;
    memset(&tel, 0, sizeof tel);
    assert_int_equal(publish_guard_init(&g, 100u), 0);
    assert_int_equal(run(&g, &tel, 0u, 500u, 500u, 0u, NULL), 0u);
    publish_guard_tick(&g, 6u);   /* the fault */
    tel = set_of(0.5);            /* the background publishes what was pending */
    assert_int_equal(publish_guard_pass(&g, &tel), 1u);
    assert_int_equal(tel.valid, 0u);
    assert_int_equal(publish_guard_init(&g, 1u), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tracking_then_fault),
        cmocka_unit_test(test_extraction),
        cmocka_unit_test(test_published_after_fault),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
