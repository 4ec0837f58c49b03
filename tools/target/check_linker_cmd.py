#!/usr/bin/env python3
"""Check TI linker command files against the TMS320F2812 memory map (4c).

The reference table below is the F2812 memory map of the data sheet
(SPRS174, "F2812 Memory Map" figure and the "Flash Sectors" /
"Peripheral Frame" tables), encoded by hand.  Checked for every MEMORY
range of every file given (all files together form one link):

  * it lies inside one real memory block of the device;
  * it overlaps no other range (PAGE 0 and PAGE 1 are the same unified
    address space on the C28x, so pages are not separate);
  * a range named like a flash sector (FLASHA..FLASHJ) is exactly that
    sector (FLASHA ends at 0x3F7F7F, before the CSM reserved words);
  * BEGIN (when present) is 0x3F7FF6/2, CSM_RSVD 0x3F7F80/0x76, CSM_PWL
    0x3F7FF8/8, IQTABLES starts at 0x3FF000 in boot ROM, RESET 0x3FFFC0;
  * peripheral frames named as in the DSP281x header files are at the
    data-sheet addresses with the data-sheet sizes;
  * SECTIONS: every '> NAME' / 'LOAD =' / 'RUN =' names a declared range;
    ramfuncs and ramfuncs_slow load from flash (or in place, RAM image), run
    in SARAM and define the three symbols each that flash_copy_ramfuncs
    uses; codestart goes to BEGIN (flash) or BEGINH0 (RAM image);
  * the two sections gather exactly the ISR path: ramfuncs the firmware's
    `ramfuncs` input sections and the #include of the generated
    F2812_isr_path.cmd (the every-period set), ramfuncs_slow the firmware's
    `ramfuncs_slow` input sections and F2812_isr_slow.cmd (the set reached
    only through the slow-task dispatch), and one of them TI's IQmath
    section (so that no linker file can drop the ISR path back into flash);
  * every #include "file" names a file next to the command file, and an
    included file holds only comments and input section specifications
    `*(.text:name)` (it is spliced inside an output section's braces).

--self-test runs the checker on broken snippets and passes only if each is
rejected (the check can fail).
"""
import os
import re
import sys

K = 1024
# SPRS174, F2812 memory map (addresses in 16-bit words). (name, first, last, kind)
DEVICE = [
    ("M0 SARAM", 0x000000, 0x0003FF, "ram"),
    ("M1 SARAM", 0x000400, 0x0007FF, "ram"),
    ("Peripheral Frame 0", 0x000800, 0x000CFF, "periph"),
    ("PIE vector RAM", 0x000D00, 0x000DFF, "periph"),
    ("XINTF zone 0", 0x002000, 0x003FFF, "ext"),
    ("XINTF zone 1", 0x004000, 0x005FFF, "ext"),
    ("Peripheral Frame 2", 0x006000, 0x006FFF, "periph"),
    ("Peripheral Frame 1", 0x007000, 0x007FFF, "periph"),
    ("L0 SARAM", 0x008000, 0x008FFF, "ram"),
    ("L1 SARAM", 0x009000, 0x009FFF, "ram"),
    ("XINTF zone 2", 0x080000, 0x0FFFFF, "ext"),
    ("XINTF zone 6", 0x100000, 0x17FFFF, "ext"),
    ("OTP", 0x3D7800, 0x3D7BFF, "flash"),
    ("Flash", 0x3D8000, 0x3F7FFF, "flash"),
    ("H0 SARAM", 0x3F8000, 0x3F9FFF, "ram"),
    ("Boot ROM", 0x3FF000, 0x3FFFBF, "rom"),
    ("Boot ROM vectors", 0x3FFFC0, 0x3FFFFF, "rom"),
]
# SPRS174 "Flash sectors" (F2812: 128K x 16)
SECTORS = {
    "FLASHJ": (0x3D8000, 0x2000), "FLASHI": (0x3DA000, 0x2000),
    "FLASHH": (0x3DC000, 0x4000), "FLASHG": (0x3E0000, 0x4000),
    "FLASHF": (0x3E4000, 0x4000), "FLASHE": (0x3E8000, 0x4000),
    "FLASHD": (0x3EC000, 0x4000), "FLASHC": (0x3F0000, 0x4000),
    "FLASHB": (0x3F4000, 0x2000),
    "FLASHA": (0x3F6000, 0x1F80),   # sector A minus CSM_RSVD, BEGIN, CSM_PWL
}
FIXED = {
    "CSM_RSVD": (0x3F7F80, 0x0076), "BEGIN": (0x3F7FF6, 0x0002),
    "CSM_PWL": (0x3F7FF8, 0x0008), "RESET": (0x3FFFC0, 0x0002),
    "BEGINH0": (0x3F8000, 0x0002),
}
# SPRS174 peripheral frame tables: register file -> (origin, length)
PERIPH = {
    "DEV_EMU": (0x000880, 0x180), "FLASH_REGS": (0x000A80, 0x60), "CSM": (0x000AE0, 0x10),
    "XINTF": (0x000B20, 0x20), "CPU_TIMER0": (0x000C00, 8), "CPU_TIMER1": (0x000C08, 8),
    "CPU_TIMER2": (0x000C10, 8), "PIE_CTRL": (0x000CE0, 0x20), "PIE_VECT": (0x000D00, 0x100),
    "ECANA": (0x006000, 0x40), "ECANA_LAM": (0x006040, 0x40), "ECANA_MOTS": (0x006080, 0x40),
    "ECANA_MOTO": (0x0060C0, 0x40), "ECANA_MBOX": (0x006100, 0x100),
    "SYSTEM": (0x007010, 0x20), "SPIA": (0x007040, 0x10), "SCIA": (0x007050, 0x10),
    "XINTRUPT": (0x007070, 0x10), "GPIOMUX": (0x0070C0, 0x20), "GPIODAT": (0x0070E0, 0x20),
    "ADC": (0x007100, 0x20), "EVA": (0x007400, 0x40), "EVB": (0x007500, 0x40),
    "SCIB": (0x007750, 0x10), "MCBSPA": (0x007800, 0x40),
}
IQTABLES_ORIGIN = 0x3FF000

RANGE_RE = re.compile(r"^\s*(\w+)\s*(?:\(\s*\w+\s*\))?\s*:\s*origin\s*=\s*(0x[0-9A-Fa-f]+|\d+)\s*,"
                      r"\s*length\s*=\s*(0x[0-9A-Fa-f]+|\d+)", re.M)


def containing_block(org, last):
    """The device block (contiguous blocks of one kind merged, e.g. L0+L1,
    M0+M1) that holds org..last, or None."""
    for b in DEVICE:
        if b[1] <= org <= b[2]:
            end, kind = b[2], b[3]
            for c in DEVICE:   # DEVICE is sorted by address
                if c[1] == end + 1 and c[3] == kind:
                    end = c[2]
            if last <= end:
                return (b[0], b[1], end, kind)
    return None


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def parse(text):
    text = strip_comments(text)
    ranges, sections = [], ""
    m = re.search(r"\bMEMORY\s*\{(.*?)\n\}", text, re.S)
    if m:
        page = None
        for line in m.group(1).splitlines():
            pm = re.match(r"\s*PAGE\s*(\d)\s*:", line)
            if pm:
                page = int(pm.group(1))
                continue
            rm = RANGE_RE.match(line)
            if rm:
                ranges.append((rm.group(1), page, int(rm.group(2), 0), int(rm.group(3), 0)))
    s = re.search(r"\bSECTIONS\s*\{(.*)\}", text, re.S)
    if s:
        sections = s.group(1)
    return ranges, sections


ISR_PATH_INCLUDE = "F2812_isr_path.cmd"
ISR_SLOW_INCLUDE = "F2812_isr_slow.cmd"
# output section -> (its input section, its generated include, its symbols)
RAM_CODE = {
    "ramfuncs": ("ramfuncs", ISR_PATH_INCLUDE,
                 ("_RamfuncsLoadStart", "_RamfuncsLoadEnd", "_RamfuncsRunStart")),
    "ramfuncs_slow": ("ramfuncs_slow", ISR_SLOW_INCLUDE,
                      ("_RamfuncsSlowLoadStart", "_RamfuncsSlowLoadEnd", "_RamfuncsSlowRunStart")),
}
INPUT_SPEC = re.compile(r"^\*\(\.text:\w+\)$"
                        # TI's IQmath functions of the ISR path: members of the library
                        r"|^-l \w+\.lib<[\w. ]+> \(IQmath\)$|^\*\(IQmath\)$"
                        r"|^#ifndef IQMATH_WHOLE_IN_RAM$|^#else$|^#endif$"
                        # the flash set: on chip in the RAM image only (bench_size.py)
                        r"|^#ifdef ISR_FLASH_SET_IN_RAM$"
                        # FAST_IN_SLOW_RAM: H0 in the flash image, L0+L1 in the RAM image
                        r"|^#ifn?def ISR_RAM_IMAGE$")
IQMATH_MEMBERS = re.compile(r"^-l \w+\.lib<[\w. ]+> \(IQmath\)$", re.M)


def include_text(name, inc, included=None):
    """The text of `#include "inc"` of command file `name`, or None."""
    if included is not None and inc in included:
        return included[inc]
    path = os.path.join(os.path.dirname(name), inc)
    return open(path).read() if os.path.exists(path) else None


def check_includes(name, text, included=None):
    """Errors of the #include lines of one command file; `included` maps an
    included file name to its text (default: read it next to `name`)."""
    errors = []
    for inc in re.findall(r'^\s*#include\s+"([^"]+)"', text, re.M):
        body = include_text(name, inc, included)
        if body is None:
            errors.append("%s: #include \"%s\": no such file next to it" % (name, inc))
            continue
        for line in strip_comments(body).split("\n"):
            if line.strip() and not INPUT_SPEC.match(line.strip()):
                errors.append("%s: %s: not an input section specification: %s"
                              % (name, inc, line.strip()))
    return errors


def check(files, included=None):
    """files: list of (name, text).  Returns a list of error strings."""
    errors, ranges, sections = [], [], {}
    for name, text in files:
        errors += check_includes(name, text, included)
        r, s = parse(text)
        if not r and not s:
            errors.append("%s: no MEMORY or SECTIONS found" % name)
        ranges += [(name,) + x for x in r]
        sections[name] = s
    for f, n, page, org, ln in ranges:
        last = org + ln - 1
        where = "%s: %s (0x%06X..0x%06X)" % (f, n, org, last)
        if page not in (0, 1):
            errors.append("%s: not in PAGE 0 or 1" % where)
        if ln <= 0:
            errors.append("%s: empty" % where)
        blk = containing_block(org, last)
        blocks = [blk] if blk else []
        if not blocks:
            errors.append("%s: not inside one F2812 memory block (SPRS174)" % where)
        if n in SECTORS and (org, ln) != SECTORS[n]:
            errors.append("%s: flash sector %s is 0x%06X/0x%X" % ((where, n) + SECTORS[n]))
        if n in FIXED and (org, ln) != FIXED[n]:
            errors.append("%s: must be 0x%06X/0x%X" % ((where,) + FIXED[n]))
        if n in PERIPH and (org, ln) != PERIPH[n]:
            errors.append("%s: register frame is 0x%06X/0x%X" % ((where,) + PERIPH[n]))
        if n == "IQTABLES" and (org != IQTABLES_ORIGIN or not blocks or blocks[0][3] != "rom"):
            errors.append("%s: IQmath tables are in boot ROM at 0x3FF000" % where)
        if n.startswith("RAM") and blocks and blocks[0][3] != "ram":
            errors.append("%s: RAM range outside SARAM" % where)
        if re.match(r"^FLASH[A-J]+$", n) and blocks and blocks[0][1] != 0x3D8000:
            errors.append("%s: flash range outside the flash array" % where)
    # overlaps, across pages and files (unified memory)
    for i, a in enumerate(ranges):
        for b in ranges[i + 1:]:
            if a[3] <= b[3] + b[4] - 1 and b[3] <= a[3] + a[4] - 1:
                errors.append("%s:%s overlaps %s:%s" % (a[0], a[1], b[0], b[1]))
    names = {r[1]: r for r in ranges}
    for f, s in sections.items():
        for target in re.findall(r"(?:>>?|LOAD\s*=|RUN\s*=)\s*([A-Za-z_]\w*(?:\s*\|\s*[A-Za-z_]\w*)*)", s):
            for t in re.split(r"\s*\|\s*", target):
                if t not in names:
                    errors.append("%s: SECTIONS places into undeclared range %s" % (f, t))
        iq_in = []
        # an image's command file (not the headers) places the RAM code
        has_code = any(re.search(r"\b%s\s*:" % o, s) for o in RAM_CODE)
        for out, (insec, inc, syms) in (RAM_CODE.items() if has_code else ()):
            rf = re.search(r"\b%s\s*:(.*?)PAGE" % out, s, re.S)
            if not rf:
                errors.append("%s: no %s output section" % (f, out))
                continue
            body = rf.group(1)
            ld = re.search(r"LOAD\s*=\s*(\w+)", body)
            rn = re.search(r"RUN\s*=\s*(\w+)", body)
            for sym in syms:
                if sym not in body:
                    errors.append("%s: %s does not define %s" % (f, out, sym))
            spec = re.search(r"\b%s\s*:\s*\{(.*?)\}" % out, s, re.S)
            spec = spec.group(1) if spec else ""
            flat = spec.replace(" ", "").replace('#include"', '#include "')
            for need, what in (("*(%s)" % insec, "the firmware's #pragma'd functions"),
                               ('#include "%s"' % inc, "the ISR path's src/ functions")):
                if need not in flat:
                    errors.append("%s: %s does not gather %s (%s)" % (f, out, what, need))
            inc_text = include_text(f, inc, included) or ""
            if "*(IQmath)" in flat or "(IQmath)" in strip_comments(inc_text):
                iq_in.append(out)
            if IQMATH_MEMBERS.search(strip_comments(inc_text)) and not re.search(
                    r"(?m)^\s*IQmath\s*:", s):
                errors.append("%s: %s takes TI's IQmath members of the ISR path; the other "
                              "IQmath functions need an output section IQmath" % (f, out))
            if not ld or not rn:
                errors.append("%s: %s needs LOAD and RUN" % (f, out))
            else:
                run = names.get(rn.group(1))
                blk = containing_block(run[3], run[3] + run[4] - 1) if run else None
                if run and (not blk or blk[3] != "ram"):
                    errors.append("%s: %s must RUN in SARAM" % (f, out))
                load = names.get(ld.group(1))
                if load and ld.group(1) != rn.group(1) and not (0x3D8000 <= load[3] <= 0x3F7FFF):
                    errors.append("%s: %s must LOAD from flash" % (f, out))
        if has_code and len(iq_in) != 1:
            errors.append("%s: TI's IQmath code of the ISR path (*(IQmath) or the library's "
                          "members) must be gathered by exactly one of ramfuncs, ramfuncs_slow, "
                          "not %s" % (f, iq_in or "none"))
        cs = re.search(r"\bcodestart\s*:\s*>\s*(\w+)", s)
        if cs and cs.group(1) not in ("BEGIN", "BEGINH0"):
            errors.append("%s: codestart must go to BEGIN (0x3F7FF6) or BEGINH0" % f)
        if re.search(r"\bIQmathTables\s*:", s) and not re.search(
                r"\bIQmathTables\s*:\s*>\s*IQTABLES[^\n]*NOLOAD", s):
            errors.append("%s: IQmathTables must be NOLOAD in IQTABLES (boot ROM)" % f)
    return errors


def self_test():
    good = """MEMORY {
PAGE 0 :
   BEGIN : origin = 0x3F7FF6, length = 0x000002
   FLASHD : origin = 0x3EC000, length = 0x004000
   RAML0L1 : origin = 0x008000, length = 0x002000
   RAMH0 : origin = 0x3F8000, length = 0x001A00
PAGE 1 :
   RAMM1 : origin = 0x000400, length = 0x000400
}
SECTIONS {
   codestart : > BEGIN, PAGE = 0
   ramfuncs : { *(ramfuncs)
#include "F2812_isr_path.cmd"
                *(IQmath) }
              LOAD = FLASHD, RUN = RAML0L1, LOAD_START(_RamfuncsLoadStart),
              LOAD_END(_RamfuncsLoadEnd), RUN_START(_RamfuncsRunStart), PAGE = 0
   ramfuncs_slow : { *(ramfuncs_slow)
#include "F2812_isr_slow.cmd"
              } LOAD = FLASHD, RUN = RAMH0, LOAD_START(_RamfuncsSlowLoadStart),
              LOAD_END(_RamfuncsSlowLoadEnd), RUN_START(_RamfuncsSlowRunStart), PAGE = 0
   .stack : > RAMM1, PAGE = 1
}
"""
    bad = {
        "overlap across pages": good.replace("RAMM1 : origin = 0x000400", "RAMM1 : origin = 0x008400"),
        "range beyond L1": good.replace("length = 0x002000", "length = 0x002400"),
        "BEGIN misplaced": good.replace("0x3F7FF6", "0x3F7FF4"),
        "wrong sector size": good.replace("length = 0x004000", "length = 0x003000"),
        "range in a hole": good.replace("0x000400, length = 0x000400", "0x000A000, length = 0x000400"),
        "undeclared target": good.replace("> RAMM1", "> RAMM2"),
        "ramfuncs runs in flash": good.replace("RUN = RAML0L1", "RUN = FLASHD"),
        "missing symbol": good.replace("RUN_START(_RamfuncsRunStart)", ""),
        "ISR path not included": good.replace('#include "F2812_isr_path.cmd"', ""),
        "IQmath left in flash": good.replace("*(IQmath)", ""),
        "IQmath in both": good.replace("*(ramfuncs_slow)", "*(ramfuncs_slow) *(IQmath)"),
        "slow set not included": good.replace('#include "F2812_isr_slow.cmd"', ""),
        "slow set runs in flash": good.replace("RUN = RAMH0", "RUN = FLASHD"),
        "slow symbol missing": good.replace("RUN_START(_RamfuncsSlowRunStart)", ""),
        "no ramfuncs_slow": good[:good.index("   ramfuncs_slow")] + good[good.index("   .stack"):],
        "include of a missing file": good.replace("F2812_isr_path.cmd", "F2812_nothing.cmd"),
        "include that is not input specs": good.replace('#include "F2812_isr_path.cmd"',
                                                        '#include "bad_include.cmd"'),
    }
    inc = {"F2812_isr_path.cmd": "/* generated */\n*(.text:_drive_isr)\n*(.text:_modulate)\n",
           "F2812_isr_slow.cmd": "/* generated */\n*(.text:_tr_track_step)\n",
           "bad_include.cmd": "*(.text:_drive_isr)\n.text : > FLASHD\n"}
    if check([("good", good)], inc):
        print("self-test: the good snippet was rejected:", check([("good", good)], inc))
        return 1
    # the ISR path's IQmath by library members (the generated slow include),
    # the rest in an IQmath output section
    members = good.replace("*(IQmath) }", "}").replace(
        "   .stack", "   IQmath : > FLASHD, PAGE = 0\n   .stack")
    inc_m = dict(inc)
    inc_m["F2812_isr_slow.cmd"] = (inc["F2812_isr_slow.cmd"] + "#ifndef IQMATH_WHOLE_IN_RAM\n"
                                   "-l IQmath_coff.lib<IQ24div.obj IQ24sinPU.obj> (IQmath)\n"
                                   "#else\n*(IQmath)\n#endif\n")
    if check([("members", members)], inc_m):
        print("self-test: the members snippet was rejected:", check([("members", members)], inc_m))
        return 1
    for what, text in (("members, rest unplaced", members.replace("   IQmath : > FLASHD, PAGE = 0\n", "")),
                       ("members and *(IQmath)", members.replace("*(ramfuncs)\n", "*(ramfuncs) *(IQmath)\n"))):
        e = check([(what, text)], inc_m)
        print("%-24s %s" % (what, "rejected: " + e[0] if e else "NOT REJECTED"))
        if not e:
            return 1
    # the flash set's block (on chip only where ISR_FLASH_SET_IN_RAM is defined)
    inc_f = dict(inc)
    inc_f["F2812_isr_path.cmd"] = (inc["F2812_isr_path.cmd"] + "#ifdef ISR_FLASH_SET_IN_RAM\n"
                                   "*(.text:_sensor_test_step)\n#endif\n")
    if check([("flash set", good)], inc_f):
        print("self-test: the flash-set snippet was rejected:", check([("flash set", good)], inc_f))
        return 1
    inc_x = dict(inc_f)
    inc_x["F2812_isr_path.cmd"] = inc_f["F2812_isr_path.cmd"].replace(
        "ISR_FLASH_SET_IN_RAM", "SOMETHING_ELSE")
    e = check([("other #ifdef", good)], inc_x)
    print("%-24s %s" % ("other #ifdef", "rejected: " + e[0] if e else "NOT REJECTED"))
    if not e:
        return 1
    failed = 0
    for what, text in bad.items():
        e = check([(what, text)], inc)
        print("%-24s %s" % (what, "rejected: " + e[0] if e else "NOT REJECTED"))
        failed += 0 if e else 1
    return 1 if failed else 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    # the flash and RAM images are separate links: check each with the headers
    images = [p for p in argv[1:] if not p.endswith("headers.cmd")]
    headers = [p for p in argv[1:] if p.endswith("headers.cmd")]
    total = 0
    for img in images:
        files = [(p, open(p).read()) for p in [img] + headers]
        errs = check(files)
        n = sum(len(parse(t)[0]) for _, t in files)
        for e in errs:
            print("ERROR", e)
        print("%s + headers: %d ranges, %d errors" % (img, n, len(errs)))
        total += len(errs)
    return 1 if total or not images else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
