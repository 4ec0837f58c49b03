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

static const char *const k_param_keys[6] = {"Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb",
                                             "Tr_s"};

/* {"Rs_ohm": v, ...} of six percentages; a negative value (not available) as null */
static void json_pct6(FILE *f, const char *name, const double v[6], int nullable)
{
    unsigned i;
    fprintf(f, "\"%s\": {", name);
    for (i = 0; i < 6u; i++) {
        if (nullable && v[i] < 0.0) {
            fprintf(f, "%s\"%s\": null", i ? ", " : "", k_param_keys[i]);
        } else {
            fprintf(f, "%s\"%s\": %.6g", i ? ", " : "", k_param_keys[i], v[i]);
        }
    }
    fputc('}', f);
}

/* The publication's verdict and the confidence of the set judged
 * (ident_conf.h): report.json's "publish_reason", "confidence_pct" and the
 * figures behind them, "confidence". */
static void json_confidence(FILE *f, const sim_result_t *r)
{
    fprintf(f, "  \"publish_reason\": \"%s\",\n", drive_pub_reason_str(r->publish_reason));
    if (r->t_decided_s >= 0.0) {
        fprintf(f, "  \"t_decided_s\": %.6g,\n", r->t_decided_s);
    } else {
        fprintf(f, "  \"t_decided_s\": null,\n");
    }
    if (r->publish_reason == 0u || !r->extracted) {
        fprintf(f, "  \"confidence_pct\": null,\n  \"confidence\": null,\n");
        return;
    }
    fprintf(f, "  ");
    json_pct6(f, "confidence_pct", r->conf_pct, 1);
    fprintf(f, ",\n  \"confidence\": {\"residual_rel\": %.6g, \"amplification\": %.6g, "
               "\"excitation\": %.6g, \"rls_samples\": %u, \"rls_pd_repairs\": %u, ",
            r->conf_residual, r->conf_amp, r->conf_excitation, (unsigned)r->conf_samples,
            (unsigned)r->conf_pd);
    json_pct6(f, "bound_pct", r->bound_pct, 0);
    fprintf(f, ", ");
    json_pct6(f, "drift_pct", r->drift_pct, 0);
    fprintf(f, "},\n");
}

static const char *fault_name(uint16_t code)
{
    static const char *const names[] = {"none", "overcurrent", "bus_overvoltage",
                                        "bus_undervoltage", "encoder", "current_offset",
                                        "adc_rail", "hw_trip", "config",
                                        "current_sensor"};
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
    json_confidence(f, r);
    if (r->identified) {
        /* identified: what the drive publishes at the end (the telemetry's set, as the
         * PC tool reads it): the RLS's extraction or, with tracking, the standstill Rs
         * and the tracked Rr, Tr (issue 8); published_end is the same set */
        json_params(f, "identified", &r->published_end, 0);
        json_params(f, "error_pct", &r->published_end_error_pct, 0);
        json_params(f, "published_end", &r->published_end, 0);
        json_params(f, "published_end_error_pct", &r->published_end_error_pct, 0);
        fprintf(f, "  \"params_tracked\": %s,\n", r->params_tracked ? "true" : "false");
    } else {
        /* nothing was published: no numbers that could be mistaken for a result */
        fprintf(f, "  \"identified\": null,\n  \"error_pct\": null,\n"
                   "  \"published_end\": null,\n  \"published_end_error_pct\": null,\n"
                   "  \"params_tracked\": false,\n");
    }
    if (r->extracted) {
        /* the RLS's last extraction as extracted (the paper's method), published or
         * refused: what the drive judged, not a result */
        json_params(f, "last_extraction", &r->ident, 0);
        json_params(f, "last_extraction_error_pct", &r->error_pct, 0);
        fprintf(f, "  \"last_extraction_valid\": %s,\n", r->ident_valid ? "true" : "false");
    } else {
        fprintf(f, "  \"last_extraction\": null,\n  \"last_extraction_error_pct\": null,\n"
                   "  \"last_extraction_valid\": false,\n");
    }
    fprintf(f, "  \"max_abs_i_A\": %.6g,\n  \"max_speed_err_rpm_ramp\": %.6g,\n"
               "  \"max_flux_q_over_d\": %.6g,\n  \"final_speed_rpm\": %.6g,\n",
            r->max_abs_i_A, r->max_speed_err_rpm_ramp, r->max_flux_q_over_d, r->final_speed_rpm);
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

static void row_values(FILE *f, const char *label, const sim_params_t *p)
{
    fprintf(f, "%-16s %10.4f %10.4f %10.5f %10.5f %10.5f %10.5f\n", label, p->Rs_ohm, p->Rr_ohm,
            p->Lm_H, p->Lr_H, p->psi_r_Wb, p->Tr_s);
}

static void row_pct(FILE *f, const char *label, const sim_params_t *p)
{
    fprintf(f, "%-16s %+10.2f %+10.2f %+10.2f %+10.2f %+10.2f %+10.2f\n", label, p->Rs_ohm,
            p->Rr_ohm, p->Lm_H, p->Lr_H, p->psi_r_Wb, p->Tr_s);
}

static void row_conf(FILE *f, const char *label, const double v[6])
{
    unsigned i;
    fprintf(f, "%-16s", label);
    for (i = 0; i < 6u; i++) {
        if (v[i] < 0.0) {
            fprintf(f, " %10s", "-");
        } else {
            fprintf(f, " %9.2f%%", v[i]);
        }
    }
    fputc('\n', f);
}

void report_print_table(FILE *f, const sim_result_t *r)
{
    /* published: what the drive publishes, as in report.json; then the
     * RLS's own extraction (the paper's method), published or not */
    const sim_params_t *t = &r->truth;
    fprintf(f, "\n%-16s %10s %10s %10s %10s %10s %10s\n", "", "Rs/ohm", "Rr/ohm", "Lm/H", "Lr/H",
            "psi_r/Wb", "Tr/s");
    row_values(f, "reference", t);
    if (r->identified) {
        row_values(f, "published", &r->published_end);
        row_pct(f, "  error %", &r->published_end_error_pct);
        row_conf(f, "  confidence +-", r->conf_pct);
    } else {
        fprintf(f, "%-16s (nothing published: %s)\n", "published",
                drive_pub_reason_str(r->publish_reason));
    }
    if (r->extracted) {
        row_values(f, "RLS (paper)", &r->ident);
        row_pct(f, "  error %", &r->error_pct);
        if (!r->params_tracked && r->publish_reason != 0u) {
            row_conf(f, "  confidence +-", r->conf_pct);
        } else {
            row_conf(f, "  bound +-", r->bound_pct);
        }
    }
    if (r->params_tracked) {
        fprintf(f, "(published: the drive's fused set: Rs from the standstill test, Rr and Tr "
                   "tracked, Lm, Lr, psi_r from the RLS; RLS (paper): the paper's RLS "
                   "extraction at the end of the last pass%s)\n",
                r->ident_valid ? "" : ", implausible");
    }
    fprintf(f, "verdict: %s%s; RLS residual %.2e of the signal, amplification %.3g over %u "
               "samples\n",
            drive_pub_reason_str(r->publish_reason),
            r->publish_reason == 0u ? " (the run ended before the drive's verdict)" : "",
            r->conf_residual, r->conf_amp, (unsigned)r->conf_samples);
    fprintf(f, "\nacceleration started at %.3f s; verdict at %.3f s%s;\n"
               "all estimates within 2 %% of their final values %.3f s after the start of the "
               "acceleration.\n",
            r->t_accel_start_s, r->t_decided_s,
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
