#!/usr/bin/env python3
"""RAM of the firmware's state structures on the C28x, in 16-bit words.

sizeof on the host counts 8-bit bytes with host alignment and 64-bit
pointers, so the C28x sizes are computed from the field types of the headers
in include/ (C28x EABI/COFF rules, large memory model):
  int32_t, uint32_t, _iq, _iqN, float       2 words, aligned on an even address
  int16_t, uint16_t, enums                  1 word
  pointers (large model, 22-bit)            2 words, even
  struct                                    its fields in order with that
                                            alignment; size rounded up to its
                                            own alignment (2 if any 32-bit field)
Array sizes may use the headers' #define constants (RLS_N).

Usage: bench_ram.py [--json] [--host-check BYTES_JSON]
"""
import argparse
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WORD32 = {"int32_t", "uint32_t", "angle_acc_t", "float", "_iq"} | {f"_iq{n}" for n in range(1, 31)}
WORD16 = {"int16_t", "uint16_t"}


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


def resolve_conditionals(text, consts):
    """Keep what the firmware build compiles of `#if NAME`, `#ifdef NAME`,
    `#ifndef NAME` blocks (NAME's value from the headers' defaults, consts;
    undefined: 0), e.g. a struct's fields under `#if IDENT_PERIOD_MEAN`;
    any other condition (`#if MATH_TYPE == IQ_MATH`) keeps both branches,
    as before.  The directive lines themselves go."""
    out, stack = [], []   # stack: (this branch kept, condition known)
    for line in text.split("\n"):
        s = line.strip()
        m = re.match(r"#\s*(if|ifdef|ifndef|elif|else|endif)\b\s*(.*)$", s)
        if not m:
            if all(k for k, _ in stack):
                out.append(line)
            continue
        d, arg = m.group(1), m.group(2).strip()
        if d in ("if", "ifdef", "ifndef"):
            known = bool(re.fullmatch(r"\w+", arg))
            if not known:
                keep = True
            elif d == "if":
                keep = bool(consts.get(arg, 0))
            else:
                keep = (arg in consts) == (d == "ifdef")
            stack.append((keep, known))
        elif d == "else" and stack:
            keep, known = stack.pop()
            stack.append(((not keep) if known else True, known))
        elif d == "elif" and stack:
            stack.pop()
            stack.append((True, False))   # a chain: every branch kept, as before
        elif d == "endif" and stack:
            stack.pop()
    return "\n".join(out)


def parse_headers(paths):
    structs, enums, consts = {}, set(), {}
    texts = [strip_comments(Path(p).read_text()) for p in paths]
    for t in texts:
        for m in re.finditer(r"#define\s+(\w+)\s+\(?(\d+)[uU]?\)?\s*\n", t + "\n"):
            consts[m.group(1)] = int(m.group(2))
    for t in texts:
        t = resolve_conditionals(t, consts)
        for m in re.finditer(r"typedef\s+enum\s*\w*\s*\{[^}]*\}\s*(\w+)\s*;", t):
            enums.add(m.group(1))
        for m in re.finditer(r"typedef\s+struct\s*\w*\s*\{(.*?)\}\s*(\w+)\s*;", t, flags=re.S):
            structs[m.group(2)] = m.group(1)
        for m in re.finditer(r"(?<!typedef )struct\s+(\w+)\s*\{(.*?)\}\s*;", t, flags=re.S):
            structs["struct " + m.group(1)] = m.group(2)
    return structs, enums, consts


def fields(body, consts):
    """[(type, name, count, is_pointer)] of a struct body."""
    out = []
    for decl in body.split(";"):
        decl = " ".join(decl.split())
        if not decl:
            continue
        m = re.match(r"(?:const\s+|volatile\s+)*((?:struct\s+)?\w+)\s+(.*)$", decl)
        if not m:
            raise ValueError(f"cannot parse field '{decl}'")
        typ, rest = m.group(1), m.group(2)
        for d in rest.split(","):
            d = d.strip()
            ptr = d.startswith("*")
            name = re.match(r"\**\s*(\w+)", d).group(1)
            n = 1
            for dim in re.findall(r"\[([^\]]+)\]", d):
                dim = dim.strip()
                n *= int(dim) if dim.isdigit() else consts[dim]
            out.append((typ, name, n, ptr))
    return out


class Layout:
    def __init__(self, structs, enums, consts):
        self.structs, self.enums, self.consts = structs, enums, consts
        self.cache = {}

    def type_size(self, typ, ptr=False):
        """(words, alignment) of one element."""
        if ptr:
            return 2, 2
        if typ in WORD32:
            return 2, 2
        if typ in WORD16 or typ in self.enums:
            return 1, 1
        if typ in self.structs:
            return self.struct_size(typ)
        raise KeyError(f"unknown type {typ}")

    def struct_size(self, name):
        if name in self.cache:
            return self.cache[name]
        off, align = 0, 1
        for typ, _n, cnt, ptr in fields(self.structs[name], self.consts):
            sz, al = self.type_size(typ, ptr)
            off = (off + al - 1) // al * al + sz * cnt
            align = max(align, al)
        size = (off + align - 1) // align * align
        self.cache[name] = (size, align)
        return size, align

    def members(self, name):
        rows = []
        for typ, n, cnt, ptr in fields(self.structs[name], self.consts):
            sz, _al = self.type_size(typ, ptr)
            rows.append((n, typ + ("*" if ptr else "") + (f"[{cnt}]" if cnt > 1 else ""),
                         sz * cnt))
        return rows


class HostLayout(Layout):
    """The same parse with x86-64 rules, in bytes (int32/float/enum 4, int16 2,
    pointer 8, natural alignment): must reproduce the host's sizeof, which
    checks the parse itself (tools/python/tests/test_bench_ram.py)."""

    def type_size(self, typ, ptr=False):
        if ptr:
            return 8, 8
        if typ in WORD32 or typ in self.enums:
            return 4, 4
        if typ in WORD16:
            return 2, 2
        if typ in self.structs:
            return self.struct_size(typ)
        raise KeyError(f"unknown type {typ}")


def layout(cls=Layout):
    hdrs = sorted((ROOT / "include").glob("*.h")) + sorted((ROOT / "host_sim" / "iqmath")
                                                          .glob("IQmathLib.h"))
    return cls(*parse_headers(hdrs))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    L = layout()
    drive_words = L.struct_size("struct drive")[0]
    members = L.members("struct drive")
    if a.json:
        print(json.dumps({"drive_t_words": drive_words,
                          "members": {n: w for n, _t, w in members}}, indent=1))
        return 0
    print(f"drive_t (one firmware instance, all ISR and background state): {drive_words} words "
          f"= {2 * drive_words} bytes of C28x RAM")
    for n, t, w in sorted(members, key=lambda r: -r[2]):
        print(f"  {n:16s} {t:24s} {w:5d} words")
    return 0


if __name__ == "__main__":
    sys.exit(main())
