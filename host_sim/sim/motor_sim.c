/**
 * motor_sim: the F2812 firmware (unchanged drive_isr) in closed loop with a
 * simulated induction motor, inverter and sensors; runs the identification
 * and reports what it found.  See `motor_sim --help`.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "report.h"
#include "sim_config.h"
#include "sim_run.h"
#include "sim_serial.h"

/* The faults --fault injects: name, plant fault, the value's meaning, its
 * default and the range in which it does something (a value outside, or one
 * that changes nothing, such as a gain error of 0, is an error). */
#define V_NONE 0u    /* takes no value */
#define V_RANGE 1u   /* a number in [lo, hi] (lo_open: (lo, hi]), not 0 */
#define V_WHOLE 2u   /* a whole number in [lo, hi], not 0 */
typedef struct {
    const char *name;
    plant_fault_t kind;
    const char *what;    /* --help */
    const char *value;   /* the value's meaning (V_NONE: NULL) */
    unsigned rule;
    double def, lo, hi;
    int lo_open;
} fault_spec_t;

static const fault_spec_t k_faults[] = {
    {"hall_gain", PLANT_FAULT_HALL_GAIN, "phase-a sensor gain error", "relative error", V_RANGE,
     0.2, -0.99, 100.0, 0},
    {"hall_lost", PLANT_FAULT_HALL_LOST, "phase b reads 0 A", NULL, V_NONE, 0, 0, 0, 0},
    {"bus_sag", PLANT_FAULT_BUS_SAG, "the source voltage drops", "relative drop", V_RANGE, 0.5,
     0.0, 1.0, 1},
    {"overvoltage", PLANT_FAULT_OVERVOLTAGE, "the source voltage rises", "relative rise", V_RANGE,
     0.5, 0.0, 100.0, 1},
    {"encoder_lost", PLANT_FAULT_ENCODER_LOST, "T2 frozen", NULL, V_NONE, 0, 0, 0, 0},
    {"encoder_jump", PLANT_FAULT_ENCODER_JUMP, "T2 jumps once", "counts", V_WHOLE, 100.0,
     -32768.0, 32767.0, 0},
    {"short", PLANT_FAULT_SHORT, "a-b short at the bridge", "loop inductance, uH", V_RANGE, 20.0,
     0.0, 100.0, 1},
    {"adc_rail", PLANT_FAULT_ADC_RAIL, "bus feedback at the top rail (divider open)", NULL,
     V_NONE, 0, 0, 0, 0},
    {"offset", PLANT_FAULT_CURRENT_OFFSET, "phase-a sensor offset", "fraction of full scale",
     V_RANGE, 0.1, -1.0, 1.0, 0},
    {"hw_trip", PLANT_FAULT_HW_TRIP, "PDPINTA low", "seconds", V_RANGE, 100.0, 0.0, 3600.0, 1},
    {"clear", PLANT_FAULT_CLEAR, "every injected fault removed (after one)", NULL, V_NONE, 0, 0,
     0, 0},
};
#define N_FAULTS (sizeof k_faults / sizeof k_faults[0])

/* "a, b, c" of every fault's or scenario's name, from its table */
static const char *fault_names(void)
{
    static char buf[256];
    size_t i, o = 0;
    for (i = 0; i < N_FAULTS && o < sizeof buf; i++) {
        o += (size_t)snprintf(buf + o, sizeof buf - o, "%s%s", i ? ", " : "", k_faults[i].name);
    }
    return buf;
}

static const char *scenario_names(void)
{
    static char buf[128];
    unsigned i;
    size_t o = 0;
    for (i = 0; i < sim_scenario_count() && o < sizeof buf; i++) {
        o += (size_t)snprintf(buf + o, sizeof buf - o, "%s%s", i ? ", " : "",
                              sim_scenario_name((sim_scenario_t)i));
    }
    return buf;
}

#define MOTOR_SIM_NOT_PUBLISHED 3   /* exit status: the run completed, nothing published */

static void usage(FILE *f)
{
    size_t i;
    fprintf(f,
            "usage: motor_sim [--config FILE] [--scenario NAME] [--duration S] [--out DIR]\n"
            "                 [--trace-every N] [--trace-max-mb M]\n"
            "                 [--fault NAME@TIME[=VALUE]]... [--cmd NAME@TIME]... [--quiet]\n"
            "                 [--serial PATH [--realtime-factor X] [--serial-keep-open]]\n"
            "                 [--keys] [--help]\n"
            "\n"
            "Runs the firmware's 15 kHz ISR against a simulated induction motor, inverter and\n"
            "sensors: offset calibration, magnetisation, acceleration with the online RLS\n"
            "identification, steady state, parameter extraction.\n"
            "\n"
            "  --config FILE      INI file (default host_sim/config/paper_motor.ini)\n"
            "  --scenario NAME    one of %s:\n"
            "                     start (default: standstill to rated speed under load),\n"
            "                     reversal (then to -rated speed), load_steps (then a load step),\n"
            "                     soak (then reversals every 4 s, a load step 2 s after each),\n"
            "                     drift (then the rotor resistance rises while the load\n"
            "                     changes: [drift] keys; for [ident] track_rr = 1)\n"
            "  --duration S       simulated seconds, at least one PWM period and at most 3600\n"
            "                     (default: the start scenario runs until the drive's verdict\n"
            "                     on its set, published or refused, and 0.5 s more, or a\n"
            "                     time-out long enough for every pass and a second bridge\n"
            "                     test; the other scenarios\n"
            "                     long enough for their events)\n"
            "  --out DIR          write DIR/trace.csv and DIR/report.json (DIR and its parents\n"
            "                     are created if missing)\n"
            "  --trace-every N    one trace row every N PWM periods (default: 1 ms, 15 at\n"
            "                     15 kHz); a whole number in [1, 1e9]\n"
            "  --trace-max-mb M   largest trace.csv, MB (default %g, at most %g): the 1 ms\n"
            "                     default is thinned to fit (a note says so); with\n"
            "                     --trace-every given, a run whose trace would be larger is\n"
            "                     refused, saying the --trace-every that fits; a --serial\n"
            "                     session without --duration stops tracing at the limit\n"
            "  --fault NAME@T[=V] inject at T seconds (before the run's last PWM period), or\n"
            "                     NAME@STATE[+T][=V]: T seconds after the sequence first\n"
            "                     enters calibrate, magnetize, accelerate, settle, run,\n"
            "                     refine or inject; V must change something (not 0; in its\n"
            "                     range):\n",
            scenario_names(), SIM_TRACE_MAX_MB_DEFAULT, SIM_TRACE_MAX_MB_LIMIT);
    for (i = 0; i < N_FAULTS; i++) {
        const fault_spec_t *k = &k_faults[i];
        if (k->rule == V_NONE) {
            fprintf(f, "                       %-13s %s (no value)\n", k->name, k->what);
        } else {
            fprintf(f, "                       %-13s %s; =%s in %c%g, %g], default %g\n",
                    k->name, k->what, k->value, k->lo_open ? '(' : '[', k->lo, k->hi, k->def);
        }
    }
    fprintf(f,
            "  --cmd NAME@T       give the drive a command at T seconds (before the run's last\n"
            "                     PWM period): start, stop, reset (a run begins with start at\n"
            "                     0).  Commands at the same instant are all kept and taken\n"
            "                     reset first, then stop, then start (dropped if a stop came\n"
            "                     with it: stop wins)\n"
            "  --serial PATH      the board's serial link: create a pseudo-terminal, make PATH a\n"
            "                     symlink to its slave (/dev/pts/N, also printed) and run the\n"
            "                     firmware's telemetry and commands over it ($T/$A 20 times a\n"
            "                     second, $C,S/X/R/D; raw, 115200 8N1 nominal) as on SCI-A.\n"
            "                     The drive waits for $C,S (no start at 0 s); the run is paced\n"
            "                     to real time and ends after --duration (default 3600 s),\n"
            "                     when the client closes the port, or on Ctrl-C / SIGTERM\n"
            "  --realtime-factor X  with --serial: simulated seconds per wall second (default\n"
            "                     1; 0: as fast as the host runs)\n"
            "  --serial-keep-open with --serial: run on when the client closes the port (for\n"
            "                     separate imfoc start / monitor calls)\n"
            "  --quiet            no progress and no table\n"
            "  --keys             list every configuration key once: section, unit, default,\n"
            "                     range, and the side that reads it (drive / sim); then the\n"
            "                     derived limits drive_init enforces\n"
            "\n"
            "report.json is always valid JSON: a figure that is not a finite number is null\n"
            "and named in its \"non_finite\" member.\n"
            "Exit status: 0 the drive published its identified set; 1 usage or configuration\n"
            "error; 2 run failed (the firmware refused the configuration, a file could not be\n"
            "written); 3 the run completed but nothing was published: the drive refused its set,\n"
            "or the run ended before its verdict (report.json \"publish_reason\": not_converged,\n"
            "low_excitation, high_residual, low_confidence, implausible, fault, timeout,\n"
            "stopped, or pending); a --serial session ends with 0 (the PC tool reads the\n"
            "verdict).  --help and --keys exit 0.\n");
}

/* The options followed by a value.  Checked before any value is used, so
 * that such an option as the last argument is an error, never a NULL value. */
static int takes_value(const char *a)
{
    static const char *const k[] = {"--config",      "--out",          "--scenario",
                                     "--duration",    "--fault",        "--cmd",
                                     "--serial",      "--realtime-factor", "--trace-every",
                                     "--trace-max-mb"};
    unsigned i;
    for (i = 0; i < sizeof k / sizeof k[0]; i++) {
        if (strcmp(a, k[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

/* A whole string that is a number.  strtod's ERANGE is an error for an
 * overflow (+-HUGE_VAL: 1e999) but not for an underflow: 1e-320 is a finite
 * (subnormal) number, which the option's range check then judges. */
static int parse_double(const char *s, double *out)
{
    char *end = NULL;
    errno = 0;
    *out = strtod(s, &end);
    if (s[0] == '\0' || end == NULL || *end != '\0') {
        return -1;
    }
    return (errno == 0 || (errno == ERANGE && fabs(*out) < 1.0)) ? 0 : -1;
}

static int parse_cmd(const char *arg, sim_cmd_t *c)
{
    static const struct { const char *name; uint16_t cmd; } k[] = {
        {"start", 1u}, {"stop", 2u}, {"reset", 3u},   /* drive_cmd_t */
    };
    const char *at = strchr(arg, '@');
    unsigned i;
    if (at == NULL) {
        return -1;
    }
    for (i = 0; i < sizeof k / sizeof k[0]; i++) {
        size_t n = (size_t)(at - arg);
        if (strlen(k[i].name) == n && strncmp(arg, k[i].name, n) == 0) {
            c->cmd = k[i].cmd;
            return (parse_double(at + 1, &c->t_s) == 0 && c->t_s >= 0.0 && c->t_s <= 1e6) ? 0
                                                                                           : -1;
        }
    }
    return -1;
}

/* The time of a --fault: SECONDS from the start, or STATE[+SECONDS] after
 * the sequence first enters that state (calibrate, magnetize, accelerate,
 * settle, run, refine, inject; any case). */
static int parse_when(const char *s, sim_fault_t *f)
{
    static const char *const states[] = {"calibrate", "magnetize", "accelerate", "settle",
                                         "run", "fault", "refine", "inject"};
    char name[16];
    const char *plus = strchr(s, '+');
    size_t n = (plus != NULL) ? (size_t)(plus - s) : strlen(s);
    unsigned i;
    if (n > 0u && isalpha((unsigned char)s[0])) {
        if (n >= sizeof name) {
            return -1;
        }
        for (i = 0; i < n; i++) {
            name[i] = (char)tolower((unsigned char)s[i]);
        }
        name[n] = '\0';
        f->t_s = 0.0;
        for (i = 0; i < sizeof states / sizeof states[0]; i++) {
            if (strcmp(name, states[i]) == 0 && strcmp(name, "fault") != 0) {
                f->at_state = (uint16_t)(i + 1u);   /* id_state_t: CALIBRATE = 1 */
                return (plus == NULL || (parse_double(plus + 1, &f->t_s) == 0 &&
                                         f->t_s >= 0.0 && f->t_s <= 1e6))
                           ? 0
                           : -1;
            }
        }
        return -1;
    }
    return (parse_double(s, &f->t_s) == 0 && f->t_s >= 0.0 && f->t_s <= 1e6) ? 0 : -1;
}

/* One --fault: 0, or -1 with the reason in @p why ("" for a malformed
 * argument: the usage line says it). */
static int parse_fault(const char *arg, sim_fault_t *f, char *why, size_t why_len)
{
    char buf[128];
    char *at, *eq;
    size_t len = strlen(arg);
    unsigned i;
    why[0] = '\0';
    if (len >= sizeof buf) {
        return -1;
    }
    memcpy(buf, arg, len + 1u);
    at = strchr(buf, '@');
    if (at == NULL) {
        return -1;
    }
    *at = '\0';
    eq = strchr(at + 1, '=');
    if (eq != NULL) {
        *eq = '\0';
    }
    for (i = 0; i < N_FAULTS; i++) {
        const fault_spec_t *k = &k_faults[i];
        if (strcmp(buf, k->name) != 0) {
            continue;
        }
        f->kind = k->kind;
        f->value = k->def;
        f->at_state = 0u;
        if (parse_when(at + 1, f) != 0) {
            return -1;
        }
        if (eq == NULL) {
            return 0;
        }
        if (k->rule == V_NONE) {
            snprintf(why, why_len, "%s takes no value", k->name);
            return -1;
        }
        /* written so that a NaN fails too */
        if (parse_double(eq + 1, &f->value) != 0 ||
            !(k->lo_open ? (f->value > k->lo) : (f->value >= k->lo)) || !(f->value <= k->hi) ||
            f->value == 0.0 || (k->rule == V_WHOLE && f->value != floor(f->value))) {
            if (parse_double(eq + 1, &f->value) == 0 && isfinite(f->value)) {
                snprintf(why, why_len, "%s's value (%s) must be %sin %c%g, %g]%s", k->name,
                         k->value, (k->rule == V_WHOLE) ? "a whole number " : "",
                         k->lo_open ? '(' : '[', k->lo, k->hi,
                         (k->lo_open && k->lo == 0.0) ? "" : " and not 0: 0 changes nothing");
            }
            return -1;
        }
        return 0;
    }
    snprintf(why, why_len, "no fault '%s': one of %s", buf, fault_names());
    return -1;
}

/* The faults and commands against the run: each must act before the run's
 * last PWM period starts (a later one would silently do nothing), a clear
 * needs a fault before it.  Returns 0, or 1 with the message printed. */
static int check_timeline(const sim_config_t *cfg, const sim_options_t *opt,
                          const char *const *fault_arg, const char *const *cmd_arg)
{
    double dur = sim_run_duration_s(cfg, opt);
    uint64_t n = sim_run_periods(cfg, dur);
    double last = (n > 0u) ? (double)(n - 1u) / cfg->board.pwm_freq_Hz : -1.0;
    unsigned i, j;
    for (i = 0; i < opt->n_faults; i++) {
        const sim_fault_t *f = &opt->faults[i];
        int before = 0;
        if (f->at_state != 0u) {
            continue;   /* after a state's entry: the run decides when (reported) */
        }
        if (f->t_s > last) {
            fprintf(stderr, "motor_sim: bad --fault '%s' (NAME@SECONDS[=VALUE], at most %d): at "
                    "%g s it comes after the run's last PWM period (%g s simulated%s)\n",
                    fault_arg[i], SIM_MAX_FAULTS, f->t_s, dur,
                    (opt->duration_s > 0.0) ? ": --duration" : ", the scenario's default");
            return 1;
        }
        for (j = 0; j < opt->n_faults; j++) {
            before |= (opt->faults[j].kind != PLANT_FAULT_CLEAR &&
                       (opt->faults[j].at_state != 0u || opt->faults[j].t_s <= f->t_s));
        }
        if (f->kind == PLANT_FAULT_CLEAR && !before) {
            fprintf(stderr, "motor_sim: bad --fault '%s' (NAME@SECONDS[=VALUE], at most %d): no "
                    "fault is injected at or before %g s, so clear would remove nothing\n",
                    fault_arg[i], SIM_MAX_FAULTS, f->t_s);
            return 1;
        }
    }
    for (i = 0; i < opt->n_cmds; i++) {
        if (opt->cmds[i].t_s > last) {
            fprintf(stderr, "motor_sim: bad --cmd '%s' (start|stop|reset@SECONDS, at most %d): at "
                    "%g s it comes after the run's last PWM period (%g s simulated%s)\n",
                    cmd_arg[i], SIM_MAX_CMDS, opt->cmds[i].t_s, dur,
                    (opt->duration_s > 0.0) ? ": --duration" : ", the scenario's default");
            return 1;
        }
    }
    return 0;
}

/* mkdir -p: every missing folder of @p path, parents first.  Returns 0, or
 * -1 with errno set and the folder that could not be made in @p failed (a
 * file in the way: the folder under it, "Not a directory"). */
static int make_dirs(const char *path, char *failed, size_t len)
{
    char buf[4096];
    size_t n = strlen(path), i;

    snprintf(failed, len, "%s", path);
    if (n >= sizeof buf) {
        errno = ENAMETOOLONG;
        return -1;
    }
    memcpy(buf, path, n + 1u);
    for (i = 1u; i <= n; i++) {
        char c = buf[i];
        if ((c != '/' && c != '\0') || buf[i - 1u] == '/') {
            continue;   /* inside a name, or a repeated '/' */
        }
        buf[i] = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
            snprintf(failed, len, "%s", buf);
            return -1;
        }
        buf[i] = c;
    }
    return 0;
}

/* The trace's size against its limit (MB): with --trace-every given, a
 * trace above the limit is an error that says which --trace-every fits;
 * without it the 1 kHz default is thinned to fit, with a note.  Returns 0 or
 * 1 (message printed).  The run itself stops at the limit (a backstop). */
static int size_trace(const sim_config_t *cfg, sim_options_t *opt, double max_mb)
{
    double dur = sim_run_duration_s(cfg, opt), limit = max_mb * 1e6;
    uint64_t every = sim_trace_every(cfg, opt), periods = sim_run_periods(cfg, dur);
    double bytes = sim_trace_bytes(cfg, dur, every);
    uint64_t fit;
    opt->trace_max_bytes = limit;
    if (bytes <= limit) {
        return 0;
    }
    if (limit < SIM_TRACE_HEADER_BYTES + SIM_TRACE_ROW_BYTES) {
        fprintf(stderr, "motor_sim: --trace-max-mb %g is less than the trace's header and one "
                "row (%g MB)\n", max_mb, (SIM_TRACE_HEADER_BYTES + SIM_TRACE_ROW_BYTES) / 1e6);
        return 1;
    }
    /* the fewest periods a row such that the rows fit */
    fit = (limit > SIM_TRACE_HEADER_BYTES + SIM_TRACE_ROW_BYTES)
              ? (uint64_t)ceil((double)periods * SIM_TRACE_ROW_BYTES /
                               (limit - SIM_TRACE_HEADER_BYTES - SIM_TRACE_ROW_BYTES))
              : periods;
    if (fit < 1u) {
        fit = 1u;
    }
    if (opt->trace_every > 0u || fit > 1000000000u) {
        fprintf(stderr, "motor_sim: the trace of this run (%g s, one row every %llu PWM periods) "
                "would take up to %.4g MB, above --trace-max-mb %g: --trace-every %llu or more "
                "fits, or raise --trace-max-mb\n", dur, (unsigned long long)every, bytes / 1e6,
                max_mb, (unsigned long long)fit);
        return 1;
    }
    opt->trace_every = (uint32_t)fit;
    fprintf(stderr, "motor_sim: note: a 1 ms trace of this run (%g s) would take up to %.4g MB, "
            "above --trace-max-mb %g: one row every %llu PWM periods instead (--trace-every "
            "sets it)\n", dur, bytes / 1e6, max_mb, (unsigned long long)fit);
    return 0;
}

/* An earlier run's file in --out: removed when it is a plain file (a
 * directory or a link there is the user's, and the write reports it). */
static void remove_stale(const char *dir, const char *name)
{
    char path[4200];
    struct stat st;
    int n = snprintf(path, sizeof path, "%s/%s", dir, name);
    if (n > 0 && (size_t)n < sizeof path && lstat(path, &st) == 0 && S_ISREG(st.st_mode)) {
        (void)remove(path);
    }
}

int main(int argc, char **argv)
{
    const char *config = "host_sim/config/paper_motor.ini";
    const char *out_dir = NULL;
    sim_options_t opt;
    sim_config_t cfg;
    sim_result_t res;
    char err[SIM_CONFIG_ERR_LEN + 64];
    char trace_path[1024], report_path[1024];
    sim_serial_options_t ser;
    sim_serial_t *serial = NULL;
    const char *fault_arg[SIM_MAX_FAULTS] = {NULL}, *cmd_arg[SIM_MAX_CMDS] = {NULL};
    const char *duration_arg = NULL;
    double trace_max_mb = SIM_TRACE_MAX_MB_DEFAULT;
    char why[512];
    int i, rc;

    memset(&opt, 0, sizeof opt);
    memset(&ser, 0, sizeof ser);
    ser.realtime_factor = 1.0;
    opt.scenario = SCEN_START;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--keys") == 0) {
            sim_config_print_keys();
            return 0;
        } else if (strcmp(a, "--quiet") == 0) {
            opt.quiet = 1u;
        } else if (strcmp(a, "--serial-keep-open") == 0) {
            ser.keep_open = 1u;
        } else if (!takes_value(a)) {
            fprintf(stderr, "motor_sim: unknown option '%s'; see --help\n", a);
            return 1;
        } else if (v == NULL) {
            fprintf(stderr, "motor_sim: %s needs a value; see --help\n", a);
            return 1;
        } else if (strcmp(a, "--config") == 0) {
            config = v;
            i++;
        } else if (strcmp(a, "--out") == 0) {
            out_dir = v;
            i++;
        } else if (strcmp(a, "--scenario") == 0) {
            if (sim_scenario_parse(v, &opt.scenario) != 0) {
                fprintf(stderr, "motor_sim: unknown scenario '%s' (%s)\n", v, scenario_names());
                return 1;
            }
            i++;
        } else if (strcmp(a, "--duration") == 0) {
            if (parse_double(v, &opt.duration_s) != 0 || !(opt.duration_s > 0.0) ||
                opt.duration_s > 3600.0) {
                fprintf(stderr, "motor_sim: --duration '%s' must be a number in (0, 3600]\n", v);
                return 1;
            }
            duration_arg = v;
            i++;
        } else if (strcmp(a, "--trace-every") == 0) {
            double n;
            if (parse_double(v, &n) != 0 || !(n >= 1.0 && n <= 1e9) || n != floor(n)) {
                fprintf(stderr, "motor_sim: --trace-every '%s' must be a whole number of PWM "
                        "periods in [1, 1e9]\n", v);
                return 1;
            }
            opt.trace_every = (uint32_t)n;
            i++;
        } else if (strcmp(a, "--trace-max-mb") == 0) {
            if (parse_double(v, &trace_max_mb) != 0 || !(trace_max_mb > 0.0) ||
                trace_max_mb > SIM_TRACE_MAX_MB_LIMIT) {
                fprintf(stderr, "motor_sim: --trace-max-mb '%s' must be a number in (0, %g]\n", v,
                        SIM_TRACE_MAX_MB_LIMIT);
                return 1;
            }
            i++;
        } else if (strcmp(a, "--fault") == 0) {
            why[0] = '\0';
            if (opt.n_faults >= SIM_MAX_FAULTS ||
                parse_fault(v, &opt.faults[opt.n_faults], why, sizeof why) != 0) {
                fprintf(stderr, "motor_sim: bad --fault '%s' (NAME@SECONDS[=VALUE] or NAME@STATE[+SECONDS][=VALUE], "
                        "at most %d)%s%s\n",
                        v, SIM_MAX_FAULTS, why[0] ? ": " : "", why);
                return 1;
            }
            fault_arg[opt.n_faults] = v;
            opt.n_faults++;
            i++;
        } else if (strcmp(a, "--cmd") == 0) {
            if (opt.n_cmds >= SIM_MAX_CMDS || parse_cmd(v, &opt.cmds[opt.n_cmds]) != 0) {
                fprintf(stderr, "motor_sim: bad --cmd '%s' (start|stop|reset@SECONDS, at most %d)\n",
                        v, SIM_MAX_CMDS);
                return 1;
            }
            cmd_arg[opt.n_cmds] = v;
            opt.n_cmds++;
            i++;
        } else if (strcmp(a, "--serial") == 0) {
            ser.link_path = v;
            i++;
        } else if (strcmp(a, "--realtime-factor") == 0) {
            if (parse_double(v, &ser.realtime_factor) != 0 || !(ser.realtime_factor >= 0.0) ||
                ser.realtime_factor > 1e6) {
                fprintf(stderr, "motor_sim: --realtime-factor '%s' must be a number in [0, 1e6]\n",
                        v);
                return 1;
            }
            i++;
        } else {
            /* takes_value() lists an option that has no branch here */
            fprintf(stderr, "motor_sim: option '%s' is not implemented\n", a);
            return 1;
        }
    }
    if (ser.link_path == NULL && (ser.keep_open != 0u || ser.realtime_factor != 1.0)) {
        fprintf(stderr, "motor_sim: --realtime-factor and --serial-keep-open need --serial\n");
        return 1;
    }
    if (out_dir != NULL) {
        /* what an earlier run left there must not pass for this run's, whatever
         * makes this one fail (the INI, the options, the run itself): both
         * files are written anew only by a run that completes */
        remove_stale(out_dir, "report.json");
        remove_stale(out_dir, "trace.csv");
    }
    if (sim_config_load(config, &cfg, err, sizeof err) != 0) {
        fprintf(stderr, "motor_sim: %s\n", err);
        return 1;
    }
    if (cfg.note[0] != '\0') {
        fprintf(stderr, "motor_sim: note: %s\n", cfg.note);
    }
    if (ser.link_path != NULL && opt.duration_s <= 0.0) {
        opt.duration_s = 3600.0;   /* the board runs until stopped */
    }
    if (sim_run_periods(&cfg, sim_run_duration_s(&cfg, &opt)) == 0u) {
        fprintf(stderr, "motor_sim: --duration '%s' is shorter than one PWM period (%g s): "
                "nothing would be simulated\n", (duration_arg != NULL) ? duration_arg : "(default)", 1.0 / cfg.board.pwm_freq_Hz);
        return 1;
    }
    if (check_timeline(&cfg, &opt, fault_arg, cmd_arg) != 0) {
        return 1;
    }
    if (out_dir != NULL) {
        struct stat st;
        int n_trace, n_report;
        char failed[4096];
        if (make_dirs(out_dir, failed, sizeof failed) != 0) {
            fprintf(stderr, "motor_sim: cannot create %s (%s)\n", failed, strerror(errno));
            return 1;
        }
        if (stat(out_dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
            fprintf(stderr, "motor_sim: --out %s is not a directory\n", out_dir);
            return 1;
        }
        /* a truncated path would write some other file */
        n_trace = snprintf(trace_path, sizeof trace_path, "%s/trace.csv", out_dir);
        n_report = snprintf(report_path, sizeof report_path, "%s/report.json", out_dir);
        if (n_trace < 0 || (size_t)n_trace >= sizeof trace_path || n_report < 0 ||
            (size_t)n_report >= sizeof report_path) {
            fprintf(stderr, "motor_sim: --out path longer than %u characters\n",
                    (unsigned)(sizeof report_path - sizeof "/report.json"));
            return 1;
        }
        opt.trace_path = trace_path;
        if (ser.link_path != NULL && duration_arg == NULL) {
            /* a session the client ends: no length to size the trace by; it
             * stops at the limit (the run goes on), saying so */
            opt.trace_max_bytes = trace_max_mb * 1e6;
        } else if (size_trace(&cfg, &opt, trace_max_mb) != 0) {
            return 1;
        }
    }
    if (ser.link_path != NULL) {
        serial = sim_serial_open(&ser, err, sizeof err);
        if (serial == NULL) {
            fprintf(stderr, "motor_sim: --serial: %s\n", err);
            return 1;
        }
        opt.no_autostart = 1u;   /* the board waits for $C,S or its button */
        opt.background_hook = sim_serial_hook;
        opt.hook_ctx = serial;
        printf("motor_sim: serial link %s -> %s (raw, 115200 8N1 nominal), real-time factor "
               "%g; waiting for $C,S\n",
               ser.link_path, sim_serial_slave_name(serial), ser.realtime_factor);
        fflush(stdout);
    }
    /* the start scenario, as a board would be run: until the verdict */
    opt.stop_when_decided =
        (uint16_t)(opt.scenario == SCEN_START && opt.duration_s <= 0.0 && serial == NULL);
    rc = sim_run(&cfg, &opt, &res, err, sizeof err);
    if (serial != NULL) {
        uint32_t n_cmds, n_frames;
        uint16_t dropped, rx_errors;
        sim_serial_counts(serial, &n_cmds, &n_frames, &dropped, &rx_errors);
        if (!opt.quiet) {
            printf("motor_sim: serial link ended (%s): %u commands, %u frame pairs, %u frames "
                   "dropped, %u bad command frames\n",
                   sim_serial_end_reason(serial), (unsigned)n_cmds, (unsigned)n_frames, dropped,
                   rx_errors);
        }
        sim_serial_close(serial);
    }
    if (rc != 0) {
        fprintf(stderr, "motor_sim: %s\n", err);
        return 2;
    }
    if (out_dir != NULL && report_write_json(report_path, &cfg, config, &opt, &res) != 0) {
        fprintf(stderr, "motor_sim: cannot write %s\n", report_path);
        return 2;
    }
    if (res.trace_truncated_at_s >= 0.0) {
        fprintf(stderr, "motor_sim: %s reached --trace-max-mb %g at %.3f s: the rest of the run "
                "is not traced (--trace-every thins it)\n", trace_path, trace_max_mb,
                res.trace_truncated_at_s);
    }
    if (res.plant_diverged_at_s >= 0.0) {
        fprintf(stderr, "motor_sim: the simulated motor's state stopped being finite at %.6f s "
                "(its integration diverged): the run ended there%s\n", res.plant_diverged_at_s,
                (out_dir != NULL) ? "; report.json has null for each figure that was not a "
                                    "number (\"non_finite\")" : "");
        return 2;
    }
    if (!opt.quiet) {
        printf("motor_sim: %s, scenario %s, %.2f s simulated in %.2f s (%.0fx real time)\n",
               config, sim_scenario_name(opt.scenario), res.duration_s, res.wall_s,
               res.wall_s > 0 ? res.duration_s / res.wall_s : 0.0);
        report_print_table(stdout, &res);
        report_print_adaptation(stdout, &res);
        printf("final speed %.1f r/min, state %u, fault %u, PWM %s\n", res.final_speed_rpm,
               res.final_state, res.final_fault, res.final_pwm_on ? "on" : "off");
        if (out_dir != NULL) {
            printf("wrote %s and %s\n", trace_path, report_path);
        }
    }
    /* (a --serial session is the PC tool's: it reads the verdict over the
     * link, and a clean end of the session is a success) */
    if (!res.identified && serial == NULL) {
        if (!opt.quiet) {
            fprintf(stderr, "motor_sim: nothing published: %s\n",
                    drive_pub_reason_str(res.publish_reason));
        }
        return MOTOR_SIM_NOT_PUBLISHED;
    }
    return 0;
}
