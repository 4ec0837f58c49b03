#!/usr/bin/env python3
"""Co-simulation of the portable core on a 16-bit-int target (check 4b).

Compiles ALL of src/ and host_sim/iqmath/ (every .c found, so new modules
are picked up without edits) plus a harness from tests/target/avr/:

  * with avr-gcc for an ATmega2560 (16-bit int, 32-bit double) with the
    project's strict warnings and -Werror, and runs it on simavr;
  * with the host gcc (IQ_MATH, -fsanitize=undefined) from the same files;

then compares the two outputs line by line.

Honesty of the comparison:
  * avr-gcc's double is 32 bits, so a non-dyadic literal in _IQ()/_IQN() is
    rounded to float before scaling.  The host reference is built with
    -fsingle-precision-constant so that both sides see the same literal
    values; the fixed-point arithmetic itself (what 16-bit int can break) is
    then compared bit for bit.  (On the C28x, TI's _IQN() scales in 64-bit
    long double, as the host's native build does.)
  * *_init functions compute in float, where avr-libc and glibc expf differ
    in the last bit (measured); both builds link one shared expf
    (tests/target/avr/cosim_libm.c) so that the init constants are equal.
    Harness lines tagged 'I' carry init results and are reported as INIT
    mismatches, separately from the fixed-point step outputs (tags 'S',
    'T'); both make the check fail.

Exit status: 0 identical, 1 mismatch, 2 build or run error.
"""
import argparse
import concurrent.futures
import os
import re
import subprocess
import sys

STRICT = ["-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wsign-conversion",
          "-Wshadow", "-Wstrict-prototypes", "-Wmissing-prototypes", "-Wundef",
          "-Wdouble-promotion", "-Werror"]
# the RLS queue (drive_types.h) at 4 entries: the harnesses run the
# background every 15 steps (2 entries at most); the limits' names off
# (drive_limits.h: avr-gcc keeps every constant in RAM, and the 8 KB of the
# atmega2560 must hold drive_t, the tables and the stack); the period-mean
# regression's filters and state out (ident_regressor.h: 194 bytes; with them
# the stack met .bss and the harness never ended)
DEFS = ["-DMATH_TYPE=IQ_MATH", "-DGLOBAL_Q=24", "-DDRIVE_RLSQ_LEN=4u", "-DDRIVE_LIMITS_NAMES=0",
        "-DIDENT_PERIOD_MEAN=0"]


def sources(root, dirs):
    """Every C source under the given folders (default: all of src/ and the
    host IQmath)."""
    out = []
    for base in dirs:
        for d, dirs, files in os.walk(os.path.join(root, base)):
            dirs[:] = [x for x in dirs if x not in ("tools", "test", "tests")]
            out += [os.path.join(d, f) for f in sorted(files) if f.endswith(".c")]
    return sorted(out)


def run(cmd, **kw):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    return p.returncode, p.stdout, p.stderr


def build(cc, flags, srcs, objdir, exe, link_flags, jobs):
    os.makedirs(objdir, exist_ok=True)

    def one(src):
        obj = os.path.join(objdir, re.sub(r"[^A-Za-z0-9_.]", "_", os.path.relpath(src)) + ".o")
        rc, _, err = run([cc] + flags + ["-c", src, "-o", obj])
        return src, obj, rc, err

    objs, failed = [], []
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        for src, obj, rc, err in ex.map(one, srcs):
            objs.append(obj)
            if rc != 0:
                failed.append((src, err))
    if failed:
        for src, err in failed:
            print("COMPILE ERROR (%s) %s\n%s" % (cc, src, err))
        return False
    rc, _, err = run([cc] + flags + objs + ["-o", exe] + link_flags)
    if rc != 0:
        print("LINK ERROR (%s)\n%s" % (cc, err))
        return False
    return True


ANSI = re.compile(r"\x1b\[[0-9;]*m")


def simavr_lines(text):
    """simavr prints the UART output on stderr, one colored line per '\\n'
    (shown as a trailing '.')."""
    out = []
    for raw in text.splitlines():
        line = ANSI.sub("", raw).rstrip()
        if line.endswith("."):
            line = line[:-1]
        if re.match(r"^(I|S|T) [0-9A-F]{8}( |$)|^END$", line):
            out.append(line)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--harness", required=True, help="tests/target/avr/<harness>.c")
    ap.add_argument("--extra", action="append", default=[], help="extra source (both builds)")
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--mcu", default="atmega2560")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--dirs", nargs="+", default=["src", "host_sim/iqmath"],
                    help="source folders compiled into the image (relative to --root)")
    a = ap.parse_args()

    root = os.path.abspath(a.root)
    name = os.path.splitext(os.path.basename(a.harness))[0]
    inc = ["-I" + os.path.join(root, "include"), "-I" + os.path.join(root, "host_sim", "iqmath"),
           "-I" + os.path.join(root, "tests", "target", "avr"), "-I" + os.path.join(root, "firmware")]
    core = sources(root, a.dirs)
    srcs = core + [os.path.abspath(a.harness),
                   os.path.join(root, "tests", "target", "avr", "cosim_io.c"),
                   os.path.join(root, "tests", "target", "avr", "cosim_libm.c")]
    srcs += [os.path.abspath(x) for x in a.extra]
    print("core sources: %d from %s" % (len(core), " ".join(a.dirs)))

    avr_exe = os.path.join(a.workdir, name + ".elf")
    host_exe = os.path.join(a.workdir, name + ".host")
    # -Wdouble-promotion is dropped for avr-gcc only: avr-libc maps expf,
    # fabsf, ... to the double functions and double is float there, so the
    # warning fires on float-only expressions (the host build keeps it).
    avr_strict = [f for f in STRICT if f != "-Wdouble-promotion"]
    # no built-in exp: both sides call cosim_libm.c's (see there)
    nobuiltin = ["-fno-builtin-exp", "-fno-builtin-expf"]
    # each function and object in its own section, the unused ones dropped
    # at the link (--gc-sections): the 8 KB of atmega2560 RAM hold drive_t
    # and what the harness really uses, not every table of the core
    avr_flags = (["-mmcu=" + a.mcu, "-Os", "-ffunction-sections", "-fdata-sections"] + nobuiltin
                 + avr_strict + DEFS + inc)
    host_flags = ["-O1"] + nobuiltin + ["-fsingle-precision-constant", "-fsanitize=undefined",
                  "-fno-sanitize-recover=all"] + STRICT + DEFS + inc
    if not build("avr-gcc", avr_flags, srcs, os.path.join(a.workdir, name + "_avr"), avr_exe,
                 ["-lm", "-Wl,--gc-sections"], a.jobs):
        return 2
    if not build("gcc", host_flags, srcs, os.path.join(a.workdir, name + "_host"), host_exe,
                 ["-lm", "-fsanitize=undefined"], a.jobs):
        return 2

    rc, out, err = run(["simavr", "-m", a.mcu, "-f", "16000000", avr_exe], timeout=240)
    avr = simavr_lines(err)
    if rc != 0 or not avr or avr[-1] != "END":
        print("SIMAVR RUN FAILED (rc %d, %d lines, last %r)\n%s" % (rc, len(avr), avr[-1:] , err[-2000:]))
        return 2
    rc, out, err = run([host_exe], timeout=120)
    host = [l for l in out.splitlines() if l]
    if rc != 0 or not host or host[-1] != "END":
        print("HOST RUN FAILED (rc %d)\n%s" % (rc, err[-2000:]))
        return 2

    print("lines: host %d, avr %d" % (len(host), len(avr)))
    init_bad = [(h, v) for h, v in zip(host, avr) if h.startswith("I") and h != v]
    step_bad = [(i, h, v) for i, (h, v) in enumerate(zip(host, avr)) if not h.startswith("I") and h != v]
    for h, v in init_bad[:5]:
        print("INIT MISMATCH (float init: avr-libc vs glibc)\n  host: %s\n  avr:  %s" % (h, v))
    for i, h, v in step_bad[:10]:
        print("STEP MISMATCH at line %d\n  host: %s\n  avr:  %s" % (i, h, v))
    if len(host) != len(avr):
        print("LENGTH MISMATCH: host %d lines, avr %d lines" % (len(host), len(avr)))
    if init_bad or step_bad or len(host) != len(avr):
        print("FAIL: %d init and %d step lines differ" % (len(init_bad), len(step_bad)))
        return 1
    steps = sum(1 for l in host if l.startswith("S"))
    print("PASS: %d init lines and %d steps bit-identical on host and %s" %
          (sum(1 for l in host if l.startswith("I")), steps, a.mcu))
    return 0


if __name__ == "__main__":
    sys.exit(main())
