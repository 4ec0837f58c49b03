/* Shared helper of the fault-injection tests: one in-process closed-loop run
 * of the paper motor (sim_run, the unchanged drive_isr) with injected faults
 * and timed commands. */
#ifndef FAULT_RUN_H
#define FAULT_RUN_H

#include <stdio.h>
#include <string.h>

#include "sim_config.h"
#include "sim_run.h"

/* The bridge's curve test (ident.vi_test, the default) lengthens CALIBRATE
 * by vi_curve_duration_s: 1.646 s on the paper motor (its acceleration
 * starts at 2.02 s, 0.376 s without it). */
#define FAULT_VI_S 1.65
/* Without faults the paper motor publishes its parameters at 3.12 s
 * (acceleration 2.02-2.72 s): 0.7 s after the curve test is inside the
 * identification, 2.0 s after it is after the publication, 2.5 s after it
 * leave room for both. */
#define FAULT_T_BEFORE (0.7 + FAULT_VI_S)
#define FAULT_T_AFTER (2.0 + FAULT_VI_S)
#define FAULT_RUN_S (2.5 + FAULT_VI_S)

/* One run of `scenario` (fault_run: the start scenario), with the file's
 * sequence (seq < 0) or sim_sequence_t seq. */
static inline int fault_run_scenario(const char *ini, sim_scenario_t scenario, int seq,
                                     const sim_fault_t *faults, unsigned n_faults,
                                     const sim_cmd_t *cmds, unsigned n_cmds, double duration_s,
                                     sim_config_t *cfg, sim_result_t *res)
{
    sim_options_t opt;
    char err[256];
    unsigned i;
    memset(&opt, 0, sizeof opt);
    opt.scenario = scenario;
    opt.quiet = 1u;
    opt.duration_s = duration_s;
    for (i = 0; i < n_faults && i < SIM_MAX_FAULTS; i++) {
        opt.faults[i] = faults[i];
    }
    opt.n_faults = (uint16_t)i;
    for (i = 0; i < n_cmds && i < SIM_MAX_CMDS; i++) {
        opt.cmds[i] = cmds[i];
    }
    opt.n_cmds = (uint16_t)i;
    if (sim_config_load(ini, cfg, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    if (seq >= 0) {
        sim_config_set_sequence(cfg, (sim_sequence_t)seq);
    }
    if (sim_run(cfg, &opt, res, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    return 0;
}

static inline int fault_run(const char *ini, const sim_fault_t *faults, unsigned n_faults,
                     const sim_cmd_t *cmds, unsigned n_cmds, double duration_s,
                     sim_config_t *cfg, sim_result_t *res)
{
    return fault_run_scenario(ini, SCEN_START, -1, faults, n_faults, cmds, n_cmds, duration_s,
                              cfg, res);
}

#endif
