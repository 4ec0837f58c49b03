"""tools/bench_ram.py: its header parse, checked against the host compiler."""
import shutil
import subprocess

import pytest

import bench_ram

STRUCTS = ("struct drive", "rls_t", "ident_regressor_t", "qep_speed_t", "svgen_t", "pi_ctrl_t")


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_parse_reproduces_host_sizeof(tmp_path):
    """With x86-64 rules the parse must give gcc's sizeof exactly: then every
    field and array size was read right, and only the word sizes differ on
    the C28x."""
    names = [n.replace("struct drive", "drive_t") for n in STRUCTS]
    src = tmp_path / "s.c"
    src.write_text('#include <stdio.h>\n#include "drive_types.h"\nint main(void){\n' +
                   "".join(f'printf("%zu\\n", sizeof({n}));\n' for n in names) +
                   "return 0;}\n")
    root = bench_ram.ROOT
    exe = tmp_path / "s"
    subprocess.run(["cc", "-std=c99", "-DMATH_TYPE=IQ_MATH", "-DGLOBAL_Q=24",
                    f"-I{root / 'include'}", f"-I{root / 'host_sim' / 'iqmath'}",
                    str(src), "-o", str(exe)], check=True)
    host = [int(x) for x in subprocess.run([str(exe)], capture_output=True, text=True,
                                           check=True).stdout.split()]
    L = bench_ram.layout(bench_ram.HostLayout)
    assert [L.struct_size(n)[0] for n in STRUCTS] == host


def test_c28x_rules_on_a_known_struct():
    """pi_ctrl_t: every field 32-bit -> 2 words each; a uint16 after a 32-bit
    field pads the struct to an even size."""
    L = bench_ram.layout()
    body = "int32_t a; uint16_t b;"
    L.structs["t_pad"] = body
    assert L.struct_size("t_pad") == (4, 2)
    L.structs["t_pack"] = "uint16_t a; uint16_t b; uint16_t c;"
    assert L.struct_size("t_pack") == (3, 1)
    L.structs["t_mid"] = "uint16_t a; int32_t b[2]; uint16_t c;"
    assert L.struct_size("t_mid") == (8, 2)    # a, pad, b (4), c, pad


def test_conditional_fields():
    """A struct's fields under `#if NAME` count when the headers' default of
    NAME is nonzero, not when it is 0 or undefined; `#else` takes the other
    side; a condition that is not a bare name keeps both branches (as the
    parse did before it read conditionals)."""
    text = ("typedef struct {\n    int32_t a;\n#if ON\n    int32_t b;\n#else\n    uint16_t c;\n"
            "#endif\n#if OFF\n    int32_t d;\n#endif\n#if MATH_TYPE == IQ_MATH\n    uint16_t e;\n"
            "#endif\n} t_cond;\n")
    kept = bench_ram.resolve_conditionals(text, {"ON": 1, "OFF": 0})
    names = [n for _t, n, _c, _p in bench_ram.fields(
        kept[kept.index("{") + 1:kept.index("}")], {})]
    assert names == ["a", "b", "e"]
    kept = bench_ram.resolve_conditionals(text, {})
    names = [n for _t, n, _c, _p in bench_ram.fields(
        kept[kept.index("{") + 1:kept.index("}")], {})]
    assert names == ["a", "c", "e"]
