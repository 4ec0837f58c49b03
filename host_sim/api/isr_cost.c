/**
 * isr_cost: the instrumented host build behind tools/bench_isr.py (IQ_MATH
 * only; not a test).  The whole core is compiled against the counted IQmath
 * (iqmath_counted: every IQmath operation increments a counter) and, by the
 * CMake target, with gcov instrumentation (line execution counts for the
 * other operations).  The paper motor's identification runs closed loop
 * against the simulator's plant; once the sequence is in ACCELERATE (every
 * block active: PWM on, speed and current loops, RLS updating) the counters
 * are reset and N ISRs are measured, then the gcov counters are dumped and
 * the program exits.
 *
 * Per-module attribution: each step function drive_step() calls is wrapped at
 * link time (-Wl,--wrap=NAME: the call in drive_step.o goes to __wrap_NAME,
 * which snapshots the counters, calls __real_NAME, and adds the difference to
 * NAME's row), so the very code path of the ISR is measured; what is left of
 * the ISR total (drive_step's own glue, and any module not wrapped here) is
 * reported as "drive_step".  Nested calls (the Butterworth filters inside
 * ident_regressor_step) count for their caller.
 *
 * Output (stdout, JSON): {"isrs": N, "iqmath_names": [...],
 *   "total": {"calls": [per operation, summed over N ISRs]},
 *   "max_isr_weighted": W,   (largest per-ISR sum of weights x calls, if
 *                             --weights w0,w1,... is given, in operation order)
 *   "functions": {"NAME": {"calls": C, "iq": [...]}, ...}}
 * Usage: isr_cost CONFIG.ini [--isrs N] [--weights w0,w1,...]
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

typedef struct {
    const char *name;
    uint32_t calls;
    uint64_t iq[N_OPS];
} fn_row_t;

enum {
    F_PHASE_CURRENT, F_DC_BUS, F_QEP_SPEED, F_PROTECT, F_VOLT_CALC, F_CLARKE, F_PARK,
    F_IFO_FRAME, F_IFO_MID, F_IFO_SLIP, F_ANGLE_SINCOS, F_ANGLE_WRAP, F_REGRESSOR, F_RLS,
    F_SEQUENCE, F_RAMP, F_PI_STEP, F_PI_RESET, F_IPARK, F_SVGEN,
    /* issue 8 (orientation 1, adaptation) */
    F_FLUX_OBS, F_ANGLE_STEP, F_TR_TRACK, F_STANDSTILL_Z, F_COUNT
};

static fn_row_t g_rows[F_COUNT] = {
    {"phase_current_step", 0u, {0}}, {"dc_bus_step", 0u, {0}}, {"qep_speed_step", 0u, {0}},
    {"protect_step", 0u, {0}}, {"volt_calc_step", 0u, {0}}, {"clarke_step", 0u, {0}},
    {"park_step", 0u, {0}}, {"ifo_frame_from_rotor", 0u, {0}}, {"ifo_theta_mid", 0u, {0}},
    {"ifo_step_slip", 0u, {0}}, {"angle_sincos", 0u, {0}}, {"angle_wrap_pu", 0u, {0}},
    {"ident_regressor_step", 0u, {0}}, {"rls_step_row", 0u, {0}}, {"id_sequence_step", 0u, {0}},
    {"ramp_gen_step", 0u, {0}}, {"pi_step", 0u, {0}}, {"pi_reset", 0u, {0}},
    {"ipark_step", 0u, {0}}, {"svgen_step", 0u, {0}}, {"flux_obs_step", 0u, {0}},
    {"angle_sincos_step", 0u, {0}}, {"tr_track_step", 0u, {0}}, {"standstill_z_step", 0u, {0}}};

static int g_measuring;
static int g_depth;                /* wrapped calls nest (a module calling angle_*) */
static uint32_t g_snap[N_OPS];

/* Only the outermost wrapped call is recorded: a nested one counts for its
 * caller, so the rows add up to what drive_step() spent in them. */
static void pre(int id)
{
    (void)id;
    if (g_depth++ == 0) {
        memcpy(g_snap, iqmath_call_count, sizeof g_snap);
    }
}

static void post(int id)
{
    int i;
    if (--g_depth != 0 || !g_measuring) {
        return;
    }
    g_rows[id].calls++;
    for (i = 0; i < N_OPS; i++) {
        g_rows[id].iq[i] += (uint64_t)(iqmath_call_count[i] - g_snap[i]);
    }
}

/* the wrappers: same prototypes as the headers (include/) */
#define WRAP_VOID1(NAME, ID, T)                                                                    \
    void __real_##NAME(T a);                                                                       \
    void __wrap_##NAME(T a);                                                                       \
    void __wrap_##NAME(T a) { pre(ID); __real_##NAME(a); post(ID); }

WRAP_VOID1(phase_current_step, F_PHASE_CURRENT, phase_current_t *)
WRAP_VOID1(dc_bus_step, F_DC_BUS, dc_bus_t *)
WRAP_VOID1(qep_speed_step, F_QEP_SPEED, qep_speed_t *)
WRAP_VOID1(protect_step, F_PROTECT, protect_t *)
WRAP_VOID1(volt_calc_step, F_VOLT_CALC, volt_calc_t *)
WRAP_VOID1(clarke_step, F_CLARKE, clarke_t *)
WRAP_VOID1(park_step, F_PARK, park_t *)
WRAP_VOID1(ifo_frame_from_rotor, F_IFO_FRAME, ifo_t *)
WRAP_VOID1(ifo_step_slip, F_IFO_SLIP, ifo_t *)
WRAP_VOID1(ident_regressor_step, F_REGRESSOR, ident_regressor_t *)
WRAP_VOID1(rls_step_row, F_RLS, rls_t *)
WRAP_VOID1(id_sequence_step, F_SEQUENCE, id_sequence_t *)
WRAP_VOID1(ramp_gen_step, F_RAMP, ramp_gen_t *)
WRAP_VOID1(pi_step, F_PI_STEP, pi_ctrl_t *)
WRAP_VOID1(pi_reset, F_PI_RESET, pi_ctrl_t *)
WRAP_VOID1(ipark_step, F_IPARK, ipark_t *)
WRAP_VOID1(svgen_step, F_SVGEN, svgen_t *)
WRAP_VOID1(flux_obs_step, F_FLUX_OBS, flux_obs_t *)
WRAP_VOID1(tr_track_step, F_TR_TRACK, tr_track_t *)
WRAP_VOID1(standstill_z_step, F_STANDSTILL_Z, standstill_z_t *)

_iq __real_ifo_theta_mid(const ifo_t *f);
_iq __wrap_ifo_theta_mid(const ifo_t *f);
_iq __wrap_ifo_theta_mid(const ifo_t *f)
{
    _iq r;
    pre(F_IFO_MID);
    r = __real_ifo_theta_mid(f);
    post(F_IFO_MID);
    return r;
}

_iq __real_angle_wrap_pu(_iq a);
_iq __wrap_angle_wrap_pu(_iq a);
_iq __wrap_angle_wrap_pu(_iq a)
{
    _iq r;
    pre(F_ANGLE_WRAP);
    r = __real_angle_wrap_pu(a);
    post(F_ANGLE_WRAP);
    return r;
}

void __real_angle_sincos(_iq a, _iq *s, _iq *c);
void __wrap_angle_sincos(_iq a, _iq *s, _iq *c);
void __wrap_angle_sincos(_iq a, _iq *s, _iq *c)
{
    pre(F_ANGLE_SINCOS);
    __real_angle_sincos(a, s, c);
    post(F_ANGLE_SINCOS);
}

void __real_angle_sincos_step(_iq s, _iq c, _iq a, _iq d, _iq *s2, _iq *c2);
void __wrap_angle_sincos_step(_iq s, _iq c, _iq a, _iq d, _iq *s2, _iq *c2);
void __wrap_angle_sincos_step(_iq s, _iq c, _iq a, _iq d, _iq *s2, _iq *c2)
{
    pre(F_ANGLE_STEP);
    __real_angle_sincos_step(s, c, a, d, s2, c2);
    post(F_ANGLE_STEP);
}

static void print_vec(const uint64_t *v)
{
    int i;
    printf("[");
    for (i = 0; i < N_OPS; i++) {
        printf("%s%llu", i ? ", " : "", (unsigned long long)v[i]);
    }
    printf("]");
}

int main(int argc, char **argv)
{
    static drive_t drive;
    sim_config_t cfg;
    drive_config_t dc;
    plant_t plant;
    hal_host_port_t port;
    hal_pwm_compare_t active;
    char err[SIM_CONFIG_ERR_LEN];
    double w[N_OPS] = {0};
    double max_w = 0.0;
    uint64_t total[N_OPS] = {0};
    uint32_t n_isr = 3000u, measured = 0u, k;
    int i, a;

    if (argc < 2) {
        fprintf(stderr, "usage: isr_cost CONFIG.ini [--isrs N] [--weights w0,w1,...]\n");
        return 2;
    }
    for (a = 2; a + 1 < argc; a += 2) {
        if (strcmp(argv[a], "--isrs") == 0) {
            n_isr = (uint32_t)strtoul(argv[a + 1], NULL, 10);
        } else if (strcmp(argv[a], "--weights") == 0) {
            char *p = argv[a + 1];
            for (i = 0; i < N_OPS && *p != '\0'; i++) {
                w[i] = strtod(p, &p);
                if (*p == ',') {
                    p++;
                }
            }
        }
    }
    if (sim_config_load(argv[1], &cfg, err, sizeof err) != 0) {
        fprintf(stderr, "isr_cost: %s\n", err);
        return 1;
    }
    sim_config_to_drive(&cfg, &dc);
    if (drive_init(&drive, &dc) != DRIVE_CFG_OK ||
        plant_init(&plant, &cfg, drive.t1pr, err, sizeof err) != 0) {
        fprintf(stderr, "isr_cost: configuration refused\n");
        return 1;
    }
    hal_host_port_init(&port, drive.t1pr);
    hal_host_bind(&port);
    active = port.cmp;
    drive_command(&drive, DRIVE_CMD_START_IDENT);
    drive_background(&drive);

    /* at most 10 s of simulated time to reach ACCELERATE and measure */
    for (k = 0; k < 150000u && measured < n_isr; k++) {
        /* the RLS actually updating (orientation 1 gates it above 0.6 pu) */
        int in_accel = (drive.seq.state == ID_ACCELERATE && drive.rls.enable != 0u);
        if (in_accel && !g_measuring) {
            __gcov_reset();
            g_measuring = 1;
        }
        plant_sample(&plant, &port);
        port.trip_input = 0u;
        iqmath_count_reset();
        drive_isr(&drive);
        if (g_measuring) {
            double s = 0.0;
            for (i = 0; i < N_OPS; i++) {
                total[i] += iqmath_call_count[i];
                s += w[i] * (double)iqmath_call_count[i];
            }
            max_w = (s > max_w) ? s : max_w;
            measured++;
        }
        /* background at 1 kHz, as motor_sim, but not in the measured window:
         * its lines (parameter extraction) are not ISR work and would mix
         * into the gcov counts.  The ISR only finds its live-snapshot mailbox
         * full and skips the copy. */
        if ((k % 15u) == 0u && !g_measuring) {
            drive_background(&drive);
        }
        plant_period(&plant, &active, port.outputs_enabled);
        active = port.cmp;
    }
    __gcov_dump();
    if (measured < n_isr) {
        fprintf(stderr, "isr_cost: ACCELERATE not reached (state %u, fault %u)\n",
                (unsigned)drive.seq.state, (unsigned)drive.prot.fault);
        return 1;
    }
    printf("{\"isrs\": %u, \"iqmath_names\": [", (unsigned)measured);
    for (i = 0; i < N_OPS; i++) {
        printf("%s\"%s\"", i ? ", " : "", iqmath_fn_name(i));
    }
    printf("],\n \"max_isr_weighted\": %.1f,\n \"total\": ", max_w);
    print_vec(total);
    printf(",\n \"functions\": {");
    for (i = 0; i < F_COUNT; i++) {
        printf("%s\n  \"%s\": {\"calls\": %u, \"iq\": ", i ? "," : "", g_rows[i].name,
               (unsigned)g_rows[i].calls);
        print_vec(g_rows[i].iq);
        printf("}");
    }
    printf("}}\n");
    return 0;
}
