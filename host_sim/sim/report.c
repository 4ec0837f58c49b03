/* report.json and the printed table.  See report.h. */
#include "report.h"

#include "IQmathLib.h"
#include "current_model_check.h"
#include "protect.h"

#include <math.h>
#include <string.h>

/* The writer: the file, and the figures that were not finite numbers.  JSON
 * (RFC 8259) has no NaN or infinity: such a figure is written as null and
 * named, with its value, in "non_finite" at the end, so that the report
 * stays valid JSON whatever the run produced. */
#define REPORT_MAX_NON_FINITE 24

typedef struct {
    FILE *f;
    unsigned n_bad;          /* non-finite figures seen (all counted) */
    char bad[REPORT_MAX_NON_FINITE][48];
    double bad_v[REPORT_MAX_NON_FINITE];
} jw_t;

static void jw_note(jw_t *w, const char *name, const char *member, double v)
{
    if (w->n_bad < REPORT_MAX_NON_FINITE) {
        snprintf(w->bad[w->n_bad], sizeof w->bad[0], "%s%s%s", name, member[0] ? "." : "",
                 member);
        w->bad_v[w->n_bad] = v;
    }
    w->n_bad++;
}

/* One number with format @p fmt, or null (noted) if it is not finite. */
static void jw_num(jw_t *w, const char *fmt, const char *name, const char *member, double v)
{
    if (isfinite(v)) {
        fprintf(w->f, fmt, v);
    } else {
        fputs("null", w->f);
        jw_note(w, name, member, v);
    }
}

/* "  \"name\": <number>,\n" */
static void jw_field(jw_t *w, const char *name, double v)
{
    fprintf(w->f, "  \"%s\": ", name);
    jw_num(w, "%.6g", name, "", v);
    fputs(",\n", w->f);
}

static void json_params(jw_t *w, const char *name, const sim_params_t *p, int last)
{
    static const char *const k[6] = {"Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s"};
    const double v[6] = {p->Rs_ohm, p->Rr_ohm, p->Lm_H, p->Lr_H, p->psi_r_Wb, p->Tr_s};
    unsigned i;
    fprintf(w->f, "  \"%s\": {", name);
    for (i = 0; i < 6u; i++) {
        fprintf(w->f, "%s\"%s\": ", i ? ", " : "", k[i]);
        jw_num(w, "%.8g", name, k[i], v[i]);
    }
    fprintf(w->f, "}%s\n", last ? "" : ",");
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
static void json_num_or_null(jw_t *w, const char *name, double v, int present)
{
    if (present) {
        jw_field(w, name, v);
    } else {
        fprintf(w->f, "  \"%s\": null,\n", name);
    }
}

/* The adaptation telemetry and the drift scenario's figures. */
static void json_adaptation(jw_t *w, const sim_result_t *r)
{
    fprintf(w->f, "  \"pass\": %u,\n", r->final_pass);
    json_num_or_null(w, "Rs_dc_ohm", r->Rs_dc_ohm, r->Rs_dc_ohm != 0.0);
    jw_field(w, "sensor_gain_pct", r->sensor_gain_pct);
    fprintf(w->f, "  \"adapt_timeouts\": %u,\n", r->adapt_timeouts);
    json_num_or_null(w, "drift_t_start_s", r->drift_t_start_s, r->drift_t_start_s >= 0.0);
    fprintf(w->f, "  \"track_samples\": %u,\n", (unsigned)r->track_samples);
    /* (written so that a NaN figure is present, then written as null and named) */
    json_num_or_null(w, "track_err_lag0_pct", r->track_err_lag0_pct,
                     !(r->track_err_lag0_pct < 0.0));
    json_num_or_null(w, "track_best_lag_s", r->track_best_lag_s, !(r->track_best_lag_s < 0.0));
    json_num_or_null(w, "track_err_best_lag_pct", r->track_err_best_lag_pct,
                     !(r->track_err_best_lag_pct < 0.0));
    json_num_or_null(w, "drift_max_q_over_d", r->drift_max_q_over_d,
                     !(r->drift_max_q_over_d < 0.0));
    json_num_or_null(w, "drift_max_q_over_d_20ms", r->drift_max_q_over_d_20ms,
                     !(r->drift_max_q_over_d_20ms < 0.0));
    json_num_or_null(w, "drift_speed_ripple_rpm", r->drift_speed_ripple_rpm,
                     !(r->drift_speed_ripple_rpm < 0.0));
    json_num_or_null(w, "drift_rr_true_end_ohm", r->drift_rr_true_end_ohm,
                     !(r->drift_rr_true_end_ohm < 0.0));
}

/* "vi_curve": the bridge's voltage-error test (vi_curve.h): the fit, the
 * true E and band, and the table with the true error (vi_curve_model_V) at
 * each measured current */
static void json_vi_curve(jw_t *w, const sim_result_t *r)
{
    const vi_fit_t *v = &r->vi;
    unsigned i;
    fprintf(w->f, "  \"vi_curve\": {\"status\": \"%s\", \"rs_ohm\": ", vi_fit_str(v->status));
    jw_num(w, "%.6g", "vi_curve", "rs_ohm", v->rs_ohm);
    fputs(", \"e_pole_V\": ", w->f);
    jw_num(w, "%.6g", "vi_curve", "e_pole_V", v->e_pole_V);
    fputs(", \"band_A\": ", w->f);
    jw_num(w, "%.6g", "vi_curve", "band_A", v->band_A);
    fputs(", \"vdc_V\": ", w->f);
    jw_num(w, "%.6g", "vi_curve", "vdc_V", v->vdc_V);
    fprintf(w->f, ", \"n_band\": %u", (unsigned)v->n_band);
    fputs(", \"i1_A\": ", w->f);
    jw_num(w, "%.6g", "vi_curve", "i1_A", r->vi_i1_A);
    fprintf(w->f, ", \"retried\": %s", r->vi_retried ? "true" : "false");
    fprintf(w->f, ", \"true_e_pole_V\": %.6g, \"true_band_A\": %.6g, \"table\": [",
            r->vi_true_e_pole_V, r->vi_true_band_A);
    for (i = 0; i < VI_CURVE_LEVELS; i++) {
        fprintf(w->f, "%s[", i ? ", " : "");
        jw_num(w, "%.6g", "vi_curve", "i_A", v->i_A[i]);
        fputs(", ", w->f);
        jw_num(w, "%.6g", "vi_curve", "u_err_V", v->u_err_V[i]);
        fprintf(w->f, ", %.6g]", (double)vi_curve_model_V((float)r->vi_true_e_pole_V,
                                                           (float)r->vi_true_band_A, v->i_A[i]));
    }
    fputs("]},\n", w->f);
}

static const char *const k_param_keys[6] = {"Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb",
                                             "Tr_s"};

/* {"Rs_ohm": v, ...} of six percentages; a negative value (not available) as null */
static void json_pct6(jw_t *w, const char *name, const double v[6], int nullable)
{
    unsigned i;
    fprintf(w->f, "\"%s\": {", name);
    for (i = 0; i < 6u; i++) {
        fprintf(w->f, "%s\"%s\": ", i ? ", " : "", k_param_keys[i]);
        if (nullable && v[i] < 0.0) {
            fputs("null", w->f);
        } else {
            jw_num(w, "%.6g", name, k_param_keys[i], v[i]);
        }
    }
    fputc('}', w->f);
}

/* The publication's verdict and the confidence of the set judged
 * (ident_conf.h): report.json's "publish_reason", "confidence_pct" and the
 * figures behind them, "confidence". */
static void json_confidence(jw_t *w, const sim_result_t *r)
{
    fprintf(w->f, "  \"publish_reason\": \"%s\",\n", drive_pub_reason_str(r->publish_reason));
    json_num_or_null(w, "t_decided_s", r->t_decided_s, r->t_decided_s >= 0.0);
    if (r->publish_reason == 0u || !r->extracted) {
        fprintf(w->f, "  \"confidence_pct\": null,\n  \"confidence\": null,\n");
        return;
    }
    fprintf(w->f, "  ");
    json_pct6(w, "confidence_pct", r->conf_pct, 1);
    fprintf(w->f, ",\n  \"confidence\": {\"residual_rel\": ");
    jw_num(w, "%.6g", "confidence", "residual_rel", r->conf_residual);
    fprintf(w->f, ", \"amplification\": ");
    jw_num(w, "%.6g", "confidence", "amplification", r->conf_amp);
    fprintf(w->f, ", \"excitation\": ");
    jw_num(w, "%.6g", "confidence", "excitation", r->conf_excitation);
    fprintf(w->f, ", \"rls_samples\": %u, \"rls_pd_repairs\": %u, ", (unsigned)r->conf_samples,
            (unsigned)r->conf_pd);
    json_pct6(w, "bound_pct", r->bound_pct, 0);
    fprintf(w->f, ", ");
    json_pct6(w, "drift_pct", r->drift_pct, 0);
    fprintf(w->f, "},\n");
}

static const char *state_name(uint16_t state)
{
    static const char *const names[] = {"idle", "calibrate", "magnetize", "accelerate", "settle",
                                        "run", "fault", "refine", "inject"};
    return (state < sizeof names / sizeof names[0]) ? names[state] : "unknown";
}

static const char *fault_name(uint16_t code)
{
    static const char *const names[] = {"none", "overcurrent", "bus_overvoltage",
                                        "bus_undervoltage", "encoder", "current_offset",
                                        "adc_rail", "hw_trip", "config",
                                        "current_sensor", "isr_overrun", "sensor_test",
                                        "stall", "vi_curve"};
    return (code < sizeof names / sizeof names[0]) ? names[code] : "unknown";
}

/* "non_finite": each figure written as null because it was not a finite
 * number, with what it was; and where the plant diverged. */
static void json_non_finite(jw_t *w, const sim_result_t *r)
{
    unsigned i;
    fprintf(w->f, "  \"non_finite\": {");
    for (i = 0; i < w->n_bad && i < REPORT_MAX_NON_FINITE; i++) {
        fprintf(w->f, "%s\"%s\": \"%s: not a finite number, written as null\"", i ? ", " : "",
                w->bad[i], isnan(w->bad_v[i]) ? "nan" : (w->bad_v[i] > 0.0 ? "+inf" : "-inf"));
    }
    if (w->n_bad > REPORT_MAX_NON_FINITE) {
        fprintf(w->f, ", \"more\": \"%u more\"", w->n_bad - REPORT_MAX_NON_FINITE);
    }
    fprintf(w->f, "},\n");
    json_num_or_null(w, "plant_diverged_at_s", r->plant_diverged_at_s,
                     r->plant_diverged_at_s >= 0.0);
}

int report_write_json(const char *path, const sim_config_t *cfg, const char *config_path,
                      const sim_options_t *opt, const sim_result_t *r)
{
    jw_t w;
    FILE *f = fopen(path, "w");
    unsigned i;
    int write_failed;
    if (f == NULL) {
        return -1;
    }
    memset(&w, 0, sizeof w);
    w.f = f;
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
    jw_field(&w, "duration_s", r->duration_s);
    if (opt->trace_path != NULL) {
        /* the trace's row spacing (motor_sim may thin the 1 ms default to fit its limit),
         * and where it stopped at its size limit (a serial session: no length known) */
        fprintf(f, "  \"trace_every_periods\": %llu,\n",
                (unsigned long long)sim_trace_every(cfg, opt));
        json_num_or_null(&w, "trace_truncated_at_s", r->trace_truncated_at_s,
                         r->trace_truncated_at_s >= 0.0);
    }
    jw_field(&w, "wall_s", r->wall_s);
    fprintf(f, "  \"published\": %s,\n", r->identified ? "true" : "false");
    fprintf(f, "  \"settle_timeout\": %s,\n", r->settle_timeout ? "true" : "false");
    jw_field(&w, "t_accel_start_s", r->t_accel_start_s);
    jw_field(&w, "t_published_s", r->t_published_s);
    jw_field(&w, "converge_s", r->converge_s);
    json_params(&w, "true", &r->truth, 0);
    json_confidence(&w, r);
    if (r->identified) {
        /* identified: what the drive publishes at the end (the telemetry's set, as the
         * PC tool reads it): the RLS's extraction or, with tracking, the standstill Rs
         * and the tracked Rr, Tr; published_end is the same set */
        json_params(&w, "identified", &r->published_end, 0);
        json_params(&w, "error_pct", &r->published_end_error_pct, 0);
        json_params(&w, "published_end", &r->published_end, 0);
        json_params(&w, "published_end_error_pct", &r->published_end_error_pct, 0);
        fprintf(f, "  \"params_tracked\": %s,\n", r->params_tracked ? "true" : "false");
    } else {
        /* nothing was published: no numbers that could be mistaken for a result */
        fprintf(f, "  \"identified\": null,\n  \"error_pct\": null,\n"
                   "  \"published_end\": null,\n  \"published_end_error_pct\": null,\n"
                   "  \"params_tracked\": false,\n");
    }
    if (r->refused_fused) {
        /* the fused set the drive judged and refused (the adaptive sequence): the set the
         * refusal concerned, to judge the verdict by, never a result */
        json_params(&w, "refused_set", &r->refused_set, 0);
        json_params(&w, "refused_set_error_pct", &r->refused_set_error_pct, 0);
    } else {
        fprintf(f, "  \"refused_set\": null,\n  \"refused_set_error_pct\": null,\n");
    }
    if (r->extracted) {
        /* the RLS's last extraction as extracted (the paper's method), published or
         * refused: what the drive judged, not a result */
        json_params(&w, "last_extraction", &r->ident, 0);
        json_params(&w, "last_extraction_error_pct", &r->error_pct, 0);
        fprintf(f, "  \"last_extraction_valid\": %s,\n", r->ident_valid ? "true" : "false");
    } else {
        fprintf(f, "  \"last_extraction\": null,\n  \"last_extraction_error_pct\": null,\n"
                   "  \"last_extraction_valid\": false,\n");
    }
    jw_field(&w, "max_abs_i_A", r->max_abs_i_A);
    jw_field(&w, "max_speed_err_rpm_ramp", r->max_speed_err_rpm_ramp);
    jw_field(&w, "max_flux_q_over_d", r->max_flux_q_over_d);
    jw_field(&w, "final_speed_rpm", r->final_speed_rpm);
    jw_field(&w, "target_rpm", r->target_rpm);
    fprintf(f, "  \"target_lowered\": %s,\n", r->target_lowered ? "true" : "false");
    jw_field(&w, "max_volt_head", r->max_volt_head);
    jw_field(&w, "max_true_phase_A", r->max_true_phase_A);
    jw_field(&w, "max_true_leg_A", r->max_true_leg_A);
    jw_field(&w, "rotor_turn_counts", r->rotor_turn_counts);
    jw_field(&w, "locked_torque_peak_Nm", r->locked_torque_peak_Nm);
    jw_field(&w, "over_trip_s", r->over_trip_s);
    jw_field(&w, "t_over_trip_first_s", r->t_over_trip_first_s);
    jw_field(&w, "t_over_trip_last_s", r->t_over_trip_last_s);
    jw_field(&w, "hw_comparator_trips", (double)r->hw_trips);
    jw_field(&w, "t_hw_comparator_s", r->t_hw_trip_s);
    jw_field(&w, "max_cmc_r_A", r->max_cmc_r_A);
    jw_field(&w, "t_max_cmc_r_s", r->t_max_cmc_r_s);
    jw_field(&w, "max_cmc_neg", r->max_cmc_neg);
    jw_field(&w, "t_max_cmc_neg_s", r->t_max_cmc_neg_s);
    jw_field(&w, "max_cmc_dc_A", r->max_cmc_dc_A);
    jw_field(&w, "t_max_cmc_dc_s", r->t_max_cmc_dc_s);
    jw_field(&w, "max_cmc_util_r", r->max_cmc_util_r);
    jw_field(&w, "max_cmc_util_neg", r->max_cmc_util_neg);
    jw_field(&w, "max_cmc_util_dc", r->max_cmc_util_dc);
    jw_field(&w, "params_withdrawn", (double)r->params_withdrawn);
    jw_field(&w, "withdraw_reason", (double)r->withdraw_reason);
    jw_field(&w, "max_pub_err_after_fault_pct", r->max_pub_err_after_fault_pct);
    jw_field(&w, "v_err_along_i_V", r->v_err_along_i_V);
    jw_field(&w, "v_err_across_i_V", r->v_err_across_i_V);
    jw_field(&w, "i_mag_steady_A", r->i_mag_steady_A);
    json_adaptation(&w, r);
    json_vi_curve(&w, r);
    fprintf(f, "  \"faults\": [");
    for (i = 0; i < r->n_faults_seen; i++) {
        char which[24];
        snprintf(which, sizeof which, "faults[%u]", i);
        fprintf(f, "%s{\"code\": %u, \"name\": \"%s\", \"time_s\": ", i ? ", " : "",
                r->fault_code[i], fault_name(r->fault_code[i]));
        jw_num(&w, "%.7g", which, "time_s", r->fault_time_s[i]);
        fprintf(f, ", \"state\": \"%s\", \"pass\": %u", state_name(r->fault_state[i]),
                r->fault_pass[i]);
        if (r->fault_code[i] == FAULT_CURRENT_SENSOR) {
            const uint16_t c = r->fault_cause[i];
            fprintf(f, ", \"checks\": \"%s%s%s%s\"", (c & 8u) ? "feedback " : "",
                    (c & CMC_MISMATCH) ? "mismatch " : "", (c & CMC_UNBALANCE) ? "unbalance " : "",
                    (c & CMC_OFFSET) ? "offset" : "");
        }
        fputc('}', f);
    }
    fprintf(f, "],\n");
    json_non_finite(&w, r);
    fprintf(f, "  \"pwm_enabled_at_end\": %s\n}\n", r->final_pwm_on ? "true" : "false");
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
    if (r->t_accel_start_s < 0.0) {
        /* nothing accelerated: the standstill sequence (or a run stopped before) */
        fprintf(f, "\nno acceleration; verdict at %.3f s; the rotor turned %.2f encoder counts "
                   "at most (true angle)%s\n",
                r->t_decided_s, r->rotor_turn_counts,
                (r->locked_torque_peak_Nm > 0.0) ? "; held by the locked load" : "");
        return;
    }
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
    if (r->adapt_timeouts != 0u) {
        fprintf(f, "the background's model came too late %u time(s): the sequence went on with "
                   "the model in use\n", r->adapt_timeouts);
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
