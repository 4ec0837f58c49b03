"""Docs that cannot drift (README.md, docs/*.md, BENCHMARKS.md).

1. Every fenced ```sh / ```bash block runs, as one bash script (`set -euo
   pipefail`), from the repository root, within TIMEOUT_S.  The host build
   must exist (tools/run_tests.sh builds it before the Python tests).  A block
   is skipped, with its reason printed, when the line before its fence is

       <!-- slow: REASON -->     (longer than a test should wait)
       <!-- board-only -->       (cl2000, UniFlash, a real serial port: REASON
       <!-- board-only: REASON -->  optional)

2. Every results table between

       <!-- table: COMMAND; tol=X[; slow: REASON] -->
       ...
       <!-- /table -->

   is COMMAND's output (run by bash from the repository root): the text
   between the numbers must be equal, line by line (blank lines and trailing
   spaces ignored), and every number within X of the committed one (the
   generator's noise; counts compare exactly as long as X < 1).  A generator
   marked slow is skipped with its reason.

3. The front door stays a front door: README.md at most 150 lines, the two
   commands in it, .ci/run calling the test command, and no issue-number
   references in the tree.

    .venv/bin/python tools/python/tests/test_docs.py --update   # rewrite every table
    .venv/bin/python tools/python/tests/test_docs.py --update --skip-slow   # all but the slow ones
"""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
TIMEOUT_S = 60
DOCS = [ROOT / "README.md", ROOT / "BENCHMARKS.md"] + sorted((ROOT / "docs").glob("*.md"))

FENCE = re.compile(r"^\s*```(\w*)\s*$")
SKIP = re.compile(r"^<!--\s*(slow|board-only)\s*(?::\s*(.*?))?\s*-->\s*$")
TABLE_OPEN = re.compile(r"^<!--\s*table:\s*(.*?)\s*-->\s*$")
TABLE_CLOSE = re.compile(r"^<!--\s*/table\s*-->\s*$")
NUMBER = re.compile(r"[+-]?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?")


def shell_blocks(path):
    """(line of the fence, kind of skip or None, reason, script) of every
    sh/bash block of path."""
    lines = path.read_text().splitlines()
    out, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m or not m.group(1):
            i += 1
            continue
        lang, start = m.group(1), i
        j = i + 1
        while j < len(lines) and not FENCE.match(lines[j]):
            j += 1
        if lang in ("sh", "bash"):
            prev = lines[start - 1] if start > 0 else ""
            s = SKIP.match(prev.strip())
            kind, reason = (s.group(1), s.group(2) or "") if s else (None, "")
            if kind == "board-only" and not reason:
                reason = "needs TI's tools or a board"
            out.append((start + 1, kind, reason, "\n".join(lines[start + 1:j]) + "\n"))
        i = j + 1
    return out


def parse_table_marker(text):
    """'CMD; tol=X; slow: R' -> (cmd, tol, slow reason or None)."""
    parts = [p.strip() for p in text.split(";")]
    cmd, tol, slow = parts[0], None, None
    for p in parts[1:]:
        if p.startswith("tol="):
            tol = float(p[4:])
        elif p.startswith("slow:"):
            slow = p[5:].strip()
        else:
            raise ValueError(f"unknown table option '{p}'")
    if tol is None:
        raise ValueError(f"table '{cmd}' states no tol=")
    return cmd, tol, slow


def tables(path):
    """(line of the marker, cmd, tol, slow, committed text, first and last
    content line index) of every marked table of path."""
    lines = path.read_text().splitlines()
    out, i = [], 0
    while i < len(lines):
        m = TABLE_OPEN.match(lines[i].strip())
        if not m:
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not TABLE_CLOSE.match(lines[j].strip()):
            j += 1
        if j == len(lines):
            raise ValueError(f"{path}:{i + 1}: table marker without <!-- /table -->")
        cmd, tol, slow = parse_table_marker(m.group(1))
        out.append((i + 1, cmd, tol, slow, "\n".join(lines[i + 1:j]), i + 1, j))
        i = j + 1
    return out


def split_numbers(text):
    """Lines without blank ones -> [(skeleton, [numbers])]."""
    rows = []
    for line in text.splitlines():
        line = line.rstrip()
        if not line:
            continue
        rows.append((NUMBER.sub("#", line), [float(x) for x in NUMBER.findall(line)]))
    return rows


def compare_tables(committed, generated, tol):
    """The differences beyond tol, as messages (empty: the same table)."""
    a, b = split_numbers(committed), split_numbers(generated)
    if len(a) != len(b):
        return [f"{len(a)} rows committed, the tool printed {len(b)}"]
    diffs = []
    for n, ((sa, na), (sb, nb)) in enumerate(zip(a, b), 1):
        if sa != sb or len(na) != len(nb):
            diffs.append(f"row {n}: committed '{sa}', tool '{sb}'")
            continue
        for x, y in zip(na, nb):
            if abs(x - y) > tol + 1e-12:
                diffs.append(f"row {n}: committed {x}, tool {y} (tol {tol})")
    return diffs


def run_generator(cmd):
    p = subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, text=True,
                       timeout=TIMEOUT_S * 5)
    # a generator may exit 1 to say a row is above its bound: the table still stands
    if p.returncode not in (0, 1) or not p.stdout.strip():
        raise AssertionError(f"'{cmd}' exited {p.returncode}:\n{p.stderr[-2000:]}")
    return "\n".join(l for l in p.stdout.splitlines() if l.startswith("|"))


def _rel(path):
    return str(path.relative_to(ROOT))


BLOCKS = [pytest.param(path, line, kind, reason, script, id=f"{_rel(path)}:{line}")
          for path in DOCS if path.exists() for line, kind, reason, script in shell_blocks(path)]
TABLES = [pytest.param(path, line, cmd, tol, slow, text, id=f"{_rel(path)}:{line}")
          for path in DOCS if path.exists()
          for line, cmd, tol, slow, text, _, _ in tables(path)]


@pytest.mark.parametrize("path, line, kind, reason, script", BLOCKS)
def test_shell_block_runs(path, line, kind, reason, script):
    where = f"{_rel(path)}:{line}"
    if kind:
        print(f"skipped {where} ({kind}: {reason})")
        pytest.skip(f"{where}: {kind}: {reason}")
    try:
        p = subprocess.run(["bash", "-c", "set -euo pipefail\n" + script], cwd=ROOT,
                           capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{where}: longer than {TIMEOUT_S} s: mark it <!-- slow: reason --> "
                    f"or make it shorter:\n{script}")
    assert p.returncode == 0, (f"{where} exited {p.returncode}:\n{script}\n"
                               f"stdout: {p.stdout[-1500:]}\nstderr: {p.stderr[-1500:]}")


@pytest.mark.parametrize("path, line, cmd, tol, slow, text", TABLES)
def test_table_is_the_tools_output(path, line, cmd, tol, slow, text):
    where = f"{_rel(path)}:{line}"
    if slow:
        print(f"skipped {where} ({cmd}: slow: {slow})")
        pytest.skip(f"{where}: {cmd}: slow: {slow}")
    diffs = compare_tables(text, run_generator(cmd), tol)
    assert not diffs, (f"{where}: the table differs from `{cmd}` beyond tol {tol} "
                       f"(rewrite: .venv/bin/python tools/python/tests/test_docs.py --update):\n"
                       + "\n".join(diffs))


def test_docs_have_commands_and_tables():
    assert len(BLOCKS) >= 10 and len(TABLES) >= 3


def test_readme_is_a_front_door():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 150
    for cmd in ("tools/run_identification.sh", "tools/run_tests.sh"):
        assert f"`{cmd}`" in text
    for link in re.findall(r"\]\(((?:docs/)?[\w./-]+\.md)", text):
        assert (ROOT / link).exists(), link
    assert re.search(r"^tools/run_tests\.sh\b", (ROOT / ".ci" / "run").read_text(), re.M)


def test_doc_links_resolve():
    for path in DOCS:
        for link in re.findall(r"\]\(([\w./-]+\.md)(?:#[\w-]*)?\)", path.read_text()):
            assert (path.parent / link).resolve().exists(), f"{_rel(path)}: {link}"


def test_no_issue_numbers():
    p = subprocess.run(["git", "grep", "-niIE", r"issue ?[0-9]", "--", "*.c", "*.h", "*.py",
                        "*.md"], cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 1 and not p.stdout, "name the feature, not the issue:\n" + p.stdout


# -- the checker's own checks -------------------------------------------------

def test_markers_parse(tmp_path):
    doc = tmp_path / "x.md"
    doc.write_text("a\n<!-- slow: ten minutes -->\n```sh\nsleep 600\n```\n"
                   "<!-- board-only -->\n```bash\ncl2000 -v28\n```\n```sh\necho ok\n```\n"
                   "```text\nnot a command\n```\n"
                   "<!-- table: echo '| a | 1.00 |'; tol=0.1; slow: long -->\n| a | 1.0 |\n"
                   "<!-- /table -->\n")
    b = shell_blocks(doc)
    assert [(k, r) for _, k, r, _ in b] == [("slow", "ten minutes"),
                                           ("board-only", "needs TI's tools or a board"),
                                           (None, "")]
    assert b[2][3] == "echo ok\n"
    t = tables(doc)
    assert len(t) == 1 and t[0][1:4] == ("echo '| a | 1.00 |'", 0.1, "long")
    with pytest.raises(ValueError):
        parse_table_marker("cmd")


def test_compare_tolerance():
    assert not compare_tables("| a | +1.00 % | 3 |", "| a | +1.04 % | 3 |", 0.05)
    assert compare_tables("| a | +1.00 % | 3 |", "| a | +1.06 % | 3 |", 0.05)
    assert compare_tables("| a | 1 | published |", "| a | 1 | low_confidence |", 0.05)
    assert compare_tables("| a | 1 |", "| a | 1 |\n| b | 2 |", 0.05)
    assert compare_tables("| a | 3 |", "| a | 4 |", 0.05)   # counts: exact


def update(skip_slow=False):
    """Rewrite every marked table with its generator's output (slow ones too,
    unless skip_slow: those marked slow are left as they are)."""
    for path in DOCS:
        if not path.exists():
            continue
        found = tables(path)
        if not found:
            continue
        lines = path.read_text().splitlines()
        for _, cmd, _, slow, _, first, last in reversed(found):
            if slow and skip_slow:
                print(f"{_rel(path)}: {cmd}: slow, kept", file=sys.stderr)
                continue
            print(f"{_rel(path)}: {cmd}", file=sys.stderr)
            lines[first:last] = run_generator(cmd).splitlines()
        path.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    if sys.argv[1:] in (["--update"], ["--update", "--skip-slow"]):
        update(skip_slow=sys.argv[2:] == ["--skip-slow"])
    else:
        sys.exit(pytest.main([__file__, "-q", "-rs"] + sys.argv[1:]))
