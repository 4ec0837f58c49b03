"""The cost rules of tools/bench_isr.py corrected when every ISR path was sampled, on lines of
C whose price is known by hand: the C28x's / and % are calls of the run-time
library in flash (SPRACN6 Table 4: up to 64 cycles for 32-bit operands, x2
from flash + a cold prefetch), a division by a constant power of two is a
shift, a constant expression is folded; _IQatan2PU at TI's own benchmark
(127 with its tables in the boot ROM); a line no sample ran is priced as
run once.  Each assertion fails on the model before those corrections."""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "tools"))
import bench_isr  # noqa: E402

RTS = 64 * 2 + 12          # one division from flash


def ops(code):
    return bench_isr.count_line(code, set())


def test_variable_division_is_a_runtime_call_from_flash():
    c = ops("uint32_t mean = (sum + ((uint32_t)n >> 1)) / (uint32_t)n;")
    assert c["div_rts"] == 1 and c["div_pow2"] == 0
    # the rest of the line: =, +, >> at 2 each; the division at its call's price
    assert bench_isr.line_cycles(c) == 3 * 2 + RTS


def test_modulo_by_a_variable_is_a_runtime_call():
    assert ops("p %= n;")["div_rts"] == 1
    assert bench_isr.line_cycles(ops("p %= n;")) == RTS


def test_64_bit_division_at_the_worst_of_tis_range():
    c = ops("k = (int32_t)(((int64_t)1 << 40) / (int64_t)t);")
    assert c["div_rts64"] == 1
    assert bench_isr.line_cycles(c) >= 2635 * 2


def test_division_by_a_power_of_two_is_a_shift():
    assert ops("return (y - b) / 2 + b;")["div_pow2"] == 1
    # through a macro: DRIVE_SLOTS = (1u << DRIVE_SLOTS_LOG2) = 8
    c = ops("d->i_t_step = (d->pi_speed.out - d->i_t_ref) / (int32_t)DRIVE_SLOTS;")
    assert c["div_pow2"] == 1 and c["div_rts"] == 0
    # a constant that is not a power of two: the library
    assert ops("z = w % DRIVE_SLOTS_LOG2;")["div_rts"] == 1
    assert ops("q = a / (2 + n);")["div_rts"] == 1


def test_constant_division_is_folded():
    c = ops("cx = _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 12.0));")
    assert c["div_rts"] == c["div_pow2"] == c["div_rts64"] == 0


def test_flash_factor_not_applied_to_the_library_twice():
    c = ops("uint32_t mean = (sum + ((uint32_t)n >> 1)) / (uint32_t)n;")
    assert bench_isr.line_cycles(c, in_flash=True) == 3 * 2 * bench_isr.FLASH_FACTOR + RTS


def test_iqmath_at_tis_benchmarks():
    # IQNatan2PU.asm: 127 cycles with the tables in the 1-wait boot ROM
    assert bench_isr.iq_op_cycles("_IQatan2PU") == 127
    # the library calls at their sources' worst case, never below
    for op, ti in (("_IQmpyI32int", 28), ("_IQmpyI32frac", 34), ("_IQint", 15),
                   ("_IQfrac", 18), ("_IQatan2", 115), ("_IQsinPU", 41), ("_IQdiv", 62)):
        assert bench_isr.iq_op_cycles(op) >= ti, op


def test_a_line_no_sample_ran_is_priced_once(tmp_path):
    src = tmp_path / "cal.c"
    src.write_text("static uint16_t mean_of(uint32_t sum, uint16_t n)\n"
                   "{\n"
                   "    uint32_t mean = (sum + ((uint32_t)n >> 1))\n"
                   "                    / (uint32_t)n;\n"
                   "    return (uint16_t)mean;\n"
                   "}\n")
    coster = bench_isr.LineCoster()
    # in RAM: the statement (its continuation line asked) once
    p = bench_isr.price_line(coster, str(src), 4)
    assert p["where"].endswith("cal.c:3") and p["cycles"] == 3 * 2 + RTS
    # in the flash set: its own operations x2, the entry, the call as it is
    coster.flash[str(src)] = [(1, 6)]
    p = bench_isr.price_line(coster, str(src), 3)
    assert p["cycles"] == 3 * 2 * bench_isr.FLASH_FACTOR + bench_isr.FLASH_ENTRY + RTS
