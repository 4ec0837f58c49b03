#!/usr/bin/env python3
"""Code size of every function of TI's C28x IQmath library, read from the
library itself: the `IQmath` section of each member object of a COFF archive
(C2000Ware core SDK, libraries/math/IQmath/c28/lib/IQmath_coff.lib; TI's
library is not in this repository: give its path).

Why: tools/bench_size.py counts the IQmath functions the ISR reaches at
these sizes (its TI_IQMATH_WORDS), instead of compiling a stand-in; this tool
is how that table was measured and how to re-measure it for another IQmath
release.

The format (TI SPRAAO8, "Common Object File Format"): a Unix `ar` archive of
COFF2 objects; each object starts with a 22-byte file header (version 0x00C2,
section count, time stamp, symbol table pointer, symbol count, optional header
size, flags, target id 0x009D for the C28x), then the optional header, then
48-byte section headers (name[8], physical and virtual address, size in
16-bit words for the C28x, ...).  A member `IQ24div.obj` holds _IQ24div in its
`IQmath` section.

Usage:
  iqmath_lib_sizes.py LIB [--json]           the largest size of each operation
                                             over N = 1..30, and the spread
  iqmath_lib_sizes.py LIB --check            exit 1 if bench_size.py's table
                                             differs from LIB
"""
import argparse
import json
import re
import struct
import sys
from pathlib import Path

COFF2_VERSION = 0x00C2
C28X_TARGET = 0x009D
FILE_HEADER = struct.Struct("<HHIIIHHH")          # 22 bytes
SECTION_HEADER = struct.Struct("<8sIIIIIIIIIHH")   # 48 bytes
MEMBER = re.compile(r"^IQ(\d+)(\w+)\.obj$")


def ar_members(data):
    """[(name, bytes)] of a Unix ar archive (GNU long names resolved)."""
    if not data.startswith(b"!<arch>\n"):
        raise ValueError("not an ar archive")
    pos, names, out = 8, b"", []
    while pos + 60 <= len(data):
        hdr = data[pos:pos + 60]
        name = hdr[:16].decode("ascii").rstrip()
        size = int(hdr[48:58].decode("ascii").strip())
        body = data[pos + 60:pos + 60 + size]
        pos += 60 + size + (size & 1)
        if name == "//":
            names = body
            continue
        if name.startswith("/") and name[1:].isdigit():
            off = int(name[1:])
            name = names[off:names.index(b"\n", off)].decode("ascii")
        out.append((name.rstrip("/"), body))
    return out


def coff_sections(obj):
    """{section name: size in words} of a C28x COFF2 object (names longer than
    8 characters, in the string table, are not needed here and read as '')."""
    ver, nsec, _ts, _sym, _nsym, opt, _flags, target = FILE_HEADER.unpack_from(obj, 0)
    if ver != COFF2_VERSION or target != C28X_TARGET:
        raise ValueError(f"not a C28x COFF2 object (version {ver:#x}, target {target:#x})")
    out = {}
    base = FILE_HEADER.size + opt
    for i in range(nsec):
        name, _pa, _va, size, *_rest = SECTION_HEADER.unpack_from(obj, base + i * SECTION_HEADER.size)
        key = name.split(b"\0")[0].decode("ascii", "replace") if name[:4] != b"\0\0\0\0" else ""
        out[key] = out.get(key, 0) + size
    return out


def sizes(lib_bytes):
    """{op: {N: words of its IQmath section}} of every IQ<N><op>.obj member."""
    out = {}
    for name, body in ar_members(lib_bytes):
        m = MEMBER.match(name)
        if m:
            out.setdefault(m.group(2), {})[int(m.group(1))] = coff_sections(body).get("IQmath", 0)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("lib", help="TI's IQmath_coff.lib")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--check", action="store_true",
                    help="compare with tools/bench_size.py TI_IQMATH_WORDS")
    a = ap.parse_args(argv)
    per = sizes(Path(a.lib).read_bytes())
    table = {op: max(v.values()) for op, v in sorted(per.items())}
    if a.check:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
        import bench_size   # noqa: E402
        errs = [f"{op}: bench_size {w}, library {table.get(op)}"
                for op, w in sorted(bench_size.TI_IQMATH_WORDS.items()) if table.get(op) != w]
        for e in errs:
            print("DIFFERS", e)
        if not errs:
            print(f"bench_size.py's TI_IQMATH_WORDS agrees with {a.lib} "
                  f"({len(bench_size.TI_IQMATH_WORDS)} operations)")
        return 1 if errs else 0
    if a.json:
        print(json.dumps(table, indent=1))
    else:
        print(f"{'operation':12s} {'words (max over N)':>18s} {'min':>5s} {'members':>8s}")
        for op, v in sorted(per.items()):
            print(f"{op:12s} {max(v.values()):18d} {min(v.values()):5d} {len(v):8d}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
