#!/usr/bin/env python3
"""How many C28x words a Thumb-2 halfword of the stand-in compile is worth,
measured on C code that TI compiled for the C28x: C2000Ware's driverlib.

tools/bench_size.py converts the stand-in's Thumb-2 code to C28x words by an
assumed factor (WORDS_PER_HALFWORD, 1.2).  This tool checks that factor against
the only C28x code of known size here: C2000Ware ships driverlib both as C
source and as the library TI built from it with cl2000 (Release:
`-O2 -v28 -ml -mt --float_support=fpu32 --gen_func_subsections=on`, COFF), so
every function's C28x size is the size of its `.text:_<name>` section.  The
same sources are compiled here with bench_size.py's stand-in compile (Thumb-2,
its SIZE_FLAGS) and the two sizes compared function by function.

What it measures and what it does not: driverlib is peripheral-register code
(16-bit register fields, read-modify-write), the core of this firmware is
32-bit fixed-point arithmetic; the ratio is a calibration of the stand-in on
TI-compiled C, not of this firmware.  The firmware's cl2000 link (.map file)
is the measurement.

Usage:
  calibrate_words.py C2000WARE_ROOT [--device f2837xd] [--json]
    C2000WARE_ROOT: a C2000Ware (core SDK) folder or checkout, with
    driverlib/<device>/driverlib/*.c and .../ccs/Release/driverlib_coff.lib
"""
import argparse
import json
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
import iqmath_lib_sizes as ils   # noqa: E402  (ar and COFF headers)
import bench_size                # noqa: E402  (the stand-in compile)

SYMBOL_ENTRY = 18   # bytes of one COFF symbol table entry (SPRAAO8)


def coff_sections_long(obj):
    """{section name: words} of a C28x COFF2 object, long names (`.text:_f`)
    read from the string table that follows the symbol table."""
    ver, nsec, _ts, symp, nsym, opt, _fl, target = ils.FILE_HEADER.unpack_from(obj, 0)
    if ver != ils.COFF2_VERSION or target != ils.C28X_TARGET:
        raise ValueError("not a C28x COFF2 object")
    strtab = symp + nsym * SYMBOL_ENTRY
    out = {}
    for i in range(nsec):
        name, _pa, _va, size, *_r = ils.SECTION_HEADER.unpack_from(
            obj, ils.FILE_HEADER.size + opt + i * ils.SECTION_HEADER.size)
        if name[:4] == b"\0\0\0\0":
            off = strtab + struct.unpack_from("<I", name, 4)[0]
            key = obj[off:obj.index(b"\0", off)].decode("ascii", "replace")
        else:
            key = name.split(b"\0")[0].decode("ascii", "replace")
        out[key] = out.get(key, 0) + size
    return out


def c28x_sizes(lib):
    """{function: C28x words} of the `.text:_f` sections of a COFF library."""
    out = {}
    for _name, body in ils.ar_members(Path(lib).read_bytes()):
        try:
            secs = coff_sections_long(body)
        except ValueError:
            continue   # the archive's symbol index and the like
        for k, w in secs.items():
            if k.startswith(".text:_"):
                out[k[len(".text:_"):]] = out.get(k[len(".text:_"):], 0) + w
    return out


# driverlib's hw_types.h declares 8-bit types as 16-bit ones (C28x has no
# bytes) and, off the C28x, two C++ references: neither compiles for Thumb-2
HW_TYPES_PATCH = ("typedef uint16_t uint8_t;", "typedef int16_t int8_t;",
                  "extern int16_t &__byte(", "extern uint32_t &__byte_peripheral_32(")
SHIM = ["-D__asm(x)=", "-D__cregister=", "-D__interrupt=", "-include", "stdint.h",
        "-include", "stdbool.h", "-w", "-std=gnu99"]


def thumb_sizes(src_dir, work):
    """{function: Thumb-2 bytes} of driverlib compiled as bench_size.py's SIZE
    compile; files that do not compile for Thumb-2 (device intrinsics) are
    skipped and listed."""
    dst = Path(work) / "driverlib"
    shutil.copytree(src_dir, dst, ignore=shutil.ignore_patterns("ccs"))
    hw = dst / "inc" / "hw_types.h"
    hw.write_text("\n".join(("/* patched */" if any(p in ln for p in HW_TYPES_PATCH) else ln)
                            for ln in hw.read_text().splitlines()) + "\n")
    out, skipped = {}, []
    for c in sorted(dst.glob("*.c")):
        obj = c.with_suffix(".o")
        r = subprocess.run([bench_size.CC] + bench_size.ARCH + bench_size.SIZE_FLAGS + SHIM
                           + ["-ffunction-sections", "-I", str(dst), "-c", str(c), "-o", str(obj)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            skipped.append(c.name)
            continue
        nm = subprocess.run([bench_size.NM, "-S", "--defined-only", str(obj)],
                            capture_output=True, text=True, check=True).stdout
        for line in nm.splitlines():
            p = line.split()
            if len(p) == 4 and p[2] in "tT":
                out[p[3]] = int(p[1], 16)
    return out, skipped


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("root", help="C2000Ware (core SDK) folder")
    ap.add_argument("--device", default="f2837xd")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    base = Path(a.root) / "driverlib" / a.device / "driverlib"
    lib = base / "ccs" / "Release" / "driverlib_coff.lib"
    for p in (base, lib):
        if not p.exists():
            ap.error(f"not found: {p}")
    c28 = c28x_sizes(lib)
    with tempfile.TemporaryDirectory() as work:
        thumb, skipped = thumb_sizes(base, work)
    common = sorted(set(c28) & set(thumb))
    if not common:
        raise SystemExit("calibrate_words: no function in both compiles")
    words = sum(c28[f] for f in common)
    halfwords = sum(thumb[f] for f in common) / 2.0
    per = [c28[f] / (thumb[f] / 2.0) for f in common if thumb[f] >= 40]
    q = statistics.quantiles(per, n=10)
    r = {"device": a.device, "functions": len(common), "c28x_words": words,
         "thumb_halfwords": halfwords, "words_per_halfword": round(words / halfwords, 3),
         "per_function_median": round(statistics.median(per), 3),
         "per_function_p10": round(q[0], 3), "per_function_p90": round(q[-1], 3),
         "per_function_n": len(per), "assumed": bench_size.WORDS_PER_HALFWORD,
         "skipped_files": skipped}
    if a.json:
        print(json.dumps(r, indent=1))
    else:
        print(f"driverlib {a.device}: {len(common)} functions in both compiles "
              f"(skipped, device intrinsics: {', '.join(skipped) or 'none'})")
        print(f"  C28x (TI's Release build) {words} words, Thumb-2 stand-in {halfwords:.0f} "
              f"halfwords: {r['words_per_halfword']} words per halfword "
              f"(bench_size.py assumes {bench_size.WORDS_PER_HALFWORD})")
        print(f"  per function (>= 20 halfwords, n = {len(per)}): median "
              f"{r['per_function_median']}, 10th-90th percentile {r['per_function_p10']}"
              f"-{r['per_function_p90']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
