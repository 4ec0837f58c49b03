/*
 * Steady state on any motor (id_sequence.h, drive_design.h): the 37 kW,
 * 8-pole, 690 V motor of the family with 3 us of dead time on a 1160 V bus
 * (host_sim/config/motor_37kw.ini).  Its dead time's 6 f_e current ripple
 * makes a filtered di/dt of about 1.2e-4 pu, twice the former fixed
 * threshold (5 % of the rated peak current per second, 6.0e-5 pu): SETTLE
 * timed out on every pass of the adaptive sequence (measured).  The net
 * change of the filtered currents over the hold window confirms it.  Both
 * sequences: steady state confirmed on every pass (no SETTLE time-out, the
 * verdict not "timeout"), at most 1 s after the ramp; the adaptive
 * sequence's set published within 3 %.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "drive.h"
#include "sim_config.h"
#include "sim_run.h"

static sim_config_t g_cfg;

static int load(void **state)
{
    char err[256];
    (void)state;
    if (sim_config_load(MC_CONFIG_DIR "/motor_37kw.ini", &g_cfg, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    return 0;
}

static void run(sim_config_t *c, sim_result_t *r, const char *name)
{
    sim_options_t opt;
    char err[256];
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.stop_when_decided = 1u;
    assert_int_equal(sim_run(c, &opt, r, err, sizeof err), 0);
    printf("37 kW, %s: verdict %s at %.2f s, settle time-out %u, pass %u; published error %% "
           "Rs %+.2f Rr %+.2f Lm %+.2f Lr %+.2f psi_r %+.2f Tr %+.2f\n",
           name, drive_pub_reason_str(r->publish_reason), r->t_decided_s, r->settle_timeout,
           r->final_pass, r->published_end_error_pct.Rs_ohm, r->published_end_error_pct.Rr_ohm,
           r->published_end_error_pct.Lm_H, r->published_end_error_pct.Lr_H,
           r->published_end_error_pct.psi_r_Wb, r->published_end_error_pct.Tr_s);
    assert_int_equal(r->n_faults_seen, 0);
    assert_int_equal(r->settle_timeout, 0);
    assert_int_not_equal(r->publish_reason, DRIVE_PUB_TIMEOUT);
    assert_int_not_equal(r->publish_reason, DRIVE_PUB_PENDING);
}

/* The paper's sequence: one SETTLE; the set itself is refused (w_r Tr 94:
 * its Tr off by about 10 %, confidence above 3 %), not for want of a
 * steady state. */
static void test_paper_sequence_settles(void **state)
{
    sim_config_t c = g_cfg;
    sim_result_t r;
    (void)state;
    sim_config_set_sequence(&c, SIM_SEQ_PAPER);
    run(&c, &r, "paper's sequence");
    assert_int_equal(r.final_pass, 1);
    assert_int_equal(r.extracted, 1);
    /* SETTLE at most 1 s: the verdict within 1 s of the ramp's end */
    assert_true(r.t_decided_s < r.t_accel_start_s + r.target_rpm /
                                                        c.controller.speed_ramp_rpm_s + 1.0);
}

/* The adaptive sequence: two SETTLEs in the observer's frame (i_M wanders
 * 0.1-0.2 % over 0.2 s there, the tolerance is 0.5 %), then the fused set,
 * published within 3 %. */
static void test_adaptive_sequence_settles_and_publishes(void **state)
{
    sim_config_t c = g_cfg;
    sim_result_t r;
    const sim_params_t *e = &r.published_end_error_pct;
    (void)state;
    sim_config_set_sequence(&c, SIM_SEQ_ADAPTIVE);
    run(&c, &r, "adaptive sequence");
    assert_int_equal(r.final_pass, 2);
    assert_int_equal(r.identified, 1);
    assert_true(fabs(e->Rs_ohm) < 3.0 && fabs(e->Rr_ohm) < 3.0 && fabs(e->Lm_H) < 3.0);
    assert_true(fabs(e->Lr_H) < 3.0 && fabs(e->psi_r_Wb) < 3.0 && fabs(e->Tr_s) < 3.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper_sequence_settles),
        cmocka_unit_test(test_adaptive_sequence_settles_and_publishes),
    };
    return cmocka_run_group_tests(tests, load, NULL);
}
