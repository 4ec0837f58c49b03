/*
 * A current sensor's small error that the protections cannot find must not
 * give a set whose stated confidence hides it.
 *
 * The model check (current_model_check.h) finds a gain error on one of the
 * two phase sensors from about 5 % (its UNBALANCE level allows for the
 * bridge's harmonics and the model's error); below, and on some motors up
 * to 5 %, the drive runs on.  Before: the shipped 15 kW and 37 kW motors
 * with phase a's gain 3 % and 5 % high from MAGNETIZE on published sets
 * 3-5 % off (Rs -5.3 / -5.0 %, Rr -3.2 / -4.8 %, Tr +3.1 / +3.7 % at 5 %)
 * with stated confidences of 0.5-2.9 % and none for Rs.  Now every
 * confidence counts what such a gain does to its parameter
 * (drive_background.c widen_by_sensor, from the model check's negative
 * sequence: drive_safety_sensor_gain), and the standstill Rs has one (the
 * bridge's curve test's Rs against it).
 *
 * Each run (the shipped file, its default adaptive sequence, motor_sim's
 * bridge and sensors) must end one of three ways, none wrong:
 *   - a fault (the model check found the sensor; the bridge off);
 *   - refused, with the parameters the drive judged (its refused set):
 *     those whose confidence it stated, within that confidence;
 *   - published, every parameter within its stated confidence and 3 %.
 * And the estimate of the gain error itself must see it: at least 60 % of
 * the injected one where the drive reached its verdict without a fault
 * (measured 0.84-0.88 of it on these motors), at most 1 % on a healthy run
 * (measured 0.19-0.47 %).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "drive.h"
#include "fault_run.h"
#include "id_sequence.h"

static const char *const k_params[6] = {"Rs", "Rr", "Lm", "Lr", "psi_r", "Tr"};

static double param_at(const sim_params_t *p, unsigned i)
{
    const double v[6] = {p->Rs_ohm, p->Rr_ohm, p->Lm_H, p->Lr_H, p->psi_r_Wb, p->Tr_s};
    return v[i];
}

/* One run of @p ini with phase a's gain (1 + @p gain) from MAGNETIZE on
 * (gain 0: none); checks the three outcomes. */
static void check_run(const char *ini, double gain)
{
    sim_fault_t f = {PLANT_FAULT_HALL_GAIN, 0.01, gain, (uint16_t)ID_MAGNETIZE};
    sim_config_t cfg;
    sim_result_t r;
    unsigned i;
    const sim_params_t *err;
    assert_int_equal(fault_run(ini, &f, (gain != 0.0) ? 1u : 0u, NULL, 0u, 0.0, &cfg, &r), 0);
    print_message("%s gain %+.0f %%: %s, sensor gain %.2f %%\n", ini, 100.0 * gain,
                  drive_pub_reason_str(r.publish_reason), r.sensor_gain_pct);
    if (r.n_faults_seen != 0u) {
        assert_true(gain != 0.0);   /* a healthy drive never trips */
        assert_int_equal(r.publish_reason, DRIVE_PUB_FAULT);
        return;
    }
    assert_true(r.t_decided_s > 0.0);
    if (gain != 0.0) {
        assert_true(r.sensor_gain_pct >= 60.0 * fabs(gain));
    } else {
        assert_true(r.sensor_gain_pct <= 1.0);
    }
    if (r.identified != 0u) {
        err = &r.published_end_error_pct;
    } else if (r.refused_fused != 0u) {
        err = &r.refused_set_error_pct;
    } else {
        return;   /* refused before a set was judged whole: nothing stated */
    }
    for (i = 0u; i < 6u; i++) {
        const double e = fabs(param_at(err, i));
        print_message("  %-5s error %6.2f %%  confidence %6.2f %%\n", k_params[i], e,
                      r.conf_pct[i]);
        if (r.conf_pct[i] > 0.0) {
            /* the confidence covers the error, to the 0.3 % the healthy sets
             * show beyond theirs (the estimates' own noise) */
            assert_true(e <= r.conf_pct[i] + 0.3);
        }
        if (r.identified != 0u) {
            assert_true(e <= 3.0);
        }
    }
}

static void test_15kw(void **state)
{
    (void)state;
    check_run(MC_CONFIG_DIR "/motor_15kw.ini", 0.0);
    check_run(MC_CONFIG_DIR "/motor_15kw.ini", 0.05);
    check_run(MC_CONFIG_DIR "/motor_15kw.ini", 0.03);
}

static void test_37kw(void **state)
{
    (void)state;
    check_run(MC_CONFIG_DIR "/motor_37kw.ini", 0.05);
    check_run(MC_CONFIG_DIR "/motor_37kw.ini", 0.03);
}

static void test_small_motors(void **state)
{
    (void)state;
    check_run(MC_CONFIG_DIR "/motor_1kw.ini", -0.03);
    check_run(MC_CONFIG_DIR "/paper_motor_adaptive.ini", -0.03);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_15kw),
        cmocka_unit_test(test_37kw),
        cmocka_unit_test(test_small_motors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
