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
 *     ISRs of the class (the state's transitions) and K (--uniform) more
 *     spread evenly over it.  Each sampled ISR alone: the gcov counters are
 *     reset before it and dumped after it into its own folder (GCOV_PREFIX
 *     = OUT/s<index>), so that its line counts are that ISR's and nothing
 *     else's (the background, which runs between ISRs, is never inside);
 *     and after it, its slow ISR (drive_slow_isr) alone the same way
 *     (OUT/s<index>_slow);
 *     its IQmath calls are counted per operation (bench_isr.py attributes
 *     them to modules by the executed lines that make them, and checks that
 *     attribution against these counts).
 *  3. every path: the core (src/) is also compiled with
 *     -fsanitize-coverage=trace-pc, GCC's call of __sanitizer_cov_trace_pc
 *     at the entry of every basic block.  Pass 1 notes, per class and ISR
 *     (control, slow), the first ISR that runs each block; such an ISR is
 *     sampled too (a "coverage" sample), so that every block an ISR of a
 *     class runs is in one of the class's samples: the events that happen
 *     once (a test's verdict, a calibration's end, a state's entry) are in
 *     the worst ISR, not only the ISRs the schedule above happens to pick.
 *     Pass 2 checks it: a block that ran in an ISR of a class but in none
 *     of its samples is listed ("unsampled", its address in the executable
 *     for addr2line; bench_isr.py prices each such line).
 *
 * Output (stdout, JSON):
 *   {"isrs": N, "iqmath_names": [...], "slots": S, "log_slot": L,
 *    "state_isrs": {"STATE": n, ...},
 *    "samples": [{"index": k, "state": "ACCELERATE", "slot": s,
 *                 "uniform": 0|1, "coverage": 0|1, "dir": "s<k>",
 *                 "dir_slow": "s<k>_slow", "iq": [per op], "iq_slow": [per op]}, ...],
 *    "coverage_samples": c, "blocks": n, "pass_mismatch": m,
 *    "unsampled": [{"state": "...", "slot": s, "isr": "control"|"slow",
 *                   "offset": a}, ...]}
 * Usage: isr_cost CONFIG.ini --out DIR [--uniform K] [--duration S]
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "drive_probe.h"
#include "hal_host.h"
#include "plant.h"
#include "sim_config.h"

#if !defined(IQMATH_COUNT_CALLS) || (MATH_TYPE != IQ_MATH)
#error "isr_cost needs the counted IQ_MATH build (iqmath_counted)"
#endif

void __gcov_dump(void);
void __gcov_reset(void);

#define N_OPS IQMATH_FN_COUNT
/* The classes' states: id_state_t (IDLE .. INJECT), and CALIBRATE's phases
 * apart.  The sequence's outputs choose a phase for a whole control ISR (it
 * steps in the slow task): the offsets' calibration (seq.calibrating), the
 * sensor test (sensor_testing), the bridge's curve test (vi_testing); their
 * code never runs in one ISR together, so each phase is a class of its own
 * (bench_isr.py reports them as CALIBRATE, its worst the worst phase's). */
#define N_ID_STATES 9       /* id_state_t: IDLE .. INJECT */
#define ST_CAL_OFFSETS 9
#define ST_CAL_SENSOR_TEST 10
#define ST_CAL_BRIDGE_TEST 11
#define N_STATES 12
#define MAX_SAMPLES_CLASS 64u

static const char *const k_state_names[N_STATES] = {
    "IDLE", "CALIBRATE", "MAGNETIZE", "ACCELERATE", "SETTLE", "RUN", "FAULT", "REFINE", "INJECT",
    "CALIBRATE.offsets", "CALIBRATE.sensor_test", "CALIBRATE.bridge_test"};

/* The class state of the next ISR, from the sequence as it stands. */
static uint8_t class_state(const drive_probe_t *p)
{
    const uint16_t st = (uint16_t)p->seq->state;
    if (st >= N_ID_STATES) {
        return 0u;
    }
    if (st == (uint16_t)ID_CALIBRATE) {
        if (p->seq->calibrating != 0u) {
            return ST_CAL_OFFSETS;
        }
        if (p->seq->sensor_testing != 0u) {
            return ST_CAL_SENSOR_TEST;
        }
        if (p->seq->vi_testing != 0u) {
            return ST_CAL_BRIDGE_TEST;
        }
    }
    return (uint8_t)st;
}

/* ---- the closed loop --------------------------------------------------- */

typedef struct {
    drive_t drive;
    drive_probe_t pv;           /* what the rig reads of it */
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
    drive_probe(&r->drive, &r->pv);
    if (drive_init(&r->drive, &dc) != DRIVE_CFG_OK ||
        plant_init(&r->plant, cfg, r->pv.k->t1pr, err, sizeof err) != 0) {
        return 1;
    }
    hal_host_port_init(&r->port, r->pv.k->t1pr);
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

/* ---- every path: the blocks each class of ISR runs ---------------------- */

#define COV_BITS 20u
#define COV_SIZE (1u << COV_BITS)
#define COV_PASS1 1u      /* ran in an ISR of the class in pass 1 */
#define COV_PASS2 2u      /* ... in pass 2 */
#define COV_SAMPLED 4u    /* ... in a sampled ISR of pass 2 */

static uint64_t *g_cov_key;    /* (class << 40 | offset) + 1; 0: empty */
static uint8_t *g_cov_flag;
static uint32_t g_cov_n;
static int g_cov_class = -1;   /* the running ISR's class, -1 outside the ISRs */
static uint8_t g_cov_mark;     /* what the running ISR sets */
static int g_cov_new;          /* the running ISR ran a block new to its class */
static uintptr_t g_cov_base;   /* the executable's load address */
extern const char __executable_start[];

static int cov_class(uint16_t state, uint16_t slot, uint16_t slow)
{
    return (int)((state * DRIVE_SLOTS + slot) * 2u + slow);
}

void __sanitizer_cov_trace_pc(void);
/* GCC's callback (-fsanitize-coverage=trace-pc), at every basic block of
 * src/; this file itself is not instrumented */
void __sanitizer_cov_trace_pc(void)
{
    uint64_t key;
    uint32_t h;
    if (g_cov_class < 0) {
        return;
    }
    key = (((uint64_t)g_cov_class << 40) |
           (uint64_t)((uintptr_t)__builtin_return_address(0) - g_cov_base)) + 1u;
    h = (uint32_t)((key * 0x9E3779B97F4A7C15ull) >> (64u - COV_BITS));
    while (g_cov_key[h] != 0u && g_cov_key[h] != key) {
        h = (h + 1u) & (COV_SIZE - 1u);
    }
    if (g_cov_key[h] == 0u) {
        if (g_cov_n >= COV_SIZE / 2u) {
            fprintf(stderr, "isr_cost: coverage table full\n");
            _Exit(1);
        }
        g_cov_key[h] = key;
        g_cov_n++;
    }
    if ((g_cov_flag[h] & COV_PASS1) == 0u && g_cov_mark == COV_PASS1) {
        g_cov_new = 1;
    }
    g_cov_flag[h] |= g_cov_mark;
}

/* one period's two ISRs, their blocks recorded under their class */
static void run_isrs(run_t *r, uint16_t state, uint8_t mark)
{
    const uint16_t slot = r->pv.sched->slot;
    g_cov_mark = mark;
    g_cov_class = cov_class(state, slot, 0u);
    (void)drive_isr(&r->drive);
    g_cov_class = cov_class(state, slot, 1u);
    drive_slow_isr(&r->drive);
    g_cov_class = -1;
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
        if (pos == (uint32_t)(((uint64_t)(2u * j + 1u) * n) / ((uint64_t)2u * uniform))) {
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

/* One ISR alone (slow 0: the control ISR, 1: its slow ISR): the counters
 * zeroed before it, its gcov counts dumped after it into OUT/s<k> or
 * OUT/s<k>_slow; its IQmath calls stay in iqmath_call_count. */
static void sample_isr(drive_t *d, uint16_t state, uint16_t slot, uint16_t slow,
                       const char *out, uint32_t k)
{
    char dir[512];
    iqmath_count_reset();
    __gcov_reset();
    g_cov_mark = COV_PASS2 | COV_SAMPLED;
    g_cov_class = cov_class(state, slot, slow);
    if (slow != 0u) {
        drive_slow_isr(d);
    } else {
        (void)drive_isr(d);
    }
    g_cov_class = -1;
    (void)snprintf(dir, sizeof dir, "%s/s%u%s", out, (unsigned)k, slow ? "_slow" : "");
    (void)setenv("GCOV_PREFIX", dir, 1);
    __gcov_dump();
}

int main(int argc, char **argv)
{
    static run_t run;
    sim_config_t cfg;
    char err[SIM_CONFIG_ERR_LEN];
    const char *out = NULL;
    double duration = 0.0;
    uint32_t uniform = 12u, n_isr, k;
    uint8_t *state_at, *kind, *newcov;
    uint32_t n_cov = 0u, mismatch = 0u;
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
        duration = (cfg.controller.orientation == 1.0) ? 12.0 : 6.0;
    }
    n_isr = (uint32_t)(duration * cfg.board.pwm_freq_Hz);
    state_at = calloc(n_isr, 1u);
    kind = calloc(n_isr, 1u);
    newcov = calloc(n_isr, 1u);
    g_cov_key = calloc(COV_SIZE, sizeof *g_cov_key);
    g_cov_flag = calloc(COV_SIZE, 1u);
    if (state_at == NULL || kind == NULL || newcov == NULL || g_cov_key == NULL ||
        g_cov_flag == NULL) {
        fprintf(stderr, "isr_cost: out of memory\n");
        goto fail;
    }

    /* the blocks by their offset in the executable, addr2line's address
     * (GNU ld's symbol for the image's first byte, where it was loaded) */
    g_cov_base = (uintptr_t)__executable_start;

    /* pass 1: the timeline, and the first ISR of each block of each class */
    if (run_start(&run, &cfg) != 0) {
        fprintf(stderr, "isr_cost: configuration refused\n");
        goto fail;
    }
    for (k = 0u; k < n_isr; k++) {
        uint16_t slot = run.pv.sched->slot;
        state_at[k] = class_state(&run.pv);
        g_class_n[state_at[k]][slot]++;
        run_before_isr(&run);
        g_cov_new = 0;
        run_isrs(&run, state_at[k], COV_PASS1);
        newcov[k] = (uint8_t)g_cov_new;
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
            if (kind[k] == 0u && newcov[k] != 0u) {
                kind[k] = 3u;   /* a coverage sample */
                n_cov++;
            }
        }
    }

    /* pass 2: the samples */
    if (mkdir(out, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "isr_cost: cannot create %s\n", out);
        goto fail;
    }
    if (run_start(&run, &cfg) != 0) {
        goto fail;
    }
    printf("{\"isrs\": %u, \"slots\": %u, \"log_slot\": %u, \"iqmath_names\": [",
           (unsigned)n_isr, (unsigned)DRIVE_SLOTS, (unsigned)DRIVE_LOG_SLOT);
    for (i = 0; i < N_OPS; i++) {
        printf("%s\"%s\"", i ? ", " : "", iqmath_fn_name(i));
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
        if (kind[k] == 0u) {
            run_before_isr(&run);
            run_isrs(&run, state_at[k], COV_PASS2);
            run_after_isr(&run);
            continue;
        }
        {
            uint32_t iq_fast[N_OPS];
            uint16_t slot = run.pv.sched->slot;
            run_before_isr(&run);
            sample_isr(&run.drive, state_at[k], slot, 0u, out, k);
            /* its slow ISR, a sample of its own (dir s<k>_slow, "iq_slow") */
            memcpy(iq_fast, iqmath_call_count, sizeof iq_fast);
            sample_isr(&run.drive, state_at[k], slot, 1u, out, k);
            printf("%s\n  {\"index\": %u, \"state\": \"%s\", \"slot\": %u, \"uniform\": %u, "
                   "\"coverage\": %u, \"dir\": \"s%u\", \"dir_slow\": \"s%u_slow\", \"iq\": ",
                   first ? "" : ",", (unsigned)k, k_state_names[state_at[k]], (unsigned)slot,
                   (unsigned)(kind[k] == 2u), (unsigned)(kind[k] == 3u), (unsigned)k,
                   (unsigned)k);
            print_vec32(iq_fast);
            printf(", \"iq_slow\": ");
            print_vec32(iqmath_call_count);
            printf("}");
            first = 0;
            run_after_isr(&run);
        }
    }
    printf("],\n \"coverage_samples\": %u, \"blocks\": %u", (unsigned)n_cov, (unsigned)g_cov_n);
    /* pass 2 against pass 1 (the same deterministic run), and the blocks
     * that ran in an ISR of a class but in none of its samples */
    printf(",\n \"unsampled\": [");
    first = 1;
    for (k = 0u; k < COV_SIZE; k++) {
        const uint8_t f = g_cov_flag[k];
        if (g_cov_key[k] == 0u) {
            continue;
        }
        if (((f & COV_PASS1) != 0u) != ((f & COV_PASS2) != 0u)) {
            mismatch++;
        }
        if ((f & COV_PASS2) != 0u && (f & COV_SAMPLED) == 0u) {
            const uint64_t key = g_cov_key[k] - 1u;
            const unsigned cls = (unsigned)(key >> 40);
            printf("%s\n  {\"state\": \"%s\", \"slot\": %u, \"isr\": \"%s\", \"offset\": %llu}",
                   first ? "" : ",", k_state_names[(cls / 2u) / DRIVE_SLOTS],
                   (cls / 2u) % DRIVE_SLOTS, (cls & 1u) ? "slow" : "control",
                   (unsigned long long)(key & ((1ull << 40) - 1u)));
            first = 0;
        }
    }
    printf("],\n \"pass_mismatch\": %u}\n", (unsigned)mismatch);
    /* no exit-time dump: every count was written by its sample */
    (void)unsetenv("GCOV_PREFIX");
    fflush(stdout);
    _Exit(0);

fail:   /* every error after the allocations */
    free(state_at);
    free(kind);
    free(newcov);
    free(g_cov_key);
    free(g_cov_flag);
    return 1;
}
