#!/usr/bin/env python3
"""Mutation testing of the firmware core (src/, include/) against the CTest
suite of the host-iq build.  Run by hand (about 20 minutes with --jobs 2 on two cores: 1 101 s for 52), not in CI.

    tools/mutate.py --list                       the mutants: name, file, why
    tools/mutate.py [--only A,B] [--jobs N]      run them (default: all, one job)
                    [--phase1 LABELS] [--phase2 LABELS] [--no-phase2]
                    [--mutant-timeout S] [--preset host-iq|host-float|host-asan]
                    [--keep] [--report FILE]

Each mutant is one edit of one source file: a snippet that occurs exactly
once in it, its replacement, and why the behaviour it breaks matters.  A
mutant is applied to a scratch copy of the tree (the repository's tracked and
untracked, not ignored, files copied to /tmp/mutate-*; the working tree is
never touched), the copy's host-iq build is brought up to date (only the
mutated file and what includes it recompile), and CTest runs in two phases,
each stopping at the first failing test:

  phase 1: every test except the long ones (ctest -LE 'closed_loop|soak|ubsan'):
           unit, config, CLI, fault, target, fuzz-corpus tests, ~2 min;
  phase 2: the closed-loop and soak tests (ctest -L 'closed_loop|soak'), run
           only for a mutant phase 1 did not kill, ~10 min.

A mutant is KILLED when a test fails (the first failing test is named), when
the build or the tests exceed --mutant-timeout (a hang: 'timeout'), SURVIVED
when both phases pass, STILLBORN when it does not compile (left out of the
score), STALE when its snippet is not exactly once in its file (the code
moved on: fix the list).  The score is killed / (killed + survived).  The
unmutated copy is built and phase 1 run once first: a failing baseline stops
the run.

--preset: the build the mutants are tested in (default host-iq; host-asan
adds ASan + UBSan, which kills a mutant whose only effect is undefined
behaviour, e.g. a float converted to an integer beyond its range).
--jobs N: N scratch copies, each with its own build, each taking the next
mutant (the machine's cores are shared: on 2 cores use --jobs 1 or 2).
The report (default out/mutation/report.md) lists every mutant with its
status, the killing test and the time; a survivor is a missing test or an
equivalent mutant, said in the report.
"""
from __future__ import annotations

import argparse
import concurrent.futures
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PHASE1 = ("-LE", "closed_loop|soak|ubsan")
PHASE2 = ("-L", "closed_loop|soak")


@dataclass
class Mutant:
    name: str
    file: str          # relative to the repository root
    original: str      # occurs exactly once in file
    replacement: str
    why: str


M = Mutant
MUTANTS = [
    # ---- the known survivors of the earlier suite ---------------------------
    M("publish_ignores_valid", "src/app/drive_background.c",
      "    if (end->valid == 0u) {\n        return DRIVE_PUB_IMPLAUSIBLE;",
      "    if (end->valid == 0xFFFFu) {\n        return DRIVE_PUB_IMPLAUSIBLE;",
      "the published-set gate (judge_rls): an implausible extraction (a +100 % sensor gain "
      "error) would not be refused as implausible and could be published"),
    M("overcurrent_phase_c_removed", "include/protect.h",
      "protect_over(p, p->ic) | (uint16_t)(p->vdc > p->vdc_max);",
      "(uint16_t)(p->vdc > p->vdc_max);",
      "phase c (computed from a and b) is the only phase that sees a fault current "
      "between a and b returning through c"),
    M("current_check_tau_4ms", "src/app/drive_init.c",
      "fmaxf(0.002f, g.Ts_slow)", "fmaxf(0.004f, g.Ts_slow)",
      "the current-feedback check's 2 ms low-pass: twice slower detection of a lost sensor"),
    M("modulation_advance_1p0", "src/app/drive_init.c",
      "_IQ(1.5f * d->base.f_base_Hz * Ts)", "_IQ(1.0f * d->base.f_base_Hz * Ts)",
      "the inverse Park at the middle of the next period (1.5 periods after the sample): "
      "a voltage angle error of w Ts / 2"),
    M("tracker_guard_1pct", "src/app/drive_adapt.h",
      "#define TRACK_PHI_MIN_OF_RATED 0.1f", "#define TRACK_PHI_MIN_OF_RATED 0.01f",
      "the Rr tracker's wind-up guard: at 1 % it learns from noise at no load"),
    M("pass_rate_limit_x4", "src/app/drive_adapt_bg.c",
      "    _iq lo = _IQmpy(ref, _IQ(0.5));   /* any Q times Q24 0.5: the same Q */\n"
      "    _iq hi = (ref < top - ref) ? ref + ref : top;",
      "    _iq lo = _IQmpy(ref, _IQ(0.25));   /* any Q times Q24 0.5: the same Q */\n"
      "    _iq hi = (ref < _IQmpy(top, _IQ(0.25))) ? ref * 4 : top;",
      "the model handed from pass to pass moves at most a factor 2 (a bad pass cannot "
      "throw the observer off)"),
    # ---- protections ---------------------------------------------------------
    M("overvoltage_threshold_raised", "include/protect.h",
      "| (uint16_t)(p->vdc > p->vdc_max);", "| (uint16_t)(p->vdc > p->vdc_max + _IQ(0.5));",
      "the bus overvoltage trip 0.5 pu (17 V) too high"),
    M("undervoltage_only_at_clear", "include/protect.h",
      "const uint16_t uv = (uint16_t)((p->pwm_on | strict) != 0u) &",
      "const uint16_t uv = (uint16_t)(strict != 0u) &",
      "the undervoltage trip while the bridge switches"),
    M("hw_trip_ignored", "include/protect.h",
      "(uint16_t)(p->hw_trip | p->adc_rail | p->encoder_fault |",
      "(uint16_t)(p->adc_rail | p->encoder_fault |",
      "PDPINTA (the power stage tripped itself) latches no fault"),
    M("clear_not_strict", "src/app/protect.c",
      "if (protect_check(p, 1u) != FAULT_NONE) {", "if (protect_check(p, 0u) != FAULT_NONE) {",
      "a reset onto a bus still below its minimum (bridge off) is accepted"),
    M("latch_overwrites", "include/protect.h",
      "if (p->fault == FAULT_NONE && code != FAULT_NONE) {", "if (code != FAULT_NONE) {",
      "the first fault is the one latched and reported; a later one must not replace it"),
    M("overvoltage_after_rail", "include/protect.h",
      "    if (p->vdc > p->vdc_max) {\n        return FAULT_BUS_OVERVOLTAGE;\n    }\n"
      "    if (p->adc_rail != 0u) {\n        return FAULT_ADC_RAIL;\n    }",
      "    if (p->adc_rail != 0u) {\n        return FAULT_ADC_RAIL;\n    }\n"
      "    if (p->vdc > p->vdc_max) {\n        return FAULT_BUS_OVERVOLTAGE;\n    }",
      "a bus beyond its sensor's range (reading at the rail) is an overvoltage"),
    M("current_check_threshold_doubled", "include/current_check.h",
      "if (c->e_f > c->e_max) {", "if (c->e_f > c->e_max + c->e_max) {",
      "the current-feedback check trips at twice its error limit"),
    M("encoder_jump_check_off", "include/encoder_check.h",
      "const int32_t jm = e->jump_max;",
      "const int32_t jm = e->jump_max + e->jump_max;",
      "an implausible encoder step (noise on A/B) trips at twice its limit"),
    M("encoder_frozen_off_by_one", "include/encoder_check.h",
      "    if (e->frozen >= e->frozen_max) {\n        e->fault = 1u;",
      "    if (e->frozen > e->frozen_max) {\n        e->fault = 1u;",
      "the frozen-count test never trips (frozen saturates at frozen_max)"),
    M("calibration_window_widened", "src/sense/phase_current.c",
      "if (dev > (int32_t)window || dev < -(int32_t)window) {",
      "if (dev > 2 * (int32_t)window || dev < -2 * (int32_t)window) {",
      "a current-sensor offset outside its window passes the calibration"),
    M("bottom_rail_missed", "include/phase_current.h",
      "const uint16_t a = (uint16_t)((uint16_t)(a_raw - 1u) >= (uint16_t)(PHASE_CURRENT_RAIL_HIGH - 1u));",
      "const uint16_t a = (uint16_t)(a_raw >= PHASE_CURRENT_RAIL_HIGH);",
      "a phase-a reading at the bottom rail is not flagged"),
    M("bus_rail_missed", "include/dc_bus.h",
      "d->rail = (uint16_t)(d->vdc_raw >= DC_BUS_RAIL_HIGH);",
      "d->rail = (uint16_t)(d->vdc_raw > DC_BUS_RAIL_HIGH);",
      "the bus reading at its top code (0xFFF0) is not flagged as clipped"),
    # ---- the command handling -----------------------------------------------
    M("start_wins_over_stop", "src/app/drive_background.c",
      "    } else if ((req & DRIVE_CMD_BIT(DRIVE_CMD_START_IDENT)) != 0u) {",
      "    }\n    if ((req & DRIVE_CMD_BIT(DRIVE_CMD_START_IDENT)) != 0u) {",
      "a stop and a start in the same period: the stop must win"),
    M("command_slot_overwrites", "src/app/drive_background.c",
      "d->cmd_requests = (uint16_t)(d->cmd_requests | DRIVE_CMD_BIT(cmd));",
      "d->cmd_requests = DRIVE_CMD_BIT(cmd);",
      "commands from two sources in one period: the second replaced the first"),
    # ---- control ------------------------------------------------------------
    M("pi_antiwindup_removed", "include/pi_ctrl.h",
      "const _iq upper = _IQsat(ui_hi, out_max, ui0);",
      "const _iq upper = _IQsat(out_max, out_max, ui_hi);",
      "the integrator winds up (upward) while the output is saturated"),
    M("pi_output_unsaturated", "include/pi_ctrl.h",
      "p->out = _IQsat(v, out_max, out_min);", "p->out = v;",
      "the controller's output beyond its limits"),
    M("pi_sat_flag_upper_only", "include/pi_ctrl.h",
      "p->sat = (uint16_t)((v >= out_max) | (v <= out_min));",
      "p->sat = (uint16_t)(v >= out_max);",
      "saturation at the lower limit not reported"),
    M("pi_error_sign", "include/pi_ctrl.h",
      "const _iq e = p->ref - fbk;", "const _iq e = fbk - p->ref;",
      "positive feedback"),
    M("park_q_sign", "include/park.h",
      "p->qs = _IQmpy(beta, c) - _IQmpy(alpha, s);",
      "p->qs = _IQmpy(beta, c) + _IQmpy(alpha, s);",
      "the q current of the wrong rotation"),
    M("ipark_alpha_sign", "include/ipark.h",
      "*alpha = _IQmpy(ds, cosine) - _IQmpy(qs, sine);",
      "*alpha = _IQmpy(ds, cosine) + _IQmpy(qs, sine);",
      "the voltage vector of the wrong rotation"),
    M("svgen_duty_unclamped", "src/foc/svgen.c",
      "s->da = _IQsat(_IQ(0.5) + _IQmpy(va - mid, inv), _IQ(1.0), _IQ(0.0));",
      "s->da = _IQ(0.5) + _IQmpy(va - mid, inv) + 1;",
      "a duty beyond [0, 1] (one LSB over at full modulation): a compare beyond T1PR"),
    M("ramp_target_unclamped", "src/common/ramp_gen.c",
      "_iq tgt = ramp_clamp(r->target, r->out_min, r->out_max);", "_iq tgt = r->target;",
      "the speed reference beyond its +-2 pu range"),
    M("ramp_step_doubled_down", "src/common/ramp_gen.c",
      "        r->out -= r->step;", "        r->out -= r->step + r->step;",
      "the deceleration ramp twice the configured rate"),
    # ---- sensing ------------------------------------------------------------
    M("qep_speed_unfiltered", "src/sense/qep_speed.c",
      "q->speed += _IQrmpy(q->k_filt, q->speed_raw - q->speed);", "q->speed = q->speed_raw;",
      "the measured speed without its low-pass"),
    M("qep_window_saturation_removed", "src/sense/qep_speed.c",
      "    if (dw > q->d_max) {\n        dw = q->d_max;", "    if (dw > q->d_max + q->d_max) {\n        dw = q->d_max;",
      "a window count above d_max converted: the speed beyond its Q24 bound"),
    M("qep_dir_zero_is_forward", "src/sense/qep_speed.c",
      "q->dir = (int16_t)((dw > 0) ? 1 : ((dw < 0) ? -1 : 0));",
      "q->dir = (int16_t)((dw >= 0) ? 1 : ((dw < 0) ? -1 : 0));",
      "a motor at standstill reported as turning forward"),
    M("dc_bus_filter_bypassed", "include/dc_bus.h",
      "d->vdc_filt += _IQrmpy(d->k_filt, d->vdc - d->vdc_filt);", "d->vdc_filt = d->vdc;",
      "the bus's filtered value (the SVPWM's divider) unfiltered"),
    # ---- orientation ----------------------------------------------------------
    M("ifo_flux_lag_removed", "include/ifo.h",
      "f->imr = imr + iq_rmpy(f->kf, i_m - imr);", "f->imr = i_m + (imr - imr);",
      "the rotor flux follows i_M without its Tr lag: a slip too large in every transient"),
    M("ifo_slip_sign", "include/ifo.h",
      "    f->ws = wr + wslip;\n    /* Q24 * Q30",
      "    f->ws = wr - wslip;\n    /* Q24 * Q30",
      "the frame speed with the slip of the wrong sign (generating instead of motoring)"),
    M("flux_obs_ws_unfiltered", "src/orient/flux_obs.c",
      "o->ws_f += _IQrmpy(o->kf_ws, o->ws - o->ws_f);", "o->ws_f = o->ws;",
      "the observer's frame speed without its 200 Hz low-pass (the angle step's noise)"),
    M("flux_obs_lr_limit_off", "src/orient/flux_obs.c",
      "    if (!(lr_pu > lm_pu && lr_pu <= FLUX_OBS_LR_LM_MAX * lm_pu)) {",
      "    if (!(lr_pu > lm_pu && lr_pu <= 2.0f * FLUX_OBS_LR_LM_MAX * lm_pu)) {",
      "an Lr up to 8 Lm accepted: Lr/Lm beyond the observer's Q24 budget "
      "(|Lr/Lm (psi_s - sigma Ls i)| <= 96), by flux_obs_init and the table alike"),
    M("flux_obs_correction_sign", "src/orient/flux_obs.c",
      "    zn = sat_sym(*z + iq_rmpy(o->g, e), Z_MAX, sat);",
      "    zn = sat_sym(*z - iq_rmpy(o->g, e), Z_MAX, sat);",
      "the observer's voltage-model correction integrates the wrong way"),
    # ---- voltage reconstruction ------------------------------------------------
    M("deadtime_comp_sign_a", "include/volt_calc.h",
      "        pa -= volt_calc_leg_error(th, nth, inv_th, ia, dia_h, da, volt_calc_leg_e(da, e_sw, e_cl));",
      "        pa += volt_calc_leg_error(th, nth, inv_th, ia, dia_h, da, volt_calc_leg_e(da, e_sw, e_cl));",
      "phase a's dead-time voltage added instead of subtracted"),
    # ---- identification ---------------------------------------------------------
    M("settle_speed_test_inverted", "src/app/id_sequence.c",
      "        if (s->speed_err >= s->speed_tol) {\n            s->t_steady = 0u;",
      "        if (s->speed_err < s->speed_tol) {\n            s->t_steady = 0u;",
      "steady state recognised while the speed is off (the hold window counts the samples "
      "with the speed error at or above its tolerance)"),
    M("settle_timeout_ignored", "src/app/id_sequence.c",
      "        } else if (s->t_state >= s->settle_max_samples) {",
      "        } else if (s->t_state >= s->settle_max_samples + s->settle_max_samples) {",
      "the SETTLE time limit doubled"),
    M("rls_tail_off_by_one", "src/app/id_sequence.c",
      "s->rls_on = (uint16_t)(s->t_state <= s->rls_tail_samples);",
      "s->rls_on = (uint16_t)(s->t_state < 1u);",
      "the RLS stops at the end of the ramp: the tail that catches the end-of-ramp transient "
      "is lost"),
    M("magnetize_exit_early", "src/app/id_sequence.c",
      "        if (s->t_state >= s->magnetize_samples) {",
      "        if (s->t_state + s->t_state >= s->magnetize_samples) {",
      "the magnetisation half as long (2.5 Tr instead of 5)"),
    M("extract_range_ignored_rr", "src/estim/param_extract.c",
      "    pe_check(p->Rr, p->Rr_lim, PARAM_ERR_RR, &st);\n", "",
      "an Rr outside its plausibility range published"),
    M("extract_range_bound_flip", "src/estim/param_extract.c",
      "if (*st == PARAM_OK && (v < lim[0] || v > lim[1])) {",
      "if (*st == PARAM_OK && (v < lim[0] && v > lim[1])) {",
      "no parameter is ever outside its range"),
    M("guard_plausible_flip", "src/estim/theta_guard.c",
      "if (m < g->lo[i] || m > g->hi[i]) {", "if (m < g->lo[i] && m > g->hi[i]) {",
      "the estimator guard accepts every estimate"),
    M("tracker_guard_inverted", "src/estim/tr_track.c",
      "if (_IQabs(phi) < t->phi_min) {", "if (_IQabs(phi) > t->phi_min) {",
      "the tracker learns only without excitation"),
    M("tracker_p_floor_removed", "src/estim/tr_track.c",
      "    } else if (t->p < P_MIN) {\n        t->p = P_MIN;",
      "    } else if (t->p < 0) {\n        t->p = P_MIN;",
      "the tracker's covariance may shrink to 0 (it stops following drift)"),
    M("standstill_phasor_sign", "src/estim/standstill_z.c",
      "num_x = _IQmpy(z->uc, z->is) - _IQmpy(z->us, z->ic);",
      "num_x = _IQmpy(z->uc, z->is) + _IQmpy(z->us, z->ic);",
      "the standstill sigma Ls from the wrong quadrature"),
    M("regressor_row1_sign", "src/estim/ident_regressor.c",
      "r->y1 = r->f_im.dy - r->f_ws_it.y;", "r->y1 = r->f_im.dy + r->f_ws_it.y;",
      "row 1 of the regression (method eq. 5) with the cross-coupling of the wrong sign"),
    # ---- configuration limits ---------------------------------------------------
    M("dead_time_loss_40pct", "src/app/drive_limits.c",
      "#define HEADROOM_LOSS_OF_VOLTAGE 0.3f", "#define HEADROOM_LOSS_OF_VOLTAGE 0.4f",
      "a dead-time loss of 40 % of the motor's voltage at the target accepted (8 us on the "
      "paper motor: Tr -5 %)"),
    M("target_floor_10pct", "src/app/drive_target.c",
      "#define TARGET_MIN_OF_RATED 0.2f", "#define TARGET_MIN_OF_RATED 0.1f",
      "a target speed below what the RLS's excitation needs accepted"),
    M("tr_limit_off", "src/app/drive_limits.c",
      "        return verdict((int16_t)(ifo_q20(x, st, imr, tr_pu) != IFO_ERR_TR), f, x->g.tr,",
      "        return verdict((int16_t)(ifo_q20(x, st, imr, tr_pu) != IFO_ERR_IMR_MIN), f, x->g.tr,",
      "a believed Tr beyond what ifo and the observer accept (Q20 time base) accepted by the table "
      "(its Tr entry reading the wrong one of ifo's verdicts)"),
]


def find_mutant(name):
    for m in MUTANTS:
        if m.name == name:
            return m
    raise SystemExit(f"mutate.py: no mutant '{name}' (--list names them)")


def check_mutant(m):
    """'ok', or why the mutant cannot be applied to the present tree."""
    path = ROOT / m.file
    if not path.exists():
        return f"{m.file} does not exist"
    n = path.read_text().count(m.original)
    if n != 1:
        return f"its snippet occurs {n} times in {m.file} (must be once)"
    return "ok"


def tracked_files():
    out = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT,
                         check=True, capture_output=True).stdout
    return [f for f in out.decode().split("\0") if f]


def log(lock, msg):
    with lock:
        print(msg, flush=True)


def run(cmd, cwd, timeout, env=None):
    """(returncode, output); returncode None on timeout (the process group killed)."""
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, start_new_session=True, env=env)
    try:
        out, _ = p.communicate(timeout=timeout)
        return p.returncode, out
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        return None, out


FAILED_RE = re.compile(r"^\s*\d+/\d+ Test\s+#\d+: (\S+) \.*\s*\*\*\*(Failed|Timeout|Exception.*)", re.M)
NOT_RUN_RE = re.compile(r"^\s*\d+/\d+ Test\s+#\d+: (\S+) \.*\s*\*\*\*Not Run", re.M)


class Scratch:
    """One copy of the tree with its own host-iq build."""

    def __init__(self, index, files, build_jobs, lock, preset):
        self.dir = Path(tempfile.mkdtemp(prefix=f"mutate-{os.getpid()}-{index}-"))
        self.lock = lock
        self.build_jobs = build_jobs
        for f in files:
            src = ROOT / f
            if not src.is_file():
                continue
            dst = self.dir / f
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
        self.preset = preset
        self.build = self.dir / "build" / preset

    def configure_and_build(self, timeout):
        rc, out = run(["cmake", "--preset", self.preset], self.dir, timeout)
        if rc != 0:
            return False, out
        rc, out = run(["cmake", "--build", "--preset", self.preset, f"-j{self.build_jobs}"],
                      self.dir, timeout)
        return rc == 0, out

    def ctest(self, phase, timeout):
        env = dict(os.environ, CTEST_OUTPUT_ON_FAILURE="0",
                   ASAN_OPTIONS="detect_leaks=1:abort_on_error=1",
                   UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
        cmd = ["ctest", "--test-dir", str(self.build), "--stop-on-failure", "-j1", *phase]
        return run(cmd, self.dir, timeout, env)


def apply_and_test(scratch, m, args, deadline_s):
    """(status, killer, seconds) of one mutant on one scratch copy."""
    t0 = time.time()
    path = scratch.dir / m.file
    text = path.read_text()
    if text.count(m.original) != 1:
        return "stale", "", 0.0
    path.write_text(text.replace(m.original, m.replacement, 1))
    try:
        left = lambda: max(1.0, deadline_s - (time.time() - t0))
        rc, out = run(["cmake", "--build", str(scratch.build), f"-j{scratch.build_jobs}"],
                      scratch.dir, left())
        if rc is None:
            return "killed", "timeout (build)", time.time() - t0
        if rc != 0:
            return "stillborn", "does not compile", time.time() - t0
        phases = [args.phase1] + ([] if args.no_phase2 else [args.phase2])
        for ph in phases:
            rc, out = scratch.ctest(ph, left())
            if rc is None:
                return "killed", f"timeout ({' '.join(ph)})", time.time() - t0
            if rc != 0:
                f = FAILED_RE.search(out) or NOT_RUN_RE.search(out)
                return "killed", (f.group(1) if f else "ctest status %d" % rc), time.time() - t0
        return "survived", "", time.time() - t0
    finally:
        path.write_text(text)   # restored; the next build recompiles it


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--only", help="comma-separated mutant names")
    ap.add_argument("--jobs", type=int, default=1, help="scratch copies working in parallel")
    ap.add_argument("--phase1", default=None,
                    help="ctest label filter of phase 1, e.g. '-L unit' (default: -LE "
                         "'closed_loop|soak|ubsan')")
    ap.add_argument("--phase2", default=None,
                    help="ctest label filter of phase 2 (default: -L 'closed_loop|soak')")
    ap.add_argument("--no-phase2", action="store_true", help="phase 1 only (faster, weaker)")
    ap.add_argument("--mutant-timeout", type=float, default=2400.0,
                    help="seconds for one mutant's build and tests (default 2400)")
    ap.add_argument("--preset", default="host-iq", choices=("host-iq", "host-float", "host-asan"),
                    help="the build the mutants are tested in (default host-iq)")
    ap.add_argument("--keep", action="store_true", help="keep the scratch copies")
    ap.add_argument("--report", default=str(ROOT / "out" / "mutation" / "report.md"))
    args = ap.parse_args(argv)
    args.phase1 = tuple(args.phase1.split(None, 1)) if args.phase1 else PHASE1
    args.phase2 = tuple(args.phase2.split(None, 1)) if args.phase2 else PHASE2

    if args.list:
        for m in MUTANTS:
            state = check_mutant(m)
            print(f"{m.name:34s} {m.file:32s} {m.why}" + ("" if state == "ok" else
                                                          f"  [STALE: {state}]"))
        print(f"{len(MUTANTS)} mutants")
        return 0
    todo = [find_mutant(n) for n in args.only.split(",")] if args.only else list(MUTANTS)
    if args.jobs < 1:
        raise SystemExit("mutate.py: --jobs must be at least 1")
    jobs = min(args.jobs, len(todo))
    build_jobs = 2 if jobs == 1 else 1
    lock = threading.Lock()
    results = {}
    stale = [(m, check_mutant(m)) for m in todo if check_mutant(m) != "ok"]
    for m, why in stale:
        results[m.name] = ("stale", why, 0.0)
    todo = [m for m in todo if m.name not in results]

    files = tracked_files()
    log(lock, f"mutate.py: {len(todo)} mutants, {jobs} scratch copies, {args.preset}, phase 1 ctest "
              f"{' '.join(args.phase1)}" + ("" if args.no_phase2 else
                                            f", phase 2 ctest {' '.join(args.phase2)}"))
    scratches = [Scratch(i, files, build_jobs, lock, args.preset) for i in range(jobs)]
    t_start = time.time()
    try:
        for s in scratches:
            ok, out = s.configure_and_build(3600)
            if not ok:
                sys.stderr.write(out[-4000:])
                raise SystemExit(f"mutate.py: the unmutated copy in {s.dir} does not build")
        rc, out = scratches[0].ctest(args.phase1, 3600)
        if rc != 0:
            sys.stderr.write(out[-4000:])
            raise SystemExit("mutate.py: phase 1 fails on the unmutated tree: fix that first")
        log(lock, f"baseline: built and phase 1 passes ({time.time() - t_start:.0f} s)")

        queue = list(todo)
        qlock = threading.Lock()

        def worker(s):
            while True:
                with qlock:
                    if not queue:
                        return
                    m = queue.pop(0)
                st, killer, secs = apply_and_test(s, m, args, args.mutant_timeout)
                results[m.name] = (st, killer, secs)
                log(lock, f"  {m.name:34s} {st:9s} {killer}  ({secs:.0f} s)")

        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
            list(ex.map(worker, scratches))
    finally:
        if not args.keep:
            for s in scratches:
                shutil.rmtree(s.dir, ignore_errors=True)

    killed = [n for n, r in results.items() if r[0] == "killed"]
    survived = [n for n, r in results.items() if r[0] == "survived"]
    score = 100.0 * len(killed) / max(1, len(killed) + len(survived))
    lines = [f"# Mutation testing ({time.strftime('%Y-%m-%d')})", "",
             f"{len(killed)} killed, {len(survived)} survived, "
             f"{sum(r[0] == 'stillborn' for r in results.values())} stillborn, "
             f"{sum(r[0] == 'stale' for r in results.values())} stale; "
             f"score {score:.1f} % (killed / (killed + survived)); "
             f"{args.preset}; phase 1 ctest {' '.join(args.phase1)}"
             + ("" if args.no_phase2 else f", phase 2 ctest {' '.join(args.phase2)}")
             + f"; {time.time() - t_start:.0f} s", "",
             "| mutant | file | status | killed by | s | why it matters |", "|---|---|---|---|---|---|"]
    for m in MUTANTS:
        if m.name in results:
            st, killer, secs = results[m.name]
            lines.append(f"| {m.name} | {m.file} | {st} | {killer} | {secs:.0f} | {m.why} |")
    report = Path(args.report)
    report.parent.mkdir(parents=True, exist_ok=True)
    report.write_text("\n".join(lines) + "\n")
    print("\n".join(lines[:3]))
    print(f"report: {report}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
