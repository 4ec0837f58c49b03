/*
 * report.json is valid JSON whatever the run produced: a figure that is not
 * a finite number (NaN, +-inf: a diverged plant, a division by zero in a
 * figure) is written as null and named in "non_finite" with what it was.
 * The file is checked by a strict JSON parser (CMake's, json_valid.cmake),
 * which refuses the "-nan" printf gives.  Before, such a run wrote
 * "final_speed_rpm": -nan.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "report.h"
#include "sim_config.h"

static char g_text[65536];

/* Write @p r, read the file back into g_text, and have the strict parser
 * check it; returns the parser's exit status. */
static int write_and_parse(const sim_result_t *r, const char *keys)
{
    char dir[] = "/tmp/mc_report_XXXXXX";
    char path[256], cmd[1024];
    sim_options_t opt;
    sim_config_t cfg;
    FILE *f;
    size_t n;
    int rc;
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/report.json", dir);
    memset(&opt, 0, sizeof opt);
    memset(&cfg, 0, sizeof cfg);
    opt.scenario = SCEN_START;
    assert_int_equal(report_write_json(path, &cfg, "paper \"motor\".ini", &opt, r), 0);
    f = fopen(path, "r");
    assert_non_null(f);
    n = fread(g_text, 1, sizeof g_text - 1, f);
    g_text[n] = '\0';
    fclose(f);
    snprintf(cmd, sizeof cmd, "\"%s\" -DF=%s -DKEYS=\"%s\" -P \"%s\"", MC_CMAKE_COMMAND, path,
             keys, MC_JSON_VALID);
    rc = system(cmd);
    remove(path);
    rmdir(dir);
    return rc;
}

static void base_result(sim_result_t *r)
{
    memset(r, 0, sizeof *r);
    r->duration_s = 2.5;
    r->truth.Rs_ohm = 1.031;
    r->truth.Rr_ohm = 0.465;
    r->truth.Lm_H = 0.0064;
    r->truth.Lr_H = 0.0092;
    r->truth.psi_r_Wb = 0.042;
    r->truth.Tr_s = 0.0198;
    r->converge_s = -1.0;
    r->t_accel_start_s = -1.0;
    r->drift_t_start_s = -1.0;
    r->track_err_lag0_pct = -1.0;
    r->track_best_lag_s = -1.0;
    r->track_err_best_lag_pct = -1.0;
    r->drift_max_q_over_d = -1.0;
    r->drift_max_q_over_d_20ms = -1.0;
    r->drift_speed_ripple_rpm = -1.0;
    r->drift_rr_true_end_ohm = -1.0;
    r->plant_diverged_at_s = -1.0;
}

/* the parser is strict: the check can fail (a printf'd NaN is refused) */
static void test_parser_refuses_nan(void **state)
{
    char path[] = "/tmp/mc_nan_XXXXXX";
    char cmd[1024];
    int fd = mkstemp(path);
    FILE *f;
    (void)state;
    assert_true(fd >= 0);
    f = fdopen(fd, "w");
    assert_non_null(f);
    fprintf(f, "{\"final_speed_rpm\": %g}\n", -NAN);
    fclose(f);
    snprintf(cmd, sizeof cmd, "\"%s\" -DF=%s -P \"%s\" 2>/dev/null", MC_CMAKE_COMMAND, path,
             MC_JSON_VALID);
    assert_int_not_equal(system(cmd), 0);
    remove(path);
}

/* a healthy run: valid, every figure a number, "non_finite" empty */
static void test_finite_report(void **state)
{
    sim_result_t r;
    (void)state;
    base_result(&r);
    r.final_speed_rpm = 1400.2;
    assert_int_equal(write_and_parse(&r, "final_speed_rpm|non_finite|plant_diverged_at_s"), 0);
    assert_non_null(strstr(g_text, "\"final_speed_rpm\": 1400.2,"));
    assert_non_null(strstr(g_text, "\"non_finite\": {},"));
    assert_non_null(strstr(g_text, "\"plant_diverged_at_s\": null,"));
}

/* NaN and infinities in plain figures, a parameter set, a fault time and a
 * drift figure: null in their place, each named with its value */
static void test_non_finite_figures(void **state)
{
    sim_result_t r;
    (void)state;
    base_result(&r);
    r.final_speed_rpm = -NAN;
    r.max_abs_i_A = INFINITY;
    r.v_err_along_i_V = -INFINITY;
    r.identified = 1u;
    r.published_end.Rs_ohm = 1.0;
    r.published_end.Rr_ohm = NAN;
    r.published_end_error_pct.Rr_ohm = NAN;
    r.n_faults_seen = 1u;
    r.fault_code[0] = 4u;
    r.fault_time_s[0] = NAN;
    r.track_err_lag0_pct = NAN;
    r.plant_diverged_at_s = 0.375533;
    assert_int_equal(write_and_parse(&r, "final_speed_rpm|identified|non_finite|faults"), 0);
    printf("%s", strstr(g_text, "\"non_finite\""));
    assert_non_null(strstr(g_text, "\"final_speed_rpm\": null,"));
    assert_non_null(strstr(g_text, "\"max_abs_i_A\": null,"));
    assert_non_null(strstr(g_text, "\"Rs_ohm\": 1, \"Rr_ohm\": null,"));
    assert_non_null(strstr(g_text, "\"time_s\": null, \"state\""));
    assert_non_null(strstr(g_text, "\"track_err_lag0_pct\": null,"));
    assert_non_null(strstr(g_text, "\"final_speed_rpm\": \"nan: not a finite number"));
    assert_non_null(strstr(g_text, "\"max_abs_i_A\": \"+inf: not a finite number"));
    assert_non_null(strstr(g_text, "\"v_err_along_i_V\": \"-inf: not a finite number"));
    assert_non_null(strstr(g_text, "\"identified.Rr_ohm\": \"nan"));
    assert_non_null(strstr(g_text, "\"published_end.Rr_ohm\": \"nan"));
    assert_non_null(strstr(g_text, "\"faults[0].time_s\": \"nan"));
    assert_non_null(strstr(g_text, "\"plant_diverged_at_s\": 0.375533,"));
    /* no token a JSON parser could not read */
    assert_null(strstr(g_text, "nan,"));
    assert_null(strstr(g_text, "inf,"));
}

/* more non-finite figures than the list holds: all null, the rest counted */
static void test_many_non_finite(void **state)
{
    sim_result_t r;
    (void)state;
    base_result(&r);
    r.identified = 1u;
    r.extracted = 1u;   /* the last extraction is written too */
    r.published_end.Rs_ohm = r.published_end.Rr_ohm = r.published_end.Lm_H = NAN;
    r.published_end.Lr_H = r.published_end.psi_r_Wb = r.published_end.Tr_s = NAN;
    r.published_end_error_pct = r.published_end;
    r.ident = r.published_end;
    r.error_pct = r.published_end;
    r.truth = r.published_end;
    assert_int_equal(write_and_parse(&r, "non_finite"), 0);
    assert_non_null(strstr(g_text, "\"more\": \"18 more\""));
}

/* A trace at its size limit stops and the run goes on (a serial session has
 * no length to size its trace by): 20 kB of a 0.5 s run at 1 ms, about 60
 * rows of ~330 bytes; the file ends within one row (400 bytes) of the
 * limit, the run reaches its end, the report says where the trace stopped. */
static void test_trace_stops_at_its_limit(void **state)
{
    char dir[] = "/tmp/mc_trace_XXXXXX";
    char trace[256], report[256], err[256];
    sim_config_t cfg;
    sim_options_t opt;
    sim_result_t r;
    FILE *f;
    long size;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(trace, sizeof trace, "%s/trace.csv", dir);
    snprintf(report, sizeof report, "%s/report.json", dir);
    assert_int_equal(sim_config_load(MC_CONFIG_DIR "/paper_motor.ini", &cfg, err, sizeof err), 0);
    memset(&opt, 0, sizeof opt);
    opt.scenario = SCEN_START;
    opt.duration_s = 0.5;
    opt.quiet = 1u;
    opt.trace_path = trace;
    opt.trace_max_bytes = 20000.0;
    assert_int_equal(sim_run(&cfg, &opt, &r, err, sizeof err), 0);
    f = fopen(trace, "r");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0L, SEEK_END), 0);
    size = ftell(f);
    fclose(f);
    printf("  trace stopped at %.4f s, %ld bytes; run to %.3f s\n", r.trace_truncated_at_s, size,
           r.duration_s);
    assert_true(size > 20000L && size <= 20000L + (long)SIM_TRACE_ROW_BYTES);
    assert_true(r.trace_truncated_at_s > 0.03 && r.trace_truncated_at_s < 0.1);
    assert_true(fabs(r.duration_s - 0.5) < 1e-9);
    assert_int_equal(report_write_json(report, &cfg, "paper_motor.ini", &opt, &r), 0);
    f = fopen(report, "r");
    assert_non_null(f);
    size = (long)fread(g_text, 1, sizeof g_text - 1, f);
    g_text[size] = '\0';
    fclose(f);
    assert_non_null(strstr(g_text, "\"trace_truncated_at_s\": 0.0"));
    remove(trace);
    remove(report);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parser_refuses_nan),
        cmocka_unit_test(test_finite_report),
        cmocka_unit_test(test_non_finite_figures),
        cmocka_unit_test(test_many_non_finite),
        cmocka_unit_test(test_trace_stops_at_its_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
