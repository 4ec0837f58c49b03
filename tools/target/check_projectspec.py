#!/usr/bin/env python3
"""Check firmware/ccs/f2812_firmware.projectspec against the CMake firmware
build (firmware/CMakeLists.txt, cmake/toolchain-ti-c2000.cmake), so that the
CCS project and the CMake build cannot drift apart:

  * the file parses as XML, is a CCS projectSpec for device TMS320F2812, COFF;
  * the files it compiles (.c, .asm not excluded from the build) are exactly
    the sources of the CMake targets `core` and `f2812_firmware`: the
    file(GLOB ...) patterns of firmware/CMakeLists.txt evaluated here, the
    literal files, TI's DSP281x_GlobalVariableDefs.c and the generated
    board_config.c;
  * every configuration has every compiler option of the CMake build
    (CMAKE_C_FLAGS_INIT of the toolchain file, C28_FLAGS; -O2 is
    --opt_level=2) and every include folder, and every linker option
    (target_link_options) and library;
  * the Flash configuration links linker/F2812_flash.cmd, RAM
    linker/F2812_ram.cmd, both F2812_headers.cmd; F2812_isr_path.cmd is
    linked but excluded from the build (it is #included by the other two).

--self-test: a projectspec with one source missing, one option changed, or
the ISR-path include not excluded must be rejected.
"""
import copy
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SPEC = ROOT / "firmware" / "ccs" / "f2812_firmware.projectspec"
# CMake variable -> how the projectspec names the same folder
SYMBOLS = {"${ROOT}": "${IMFOC_ROOT}", "${CMAKE_CURRENT_SOURCE_DIR}": "${IMFOC_ROOT}/firmware",
           "${TI_HEADERS}": "${DSP281X_HEADERS_ROOT}/DSP281x_headers",
           "${TI_IQMATH_INC}": "${C2000_IQMATH_ROOT}/include"}


def cmake_sources(text):
    """Sources of `core` and `f2812_firmware`, as projectspec paths."""
    globs = {}
    for m in re.finditer(r"file\((GLOB(?:_RECURSE)?)\s+(\w+)\s+(?:CONFIGURE_DEPENDS\s+)?([^)]+)\)",
                         text):
        kind, var, pat = m.groups()
        pat = pat.strip()
        for k, v in SYMBOLS.items():
            pat = pat.replace(k, v)
        rel = pat.replace("${IMFOC_ROOT}/", "")
        base, _, patt = rel.rpartition("/")
        files = (ROOT / base).rglob(patt) if kind == "GLOB_RECURSE" else (ROOT / base).glob(patt)
        globs[var] = sorted("${IMFOC_ROOT}/" + f.relative_to(ROOT).as_posix() for f in files)
    args = []
    for m in re.finditer(r"add_(?:library|executable)\((?:core|f2812_firmware)\s+(.*?)\)\s*\n",
                         text, re.S):
        args += m.group(1).split()
    for m in re.finditer(r"target_sources\(f2812_firmware\s+PRIVATE\s+([^)]+)\)", text):
        args += m.group(1).split()
    out = set()
    for a in args:
        if a in ("OBJECT", "$<TARGET_OBJECTS:core>"):
            continue
        m = re.fullmatch(r"\$\{(\w+)\}", a)
        if m and m.group(1) in globs:
            out |= set(globs[m.group(1)])
        elif a == "${_board_c}":
            out.add("board_config.c")
        else:
            for k, v in SYMBOLS.items():
                a = a.replace(k, v)
            out.add(a)
    return out


def cmake_options(cm, tc):
    """(compiler options, linker options) the CMake build uses."""
    flags = re.search(r'CMAKE_C_FLAGS_INIT\s+"([^"]+)"', tc).group(1)
    abi = re.search(r'set\(C2000_ABI\s+"(\w+)"', tc).group(1)
    comp = flags.replace("${C2000_ABI}", abi).split()
    c28 = re.search(r"set\(C28_FLAGS\s+(.*?)\)", cm, re.S).group(1).split()
    comp += ["--opt_level=2" if o == "-O2" else o for o in c28]
    comp += ["-I${IMFOC_ROOT}/include", "-I${IMFOC_ROOT}/firmware", "-I${C2000_IQMATH_ROOT}/include",
             "-I${DSP281X_HEADERS_ROOT}/DSP281x_headers/include"]
    link = re.search(r"target_link_options\(f2812_firmware\s+PRIVATE\s+(.*?)\)", cm, re.S).group(1)
    lo = []
    for o in link.split():
        if o == "--search_path=${C2000_CGT_ROOT}/lib":
            continue                  # CCS adds the compiler's own lib folder
        lo.append(o.replace("--search_path=${ROOT}/linker", "-i${IMFOC_ROOT}/linker"))
    iq = "IQmath_coff.lib" if "IQmath_coff.lib" in cm else "IQmath.lib"
    lo += [f"--library={iq}", "--library=rts2800_ml.lib"]
    return comp, lo


def check(root, cm, tc):
    errs = []
    proj = root.find("project")
    if root.tag != "projectSpec" or proj is None:
        return ["not a CCS projectSpec (<projectSpec><project ...>)"]
    if proj.get("device") != "TMS320F2812":
        errs.append("device is %r, not TMS320F2812" % proj.get("device"))
    if proj.get("outputFormat") != "COFF":
        errs.append("outputFormat is %r, not COFF (the build's --abi=coffabi)" % proj.get("outputFormat"))
    files = proj.findall("file")
    built = {f.get("path") for f in files if f.get("excludeFromBuild", "False") != "True"}
    compiled = {p for p in built if p.endswith((".c", ".asm"))}
    compiled = {("board_config.c" if p.endswith("/board_config.c") else p) for p in compiled}
    want = cmake_sources(cm)
    for p in sorted(want - compiled):
        errs.append("CMake compiles %s, the projectspec does not" % p)
    for p in sorted(compiled - want):
        errs.append("the projectspec compiles %s, CMake does not" % p)
    comp, link = cmake_options(cm, tc)
    configs = proj.findall("configuration")
    if {c.get("name") for c in configs} != {"Flash", "RAM"}:
        errs.append("configurations must be Flash and RAM")
    for c in configs:
        have_c = c.get("compilerBuildOptions", "").split()
        have_l = c.get("linkerBuildOptions", "").split()
        for o in comp:
            if o not in have_c:
                errs.append("%s: compiler option %s (CMake) missing" % (c.get("name"), o))
        for o in link:
            if o not in have_l:
                errs.append("%s: linker option %s (CMake) missing" % (c.get("name"), o))
    cmds = {}
    for f in files:
        if f.get("path", "").endswith(".cmd"):
            cmds[Path(f.get("path")).name] = f
    for name, conf in (("F2812_flash.cmd", "Flash"), ("F2812_ram.cmd", "RAM")):
        f = cmds.get(name)
        if f is None or f.get("applicableConfigurations") != conf:
            errs.append("%s must be linked for the %s configuration only" % (name, conf))
    if "F2812_headers.cmd" not in cmds or cmds["F2812_headers.cmd"].get("applicableConfigurations"):
        errs.append("F2812_headers.cmd must be linked for every configuration")
    for inc in ("F2812_isr_path.cmd", "F2812_isr_slow.cmd"):
        isr = cmds.get(inc)
        if isr is None or isr.get("excludeFromBuild") != "True":
            errs.append("%s must be linked with excludeFromBuild=\"True\" "
                        "(#included by the image's command file)" % inc)
    return errs


def self_test(root, cm, tc):
    cases = {}
    r = copy.deepcopy(root)
    p = r.find("project")
    p.remove([f for f in p.findall("file") if f.get("path").endswith("drive_step.c")][0])
    cases["a source missing"] = r
    r = copy.deepcopy(root)
    c = r.find("project").find("configuration")
    c.set("compilerBuildOptions", c.get("compilerBuildOptions").replace("GLOBAL_Q=24", "GLOBAL_Q=20"))
    cases["GLOBAL_Q changed"] = r
    r = copy.deepcopy(root)
    for f in r.find("project").findall("file"):
        if f.get("path").endswith("F2812_isr_path.cmd"):
            del f.attrib["excludeFromBuild"]
    cases["ISR-path include built"] = r
    r = copy.deepcopy(root)
    r.find("project").set("device", "TMS320F28335")
    cases["another device"] = r
    bad = 0
    for what, tree in cases.items():
        e = check(tree, cm, tc)
        print("%-24s %s" % (what, "rejected: " + e[0] if e else "NOT REJECTED"))
        bad += 0 if e else 1
    return 1 if bad else 0


def main(argv):
    cm = (ROOT / "firmware" / "CMakeLists.txt").read_text()
    tc = (ROOT / "cmake" / "toolchain-ti-c2000.cmake").read_text()
    spec = Path(argv[2]) if len(argv) > 2 and argv[1] == "--spec" else SPEC
    try:
        root = ET.parse(spec).getroot()
    except ET.ParseError as e:
        print("ERROR %s: not XML: %s" % (spec, e))
        return 1
    errs = check(root, cm, tc)
    if "--self-test" in argv:
        if errs:
            print("self-test: the projectspec itself is rejected:", errs)
            return 1
        return self_test(root, cm, tc)
    for e in errs:
        print("ERROR", e)
    print("%s: %d sources, %d errors" % (spec.relative_to(ROOT) if spec.is_absolute() and ROOT in spec.parents else spec,
                                         len(cmake_sources(cm)), len(errs)))
    return 1 if errs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
