/**
 * isr_cost: the instrumented host build behind tools/bench_isr.py (IQ_MATH
 * only; not a test).  The whole core is compiled against the counted IQmath
 * (iqmath_counted: every IQmath operation increments a counter) and, by the
 * CMake target, with gcov instrumentation (line execution counts for the
 * other operations).  The configured motor's identification runs closed
 * loop against the simulator's plant, through every state of the sequence
 * (the paper's, or the adaptive one with its passes).
 *
 * Two passes over the same deterministic run (same configuration, seed,
 * background schedule; the counters do not touch the dynamics):
 *  1. the timeline: the identification state at the entry of every ISR and
 *     its slot of the multi-rate schedule (drive_slot_t);
 *  2. the samples: for every class (state, slot), the first two and last two
 *     ISRs of the class (the state's transitions) and SAMPLES_UNIFORM more
 *     spread evenly over it.  Each sampled ISR alone: the gcov counters are
 *     reset before it and dumped after it into its own folder (GCOV_PREFIX
 *     = OUT/s<index>), so that its line counts are that ISR's and nothing
 *     else's (the background, which runs between ISRs, is never inside);
 *     its IQmath calls are counted per operation, and per step function
 *     drive_step() calls (link-time wrappers, for the per-module report).
 *
 * Output (stdout, JSON):
 *   {"isrs": N, "iqmath_names": [...], "slots": S, "functions": [...],
 *    "state_isrs": {"STATE": n, ...},
 *    "samples": [{"index": k, "state": "ACCELERATE", "slot": s,
 *                 "uniform": 0|1, "dir": "s<k>", "iq": [per op],
 *                 "fn_iq": [[per op] per function]}, ...]}
 * Usage: isr_cost CONFIG.ini --out DIR [--uniform K] [--duration S]
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "drive_types.h"
#include "hal_host.h"
#include "plant.h"
#include "sim_config.h"

#if !defined(IQMATH_COUNT_CALLS) || (MATH_TYPE != IQ_MATH)
#error "isr_cost needs the counted IQ_MATH build (iqmath_counted)"
#endif

void __gcov_dump(void);
void __gcov_reset(void);

#define N_OPS IQMATH_FN_COUNT
#define N_STATES 8          /* id_state_t: IDLE .. REFINE */
#define MAX_SAMPLES_CLASS 64u

static const char *const k_state_names[N_STATES] = {
    "IDLE", "CALIBRATE", "MAGNETIZE", "ACCELERATE", "SETTLE", "RUN", "FAULT", "REFINE"};

/* ---- per-function attribution of the IQmath calls (link-time wrappers) --- */

typedef struct {
    const char *name;
    uint32_t iq[N_OPS];
} fn_row_t;

enum {
    F_PHASE_CURRENT, F_DC_BUS, F_QEP_SPEED, F_PROTECT, F_ENC_CHECK, F_CUR_CHECK, F_VOLT_CALC,
    F_VOLT_FF, F_CLARKE, F_PARK, F_IPARK, F_IFO_FRAME, F_IFO_SLIP, F_IFO_GAIN, F_ANGLE_SINCOS,
    F_ANGLE_STEP, F_REG_ACC, F_REG_FILTER, F_RLS_ROW1, F_RLS_ROW2, F_GUARD, F_SEQUENCE,
    F_RAMP, F_PI_STEP, F_PI_RESET, F_SVGEN, F_FLUX_OBS, F_ADAPT_FAST, F_ADAPT_SLOW, F_COUNT
};

static fn_row_t g_rows[F_COUNT] = {
    {"phase_current_step", {0}}, {"dc_bus_step", {0}}, {"qep_speed_step", {0}},
    {"protect_step", {0}}, {"encoder_check_step", {0}}, {"current_check_step", {0}},
    {"volt_calc_step", {0}}, {"volt_calc_feedforward", {0}}, {"clarke_step", {0}},
    {"park_step", {0}}, {"ipark_step", {0}}, {"ifo_frame_from_rotor", {0}},
    {"ifo_step_slip_fast", {0}}, {"ifo_update_slip_gain", {0}}, {"angle_sincos", {0}},
    {"angle_sincos_step", {0}}, {"ident_regressor_accumulate", {0}},
    {"ident_regressor_filter", {0}}, {"rls_step_row1", {0}}, {"rls_step_row2", {0}},
    {"theta_guard_step", {0}}, {"id_sequence_step", {0}}, {"ramp_gen_step", {0}},
    {"pi_step", {0}}, {"pi_reset", {0}}, {"svgen_step", {0}}, {"flux_obs_step", {0}},
    {"drive_adapt_fast", {0}}, {"drive_adapt_slow", {0}}};

static int g_depth;                /* wrapped calls nest (a module calling angle_*) */
static uint32_t g_snap[N_OPS];

/* Only the outermost wrapped call is recorded: a nested one counts for its
 * caller, so the rows add up to what drive_step() spent in them. */
static void pre(void)
{
    if (g_depth++ == 0) {
        memcpy(g_snap, iqmath_call_count, sizeof g_snap);
    }
}

static void post(int id)
{
    int i;
    if (--g_depth != 0) {
        return;
    }
    for (i = 0; i < N_OPS; i++) {
        g_rows[id].iq[i] += iqmath_call_count[i] - g_snap[i];
    }
}

#define WRAP_VOID1(NAME, ID, T)                                                                    \
    void __real_##NAME(T a);                                                                       \
    void __wrap_##NAME(T a);                                                                       \
    void __wrap_##NAME(T a) { pre(); __real_##NAME(a); post(ID); }

WRAP_VOID1(phase_current_step, F_PHASE_CURRENT, phase_current_t *)
WRAP_VOID1(dc_bus_step, F_DC_BUS, dc_bus_t *)
WRAP_VOID1(qep_speed_step, F_QEP_SPEED, qep_speed_t *)
WRAP_VOID1(protect_step, F_PROTECT, protect_t *)
WRAP_VOID1(encoder_check_step, F_ENC_CHECK, encoder_check_t *)
WRAP_VOID1(current_check_step, F_CUR_CHECK, current_check_t *)
WRAP_VOID1(volt_calc_step, F_VOLT_CALC, volt_calc_t *)
WRAP_VOID1(clarke_step, F_CLARKE, clarke_t *)
WRAP_VOID1(park_step, F_PARK, park_t *)
WRAP_VOID1(ipark_step, F_IPARK, ipark_t *)
WRAP_VOID1(ifo_frame_from_rotor, F_IFO_FRAME, ifo_t *)
WRAP_VOID1(ifo_step_slip_fast, F_IFO_SLIP, ifo_t *)
WRAP_VOID1(ifo_update_slip_gain, F_IFO_GAIN, ifo_t *)
WRAP_VOID1(ident_regressor_accumulate, F_REG_ACC, ident_regressor_t *)
WRAP_VOID1(ident_regressor_filter, F_REG_FILTER, ident_regressor_t *)
WRAP_VOID1(rls_step_row1, F_RLS_ROW1, rls_t *)
WRAP_VOID1(rls_step_row2, F_RLS_ROW2, rls_t *)
WRAP_VOID1(theta_guard_step, F_GUARD, theta_guard_t *)
WRAP_VOID1(id_sequence_step, F_SEQUENCE, id_sequence_t *)
WRAP_VOID1(ramp_gen_step, F_RAMP, ramp_gen_t *)
WRAP_VOID1(pi_step, F_PI_STEP, pi_ctrl_t *)
WRAP_VOID1(pi_reset, F_PI_RESET, pi_ctrl_t *)
WRAP_VOID1(svgen_step, F_SVGEN, svgen_t *)
WRAP_VOID1(flux_obs_step, F_FLUX_OBS, flux_obs_t *)
WRAP_VOID1(drive_adapt_fast, F_ADAPT_FAST, drive_t *)
WRAP_VOID1(drive_adapt_slow, F_ADAPT_SLOW, drive_t *)

void __real_angle_sincos(_iq a, _iq *s, _iq *c);
void __wrap_angle_sincos(_iq a, _iq *s, _iq *c);
void __wrap_angle_sincos(_iq a, _iq *s, _iq *c)
{
    pre();
    __real_angle_sincos(a, s, c);
    post(F_ANGLE_SINCOS);
}

void __real_angle_sincos_step(_iq s, _iq c, _iq a, _iq d, _iq *s2, _iq *c2);
void __wrap_angle_sincos_step(_iq s, _iq c, _iq a, _iq d, _iq *s2, _iq *c2);
void __wrap_angle_sincos_step(_iq s, _iq c, _iq a, _iq d, _iq *s2, _iq *c2)
{
    pre();
    __real_angle_sincos_step(s, c, a, d, s2, c2);
    post(F_ANGLE_STEP);
}

void __real_volt_calc_feedforward(const volt_calc_t *v, _iq vdc, _iq ia, _iq ib, _iq *da,
                                  _iq *db);
void __wrap_volt_calc_feedforward(const volt_calc_t *v, _iq vdc, _iq ia, _iq ib, _iq *da,
                                  _iq *db);
void __wrap_volt_calc_feedforward(const volt_calc_t *v, _iq vdc, _iq ia, _iq ib, _iq *da,
                                  _iq *db)
{
    pre();
    __real_volt_calc_feedforward(v, vdc, ia, ib, da, db);
    post(F_VOLT_FF);
}

/* ---- the closed loop --------------------------------------------------- */

typedef struct {
    drive_t drive;
    plant_t plant;
    hal_host_port_t port;
    hal_pwm_compare_t active;
    uint32_t k;
} run_t;

static int run_start(run_t *r, const sim_config_t *cfg)
{
    drive_config_t dc;
    char err[SIM_CONFIG_ERR_LEN];
    sim_config_to_drive(cfg, &dc);
    if (drive_init(&r->drive, &dc) != DRIVE_CFG_OK ||
        plant_init(&r->plant, cfg, r->drive.t1pr, err, sizeof err) != 0) {
        return 1;
    }
    hal_host_port_init(&r->port, r->drive.t1pr);
    hal_host_bind(&r->port);
    r->active = r->port.cmp;
    r->k = 0u;
    drive_command(&r->drive, DRIVE_CMD_START_IDENT);
    drive_background(&r->drive);
    return 0;
}

/* The plant's sample, one ISR (measured by the caller around it), the
 * period; the background at 1 kHz between ISRs, as motor_sim. */
static void run_before_isr(run_t *r)
{
    plant_sample(&r->plant, &r->port);
    r->port.trip_input = 0u;
}

static void run_after_isr(run_t *r)
{
    if ((r->k % 15u) == 0u) {
        drive_background(&r->drive);
    }
    plant_period(&r->plant, &r->active, r->port.outputs_enabled);
    r->active = r->port.cmp;
    r->k++;
}

/* ---- the schedule of samples ------------------------------------------- */

static uint32_t *g_class_idx[N_STATES][DRIVE_SLOTS];   /* ISR indices of each class */
static uint32_t g_class_n[N_STATES][DRIVE_SLOTS];

/* 0: not sampled; 1: a transition sample; 2: a uniform one */
static uint8_t sample_kind(uint32_t pos, uint32_t n, uint32_t uniform)
{
    uint32_t j;
    if (pos < 2u || pos + 2u >= n) {
        return 1u;
    }
    for (j = 0u; j < uniform; j++) {
        if (pos == (uint32_t)(((uint64_t)(2u * j + 1u) * n) / (2u * uniform))) {
            return 2u;
        }
    }
    return 0u;
}

static void print_vec32(const uint32_t *v)
{
    int i;
    printf("[");
    for (i = 0; i < N_OPS; i++) {
        printf("%s%u", i ? "," : "", (unsigned)v[i]);
    }
    printf("]");
}

int main(int argc, char **argv)
{
    static run_t run;
    sim_config_t cfg;
    char err[SIM_CONFIG_ERR_LEN];
    const char *out = NULL;
    double duration = 0.0;
    uint32_t uniform = 12u, n_isr, k;
    uint8_t *state_at, *kind;
    int a, i, first = 1;

    if (argc < 2) {
        fprintf(stderr, "usage: isr_cost CONFIG.ini --out DIR [--uniform K] [--duration S]\n");
        return 2;
    }
    for (a = 2; a + 1 < argc; a += 2) {
        if (strcmp(argv[a], "--out") == 0) {
            out = argv[a + 1];
        } else if (strcmp(argv[a], "--uniform") == 0) {
            uniform = (uint32_t)strtoul(argv[a + 1], NULL, 10);
        } else if (strcmp(argv[a], "--duration") == 0) {
            duration = strtod(argv[a + 1], NULL);
        } else {
            fprintf(stderr, "isr_cost: unknown option %s\n", argv[a]);
            return 2;
        }
    }
    if (out == NULL || uniform > MAX_SAMPLES_CLASS) {
        fprintf(stderr, "isr_cost: --out DIR is required, --uniform at most %u\n",
                MAX_SAMPLES_CLASS);
        return 2;
    }
    if (sim_config_load(argv[1], &cfg, err, sizeof err) != 0) {
        fprintf(stderr, "isr_cost: %s\n", err);
        return 1;
    }
    if (!(duration > 0.0)) {
        /* the paper's sequence is in RUN after ~3 s; the adaptive one's
         * passes and its tracker's first second take longer */
        duration = (cfg.orientation == 1.0) ? 12.0 : 6.0;
    }
    n_isr = (uint32_t)(duration * cfg.pwm_freq_Hz);
    state_at = calloc(n_isr, 1u);
    kind = calloc(n_isr, 1u);
    if (state_at == NULL || kind == NULL) {
        fprintf(stderr, "isr_cost: out of memory\n");
        return 1;
    }

    /* pass 1: the timeline */
    if (run_start(&run, &cfg) != 0) {
        fprintf(stderr, "isr_cost: configuration refused\n");
        return 1;
    }
    for (k = 0u; k < n_isr; k++) {
        uint16_t st = (uint16_t)run.drive.seq.state;
        uint16_t slot = run.drive.slot;
        state_at[k] = (uint8_t)((st < N_STATES) ? st : 0u);
        g_class_n[state_at[k]][slot]++;
        run_before_isr(&run);
        drive_isr(&run.drive);
        run_after_isr(&run);
    }
    {
        uint32_t pos[N_STATES][DRIVE_SLOTS] = {{0}};
        int s, t;
        for (s = 0; s < N_STATES; s++) {
            for (t = 0; t < (int)DRIVE_SLOTS; t++) {
                g_class_idx[s][t] = calloc(g_class_n[s][t] + 1u, sizeof(uint32_t));
            }
        }
        for (k = 0u; k < n_isr; k++) {
            int st = state_at[k];
            int sl = (int)(k % DRIVE_SLOTS);   /* the slot advances every ISR from 0 */
            uint32_t p = pos[st][sl]++;
            kind[k] = sample_kind(p, g_class_n[st][sl], uniform);
        }
    }

    /* pass 2: the samples */
    if (mkdir(out, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "isr_cost: cannot create %s\n", out);
        return 1;
    }
    if (run_start(&run, &cfg) != 0) {
        return 1;
    }
    printf("{\"isrs\": %u, \"slots\": %u, \"iqmath_names\": [", (unsigned)n_isr,
           (unsigned)DRIVE_SLOTS);
    for (i = 0; i < N_OPS; i++) {
        printf("%s\"%s\"", i ? ", " : "", iqmath_fn_name(i));
    }
    printf("],\n \"functions\": [");
    for (i = 0; i < F_COUNT; i++) {
        printf("%s\"%s\"", i ? ", " : "", g_rows[i].name);
    }
    printf("],\n \"state_isrs\": {");
    for (i = 0; i < N_STATES; i++) {
        uint32_t n = 0u;
        int t;
        for (t = 0; t < (int)DRIVE_SLOTS; t++) {
            n += g_class_n[i][t];
        }
        printf("%s\"%s\": %u", i ? ", " : "", k_state_names[i], (unsigned)n);
    }
    printf("},\n \"samples\": [");
    for (k = 0u; k < n_isr; k++) {
        if (kind[k] == 0u || state_at[k] == (uint8_t)ID_IDLE) {
            run_before_isr(&run);
            drive_isr(&run.drive);
            run_after_isr(&run);
            continue;
        }
        {
            char dir[512];
            uint16_t slot = run.drive.slot;
            run_before_isr(&run);
            for (i = 0; i < F_COUNT; i++) {
                memset(g_rows[i].iq, 0, sizeof g_rows[i].iq);
            }
            iqmath_count_reset();
            __gcov_reset();
            drive_isr(&run.drive);
            (void)snprintf(dir, sizeof dir, "%s/s%u", out, (unsigned)k);
            (void)setenv("GCOV_PREFIX", dir, 1);
            __gcov_dump();
            printf("%s\n  {\"index\": %u, \"state\": \"%s\", \"slot\": %u, \"uniform\": %u, "
                   "\"dir\": \"s%u\", \"iq\": ",
                   first ? "" : ",", (unsigned)k, k_state_names[state_at[k]], (unsigned)slot,
                   (unsigned)(kind[k] == 2u), (unsigned)k);
            print_vec32(iqmath_call_count);
            printf(", \"fn_iq\": [");
            for (i = 0; i < F_COUNT; i++) {
                printf("%s", i ? "," : "");
                print_vec32(g_rows[i].iq);
            }
            printf("]}");
            first = 0;
            run_after_isr(&run);
        }
    }
    printf("]}\n");
    /* no exit-time dump: every count was written by its sample */
    (void)unsetenv("GCOV_PREFIX");
    fflush(stdout);
    _Exit(0);
}
