/**
 * motor_sim: the F2812 firmware (unchanged drive_isr) in closed loop with a
 * simulated induction motor, inverter and sensors; runs the identification
 * and reports what it found.  See `motor_sim --help`.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "report.h"
#include "sim_config.h"
#include "sim_run.h"
#include "sim_serial.h"

#define MOTOR_SIM_NOT_PUBLISHED 3   /* exit status: the run completed, nothing published */

static void usage(FILE *f)
{
    fprintf(f,
            "usage: motor_sim [--config FILE] [--scenario NAME] [--duration S] [--out DIR]\n"
            "                 [--fault NAME@TIME[=VALUE]]... [--cmd NAME@TIME]... [--quiet]\n"
            "                 [--serial PATH [--realtime-factor X] [--serial-keep-open]]\n"
            "                 [--keys] [--help]\n"
            "\n"
            "Runs the firmware's 15 kHz ISR against a simulated induction motor, inverter and\n"
            "sensors: offset calibration, magnetisation, acceleration with the online RLS\n"
            "identification, steady state, parameter extraction.\n"
            "\n"
            "  --config FILE      INI file (default host_sim/config/paper_motor.ini)\n"
            "  --scenario NAME    start (default: standstill to rated speed under load),\n"
            "                     reversal (then to -rated speed), load_steps (then a load step),\n"
            "                     soak (then reversals every 4 s, a load step 2 s after each),\n"
            "                     drift (then the rotor resistance rises while the load\n"
            "                     changes: [drift] keys; for [ident] track_rr = 1)\n"
            "  --duration S       simulated seconds (default: the start scenario runs until the\n"
            "                     drive's verdict on its set, published or refused, and 0.5 s\n"
            "                     more, or a time-out long enough for every pass; the other\n"
            "                     scenarios long enough for their events)\n"
            "  --out DIR          write DIR/trace.csv and DIR/report.json (DIR and its parents\n"
            "                     are created if missing)\n"
            "  --fault NAME@T     inject at T seconds: hall_gain (=rel. error, default 0.2),\n"
            "                     hall_lost (phase b reads 0 A), bus_sag (=rel. drop, default\n"
            "                     0.5), overvoltage (=rel. rise, default 0.5), encoder_lost\n"
            "                     (T2 frozen), encoder_jump (=counts, default 100), short\n"
            "                     (a-b short, =loop inductance uH, default 20), adc_rail (bus\n"
            "                     feedback at the top rail), offset (phase-a sensor offset, =fraction\n"
            "                     of full scale, default 0.1), hw_trip (PDPINTA low, =seconds,\n"
            "                     default 100), clear (every injected fault removed)\n"
            "  --cmd NAME@T       give the drive a command at T seconds: start, stop, reset\n"
            "                     (a run begins with start at 0)\n"
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
            "Exit status: 0 the drive published its identified set; 1 usage or configuration\n"
            "error; 2 run failed (the firmware refused the configuration, a file could not be\n"
            "written); 3 the run completed but nothing was published: the drive refused its set,\n"
            "or the run ended before its verdict (report.json \"publish_reason\": not_converged,\n"
            "low_excitation, high_residual, low_confidence, implausible, fault, timeout,\n"
            "stopped, or pending).  --help and --keys exit 0.\n");
}

/* The options followed by a value.  Checked before any value is used, so
 * that such an option as the last argument is an error, never a NULL value. */
static int takes_value(const char *a)
{
    static const char *const k[] = {"--config", "--out",   "--scenario",
                                     "--duration", "--fault", "--cmd",
                                     "--serial", "--realtime-factor"};
    unsigned i;
    for (i = 0; i < sizeof k / sizeof k[0]; i++) {
        if (strcmp(a, k[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

static int parse_double(const char *s, double *out)
{
    char *end = NULL;
    errno = 0;
    *out = strtod(s, &end);
    return (s[0] != '\0' && end != NULL && *end == '\0' && errno == 0) ? 0 : -1;
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

static int parse_fault(const char *arg, sim_fault_t *f)
{
    static const struct { const char *name; plant_fault_t kind; double def; } k[] = {
        {"hall_gain", PLANT_FAULT_HALL_GAIN, 0.2},   {"hall_lost", PLANT_FAULT_HALL_LOST, 0},
        {"bus_sag", PLANT_FAULT_BUS_SAG, 0.5},       {"overvoltage", PLANT_FAULT_OVERVOLTAGE, 0.5},
        {"encoder_lost", PLANT_FAULT_ENCODER_LOST, 0}, {"short", PLANT_FAULT_SHORT, 20.0},
        {"adc_rail", PLANT_FAULT_ADC_RAIL, 0},       {"offset", PLANT_FAULT_CURRENT_OFFSET, 0.1},
        {"encoder_jump", PLANT_FAULT_ENCODER_JUMP, 100}, {"hw_trip", PLANT_FAULT_HW_TRIP, 100},
        {"clear", PLANT_FAULT_CLEAR, 0},
    };
    char buf[128];
    char *at, *eq;
    size_t len = strlen(arg);
    unsigned i;
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
    for (i = 0; i < sizeof k / sizeof k[0]; i++) {
        if (strcmp(buf, k[i].name) == 0) {
            f->kind = k[i].kind;
            f->value = k[i].def;
            if (parse_double(at + 1, &f->t_s) != 0 || !(f->t_s >= 0.0) || f->t_s > 1e6) {
                return -1;
            }
            /* written so that a NaN fails too */
            if (eq != NULL && (parse_double(eq + 1, &f->value) != 0 ||
                               !(f->value >= -0.99 && f->value <= 100.0))) {
                return -1;
            }
            return 0;
        }
    }
    return -1;
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
                fprintf(stderr, "motor_sim: unknown scenario '%s' (start, reversal, load_steps)\n",
                        v);
                return 1;
            }
            i++;
        } else if (strcmp(a, "--duration") == 0) {
            if (parse_double(v, &opt.duration_s) != 0 || !(opt.duration_s > 0.0) ||
                opt.duration_s > 3600.0) {
                fprintf(stderr, "motor_sim: --duration '%s' must be a number in (0, 3600]\n", v);
                return 1;
            }
            i++;
        } else if (strcmp(a, "--fault") == 0) {
            if (opt.n_faults >= SIM_MAX_FAULTS || parse_fault(v, &opt.faults[opt.n_faults]) != 0) {
                fprintf(stderr, "motor_sim: bad --fault '%s' (NAME@SECONDS[=VALUE], at most %d)\n",
                        v, SIM_MAX_FAULTS);
                return 1;
            }
            opt.n_faults++;
            i++;
        } else if (strcmp(a, "--cmd") == 0) {
            if (opt.n_cmds >= SIM_MAX_CMDS || parse_cmd(v, &opt.cmds[opt.n_cmds]) != 0) {
                fprintf(stderr, "motor_sim: bad --cmd '%s' (start|stop|reset@SECONDS, at most %d)\n",
                        v, SIM_MAX_CMDS);
                return 1;
            }
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
    if (sim_config_load(config, &cfg, err, sizeof err) != 0) {
        fprintf(stderr, "motor_sim: %s\n", err);
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
        if (opt.duration_s <= 0.0) {
            opt.duration_s = 3600.0;
        }
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
    if (!res.identified) {
        if (!opt.quiet) {
            fprintf(stderr, "motor_sim: nothing published: %s\n",
                    drive_pub_reason_str(res.publish_reason));
        }
        return MOTOR_SIM_NOT_PUBLISHED;
    }
    return 0;
}
