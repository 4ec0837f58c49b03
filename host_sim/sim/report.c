/* report.json and the printed table.  See report.h. */
#include "report.h"

#include "IQmathLib.h"

#include <math.h>

static void json_params(FILE *f, const char *name, const sim_params_t *p, int last)
{
    fprintf(f,
            "  \"%s\": {\"Rs_ohm\": %.8g, \"Rr_ohm\": %.8g, \"Lm_H\": %.8g, \"Lr_H\": %.8g, "
            "\"psi_r_Wb\": %.8g, \"Tr_s\": %.8g}%s\n",
            name, p->Rs_ohm, p->Rr_ohm, p->Lm_H, p->Lr_H, p->psi_r_Wb, p->Tr_s, last ? "" : ",");
}

/* A JSON string: the path comes from the command line and may hold quotes,
 * backslashes or control characters (RFC 8259 section 7). */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != '\0'; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') {
            fprintf(f, "\\%c", c);
        } else if (c < 0x20u) {
            fprintf(f, "\\u%04x", c);
        } else {
            fputc(c, f);
        }
    }
    fputc('"', f);
}

/* A number, or null where the run has none to give (a negative figure or
 * a zero Rs_dc mean "none": see sim_result_t). */
static void json_num_or_null(FILE *f, const char *name, double v, int present)
{
    if (present) {
        fprintf(f, "  \"%s\": %.6g,\n", name, v);
    } else {
        fprintf(f, "  \"%s\": null,\n", name);
    }
}

/* The adaptation telemetry and the drift scenario's figures (issue 8). */
static void json_adaptation(FILE *f, const sim_result_t *r)
{
    fprintf(f, "  \"pass\": %u,\n", r->final_pass);
    json_num_or_null(f, "Rs_dc_ohm", r->Rs_dc_ohm, r->Rs_dc_ohm != 0.0);
    json_num_or_null(f, "drift_t_start_s", r->drift_t_start_s, r->drift_t_start_s >= 0.0);
    fprintf(f, "  \"track_samples\": %u,\n", (unsigned)r->track_samples);
    json_num_or_null(f, "track_err_lag0_pct", r->track_err_lag0_pct, r->track_err_lag0_pct >= 0.0);
    json_num_or_null(f, "track_best_lag_s", r->track_best_lag_s, r->track_best_lag_s >= 0.0);
    json_num_or_null(f, "track_err_best_lag_pct", r->track_err_best_lag_pct,
                     r->track_err_best_lag_pct >= 0.0);
    json_num_or_null(f, "drift_max_q_over_d", r->drift_max_q_over_d, r->drift_max_q_over_d >= 0.0);
    json_num_or_null(f, "drift_max_q_over_d_20ms", r->drift_max_q_over_d_20ms,
                     r->drift_max_q_over_d_20ms >= 0.0);
    json_num_or_null(f, "drift_speed_ripple_rpm", r->drift_speed_ripple_rpm,
                     r->drift_speed_ripple_rpm >= 0.0);
    json_num_or_null(f, "drift_rr_true_end_ohm", r->drift_rr_true_end_ohm,
                     r->drift_rr_true_end_ohm >= 0.0);
}

static const char *fault_name(uint16_t code)
{
    static const char *const names[] = {"none", "overcurrent", "bus_overvoltage",
                                        "bus_undervoltage", "encoder", "current_offset",
                                        "adc_rail", "hw_trip", "config",
                                        "current_sensor", "isr_overrun", "sensor_test",
                                        "stall"};
    return (code < sizeof names / sizeof names[0]) ? names[code] : "unknown";
}

int report_write_json(const char *path, const sim_config_t *cfg, const char *config_path,
                      const sim_options_t *opt, const sim_result_t *r)
{
    FILE *f = fopen(path, "w");
    unsigned i;
    int write_failed;
    (void)cfg;
    if (f == NULL) {
        return -1;
    }
    fprintf(f, "{\n  \"config\": ");
    json_string(f, config_path);
    fprintf(f, ",\n  \"scenario\": \"%s\",\n  \"math_type\": \"%s\",\n",
            sim_scenario_name(opt->scenario),
#if MATH_TYPE == IQ_MATH
            "IQ_MATH"
#else
            "FLOAT_MATH"
#endif
    );
    fprintf(f, "  \"duration_s\": %.6g,\n  \"wall_s\": %.6g,\n  \"published\": %s,\n",
            r->duration_s, r->wall_s, r->identified ? "true" : "false");
    fprintf(f, "  \"settle_timeout\": %s,\n", r->settle_timeout ? "true" : "false");
    fprintf(f, "  \"t_accel_start_s\": %.6g,\n  \"t_published_s\": %.6g,\n  \"converge_s\": %.6g,\n",
            r->t_accel_start_s, r->t_published_s, r->converge_s);
    json_params(f, "true", &r->truth, 0);
    if (r->identified) {
        /* identified: what the drive publishes at the end (the telemetry's set, as the
         * PC tool reads it): the RLS's extraction or, with tracking, the standstill Rs
         * and the tracked Rr, Tr (issue 8); published_end is the same set */
        json_params(f, "identified", &r->published_end, 0);
        json_params(f, "error_pct", &r->published_end_error_pct, 0);
        json_params(f, "published_end", &r->published_end, 0);
        json_params(f, "published_end_error_pct", &r->published_end_error_pct, 0);
        fprintf(f, "  \"params_tracked\": %s,\n", r->params_tracked ? "true" : "false");
        /* the RLS's last extraction as extracted (not published if implausible) */
        json_params(f, "last_extraction", &r->ident, 0);
        json_params(f, "last_extraction_error_pct", &r->error_pct, 0);
        fprintf(f, "  \"last_extraction_valid\": %s,\n", r->ident_valid ? "true" : "false");
    } else {
        /* nothing was published: no numbers that could be mistaken for a result */
        fprintf(f, "  \"identified\": null,\n  \"error_pct\": null,\n"
                   "  \"published_end\": null,\n  \"published_end_error_pct\": null,\n"
                   "  \"params_tracked\": false,\n  \"last_extraction\": null,\n"
                   "  \"last_extraction_error_pct\": null,\n  \"last_extraction_valid\": false,\n");
    }
    fprintf(f, "  \"max_abs_i_A\": %.6g,\n  \"max_speed_err_rpm_ramp\": %.6g,\n"
               "  \"max_flux_q_over_d\": %.6g,\n  \"final_speed_rpm\": %.6g,\n",
            r->max_abs_i_A, r->max_speed_err_rpm_ramp, r->max_flux_q_over_d, r->final_speed_rpm);
    fprintf(f, "  \"max_true_phase_A\": %.6g,\n  \"max_true_leg_A\": %.6g,\n"
               "  \"over_trip_s\": %.6g,\n  \"t_over_trip_first_s\": %.6g,\n"
               "  \"t_over_trip_last_s\": %.6g,\n  \"hw_comparator_trips\": %u,\n"
               "  \"t_hw_comparator_s\": %.7g,\n"
               "  \"max_cmc_r_A\": %.6g,\n  \"t_max_cmc_r_s\": %.6g,\n"
               "  \"max_cmc_neg\": %.6g,\n  \"t_max_cmc_neg_s\": %.6g,\n"
               "  \"max_cmc_dc_A\": %.6g,\n  \"t_max_cmc_dc_s\": %.6g,\n"
               "  \"max_cmc_util_r\": %.6g,\n  \"max_cmc_util_neg\": %.6g,\n"
               "  \"max_cmc_util_dc\": %.6g,\n"
               "  \"params_withdrawn\": %u,\n  \"withdraw_reason\": %u,\n"
               "  \"max_pub_err_after_fault_pct\": %.6g,\n",
            r->max_true_phase_A, r->max_true_leg_A, r->over_trip_s, r->t_over_trip_first_s,
            r->t_over_trip_last_s, (unsigned)r->hw_trips, r->t_hw_trip_s, r->max_cmc_r_A,
            r->t_max_cmc_r_s, r->max_cmc_neg, r->t_max_cmc_neg_s, r->max_cmc_dc_A,
            r->t_max_cmc_dc_s, r->max_cmc_util_r, r->max_cmc_util_neg, r->max_cmc_util_dc,
            r->params_withdrawn, r->withdraw_reason,
            r->max_pub_err_after_fault_pct);
    fprintf(f, "  \"v_err_along_i_V\": %.6g,\n  \"v_err_across_i_V\": %.6g,\n"
               "  \"i_mag_steady_A\": %.6g,\n",
            r->v_err_along_i_V, r->v_err_across_i_V, r->i_mag_steady_A);
    json_adaptation(f, r);
    fprintf(f, "  \"faults\": [");
    for (i = 0; i < r->n_faults_seen; i++) {
        fprintf(f, "%s{\"code\": %u, \"name\": \"%s\", \"time_s\": %.7g}", i ? ", " : "",
                r->fault_code[i], fault_name(r->fault_code[i]), r->fault_time_s[i]);
    }
    fprintf(f, "],\n  \"pwm_enabled_at_end\": %s\n}\n", r->final_pwm_on ? "true" : "false");
    write_failed = ferror(f);
    return (fclose(f) == 0 && write_failed == 0) ? 0 : -1;
}

void report_print_table(FILE *f, const sim_result_t *r)
{
    /* identified: what the drive publishes, as in report.json */
    const sim_params_t *t = &r->truth, *e = &r->published_end, *p = &r->published_end_error_pct;
    fprintf(f, "\n%-12s %10s %10s %10s %10s %10s %10s\n", "", "Rs/ohm", "Rr/ohm", "Lm/H", "Lr/H",
            "psi_r/Wb", "Tr/s");
    fprintf(f, "%-12s %10.4f %10.4f %10.5f %10.5f %10.5f %10.5f\n", "reference", t->Rs_ohm,
            t->Rr_ohm, t->Lm_H, t->Lr_H, t->psi_r_Wb, t->Tr_s);
    if (!r->identified) {
        fprintf(f, "%-12s (not identified)\n", "identified");
        return;
    }
    fprintf(f, "%-12s %10.4f %10.4f %10.5f %10.5f %10.5f %10.5f\n", "identified", e->Rs_ohm,
            e->Rr_ohm, e->Lm_H, e->Lr_H, e->psi_r_Wb, e->Tr_s);
    fprintf(f, "%-12s %+10.2f %+10.2f %+10.2f %+10.2f %+10.2f %+10.2f\n", "error %", p->Rs_ohm,
            p->Rr_ohm, p->Lm_H, p->Lr_H, p->psi_r_Wb, p->Tr_s);
    if (r->params_tracked) {
        /* issue 8: the published set above is the fused one (standstill Rs,
         * tracked Rr and Tr, the RLS's Lm, Lr, psi_r); the RLS's own */
        const sim_params_t *q = &r->ident, *qe = &r->error_pct;
        fprintf(f, "%-12s %10.4f %10.4f %10.5f %10.5f %10.5f %10.5f\n", "extraction", q->Rs_ohm,
                q->Rr_ohm, q->Lm_H, q->Lr_H, q->psi_r_Wb, q->Tr_s);
        fprintf(f, "%-12s %+10.2f %+10.2f %+10.2f %+10.2f %+10.2f %+10.2f\n", "error %",
                qe->Rs_ohm, qe->Rr_ohm, qe->Lm_H, qe->Lr_H, qe->psi_r_Wb, qe->Tr_s);
        fprintf(f, "(identified: published by the drive: Rs from the standstill test, Rr and Tr "
                   "tracked, Lm, Lr, psi_r from the RLS; extraction: the RLS at the end of the "
                   "last pass%s)\n", r->ident_valid ? "" : ", implausible");
    }
    fprintf(f, "\nacceleration started at %.3f s; parameters published at %.3f s%s;\n"
               "all estimates within 2 %% of their final values %.3f s after the start of the "
               "acceleration.\n",
            r->t_accel_start_s, r->t_published_s,
            r->settle_timeout ? " (steady state not confirmed: settle time-out)" : "",
            r->converge_s);
}

/* A figure of the drift window as text: "none" where it has none. */
static const char *figure(char *buf, size_t len, const char *fmt, double v)
{
    if (v < 0.0) {
        return "none";
    }
    (void)snprintf(buf, len, fmt, v);
    return buf;
}

void report_print_adaptation(FILE *f, const sim_result_t *r)
{
    char qd[32], qd20[32], sp[32];
    if (r->final_pass > 1u) {
        fprintf(f, "identification passes: %u\n", r->final_pass);
    }
    if (r->Rs_dc_ohm != 0.0) {
        fprintf(f, "standstill Rs %.4f ohm (%+.2f %%)\n", r->Rs_dc_ohm,
                100.0 * (r->Rs_dc_ohm - r->truth.Rs_ohm) / r->truth.Rs_ohm);
    }
    if (r->drift_t_start_s < 0.0) {
        return;
    }
    fprintf(f, "\ndrift from %.2f s: true Rr %.4f -> %.4f ohm; max |psi_q/psi_d| %s "
               "(20 ms mean %s); speed error up to %s r/min\n",
            r->drift_t_start_s, r->truth.Rr_ohm, r->drift_rr_true_end_ohm,
            figure(qd, sizeof qd, "%.4f", r->drift_max_q_over_d),
            figure(qd20, sizeof qd20, "%.4f", r->drift_max_q_over_d_20ms),
            figure(sp, sizeof sp, "%.1f", r->drift_speed_ripple_rpm));
    if (r->track_samples == 0u) {
        fprintf(f, "tracked Rr: no valid sample in the window (track_valid never set)\n");
        return;
    }
    fprintf(f, "tracked Rr: %u valid samples (100 Hz); worst error %.2f %% at lag 0, "
               "%.2f %% at the best lag %.1f s\n",
            (unsigned)r->track_samples, r->track_err_lag0_pct, r->track_err_best_lag_pct,
            r->track_best_lag_s);
}
