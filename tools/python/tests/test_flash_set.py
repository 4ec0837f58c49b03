"""The ISR path's FLASH set (tools/bench_size.py FLASH_ROOTS): which functions
leave the SARAM (a helper that any RAM function still calls stays in RAM), and
that tools/bench_isr.py charges every line of them the flash's price
(FLASH_FACTOR per line, FLASH_ENTRY per entry) and nothing else."""
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "tools"))
import bench_isr  # noqa: E402
import bench_size  # noqa: E402


def graph(edges, files=None):
    """A bench_size.Graph from {caller: [callees]} (no compile)."""
    g = object.__new__(bench_size.Graph)
    names = set(edges) | {c for cs in edges.values() for c in cs}
    g.func = {n: {"name": n, "tu": "t", "file": str(ROOT / (files or {}).get(n, "src/app/x.c")),
                  "stack": 0, "bytes": 10, "dynamic": False} for n in names}
    g.edges = {k: set(v) for k, v in edges.items()}
    g.byname = {n: [n] for n in names}
    return g


@pytest.fixture
def roots(monkeypatch):
    monkeypatch.setattr(bench_size, "FLASH_ROOTS", {"test_step": "test", "change": "test"})


def test_flash_set_keeps_shared_helpers_in_ram(roots):
    g = graph({
        "isr_control": ["drive_isr"],
        "drive_isr": ["test_step", "svgen_step", "modulate"],
        "test_step": ["judge", "svgen_step"],        # svgen_step: also every period
        "judge": ["unit"],
        "isr_slow": ["drive_slow_task"],
        "drive_slow_task": ["change", "disarm"],
        "disarm": ["test_step"],                     # a second caller of a root
        "change": ["reset"],
        "modulate": [],
    })
    flash = bench_size.flash_set(g)
    assert flash == {"test_step", "judge", "unit", "change", "reset"}
    fast, slow = bench_size.isr_sets(g)
    assert "svgen_step" in fast - flash and "modulate" in fast - flash
    assert {"disarm", "drive_slow_task"} <= slow - flash


def test_fast_in_slow_ram_takes_only_what_its_roots_alone_reach(roots, monkeypatch):
    """FAST_IN_SLOW_RAM: control-ISR code placed in H0 (the slow include) in the
    flash image: its root and what only it reaches; a helper the control ISR
    also calls elsewhere stays in the fast set, and the includes list the moved
    code once per image (#ifndef / #ifdef ISR_RAM_IMAGE)."""
    monkeypatch.setattr(bench_size, "FAST_IN_SLOW_RAM", ("test_period",))
    g = graph({
        "isr_control": ["drive_isr"],
        "drive_isr": ["test_period", "svgen_step", "test_step"],   # test_step: the flash root
        "test_period": ["pulse", "svgen_step"],
        "pulse": ["unit"],
        "isr_slow": ["drive_slow_task"],
        "drive_slow_task": ["change", "disarm"],
        "disarm": ["pulse"],                      # the slow ISR reaches it too: still moved
    })
    assert bench_size.fast_in_slow_ram(g) == {"test_period", "pulse", "unit"}
    fast_txt, slow_txt = bench_size.isr_cmd_texts(g)
    for txt, which in ((fast_txt, "#ifdef ISR_RAM_IMAGE"), (slow_txt, "#ifndef ISR_RAM_IMAGE")):
        block = txt.split(which, 1)[1].split("#endif", 1)[0]
        assert "_test_period)" in block and "_pulse)" in block and "_svgen_step)" not in block
    assert "_svgen_step)" in fast_txt.split("#ifdef ISR_RAM_IMAGE", 1)[0]
    monkeypatch.setattr(bench_size, "FAST_IN_SLOW_RAM", ("nowhere",))
    with pytest.raises(SystemExit, match="nowhere"):
        bench_size.fast_in_slow_ram(g)


def test_flash_root_off_the_isr_path_is_an_error(roots):
    g = graph({"isr_control": ["drive_isr"], "isr_slow": ["drive_slow_task"],
               "drive_isr": ["test_step"], "drive_slow_task": []})
    with pytest.raises(SystemExit, match="change"):
        bench_size.flash_set(g)


def test_firmware_functions_never_leave_ram(roots):
    g = graph({"isr_control": ["drive_isr"], "isr_slow": ["drive_slow_task"],
               "drive_isr": ["test_step"], "test_step": ["hal_pwm_write"],
               "drive_slow_task": ["change"]},
              files={"hal_pwm_write": "firmware/hal_pwm_f2812.c"})
    assert "hal_pwm_write" not in bench_size.flash_set(g)


def test_committed_includes_name_the_flash_set_in_ifdef_blocks():
    """Each generated include ends its RAM list with one ISR_FLASH_SET_IN_RAM
    block; the linker file of the flash image does not define it, the RAM
    image's does."""
    for inc in bench_isr.FLASH_SET_INCLUDES:
        blocks = bench_isr.FLASH_SET_BLOCK.findall((ROOT / inc).read_text())
        assert len(blocks) == 1, inc
    assert "#define ISR_FLASH_SET_IN_RAM" not in (ROOT / "linker/F2812_flash.cmd").read_text()
    assert "#define ISR_FLASH_SET_IN_RAM" in (ROOT / "linker/F2812_ram.cmd").read_text()


def test_flash_lines_cover_each_function_body():
    spans, names = bench_isr.flash_lines()
    assert "id_sequence_step" in names and "flux_obs_step_a" in names
    # the sensor test's pulses run from H0 (FAST_IN_SLOW_RAM), not from flash
    assert "sensor_test_step" not in names and "drive_safety_test_period" not in names
    seq = str(ROOT / "src/app/id_sequence.c")
    src = Path(seq).read_text().splitlines()
    first, last = next((a, b) for a, b in spans[seq] if "id_sequence_step" in src[a - 1])
    assert src[last - 1].startswith("}")
    assert first < last


def test_cost_charges_flash_lines_and_entries_only():
    coster = bench_isr.LineCoster()
    seq = str(ROOT / "src/app/id_sequence.c")
    src = Path(seq).read_text().splitlines()
    a, b = next((a, b) for a, b in coster.flash[seq] if "id_sequence_step" in src[a - 1])
    body = [ln for ln in range(a + 1, b) if coster.ops(seq, ln)]
    ln = next(ln for ln in body if bench_isr.line_cycles(coster.ops(seq, ln)) > 0)
    plain = bench_isr.line_cycles(coster.ops(seq, ln))
    runs = 3
    cost, _mods, _hot = coster.cost({seq: {ln: runs}})
    assert cost == pytest.approx(runs * (plain * bench_isr.FLASH_FACTOR + bench_isr.FLASH_ENTRY))
    # a line of a function in SARAM: its plain cost
    ram = str(ROOT / "src/foc/svgen.c")
    coster.flash.pop(ram, None)
    rsrc = Path(ram).read_text().splitlines()
    rl = next(k for k in range(1, len(rsrc) + 1)
              if coster.ops(ram, k) and bench_isr.line_cycles(coster.ops(ram, k)) > 0)
    cost, _m, _h = coster.cost({ram: {rl: runs}})
    assert cost == pytest.approx(runs * bench_isr.line_cycles(coster.ops(ram, rl)))


def test_static_name_clash_with_the_isr_path_is_an_error():
    """The includes place `.text:_name`: a static of a background file named as
    an ISR-path static of another file would land in RAM uncounted."""
    g = graph({"isr_control": ["drive_isr"], "isr_slow": ["drive_slow_task"],
               "drive_isr": ["update"], "drive_slow_task": ["mean"],
               "bg_loop": ["bg_update", "inline_helper"], "update": ["inline_helper"]},
              files={"inline_helper": "include/helper.h"})
    g.func["bg_update"]["name"] = "update"             # another file's static 'update'
    g.func["bg_update"]["file"] = str(ROOT / "src/app/y.c")
    errs = bench_size.name_clash_problems(g)
    assert len(errs) == 1 and errs[0].startswith("update (src/app/y.c)")
    g.func["bg_update"]["name"] = "update_queued"      # renamed: no clash
    assert bench_size.name_clash_problems(g) == []
