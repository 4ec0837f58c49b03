import sys
from pathlib import Path

import pytest

TOOLS = Path(__file__).resolve().parents[2]   # tools/
sys.path.insert(0, str(TOOLS))                # batch_ls.py, bench_ram.py


@pytest.fixture(scope="session")
def paper_run():
    """One closed-loop identification of the paper's motor (2.5 s simulated,
    ~4 s wall), shared by the tests that check its results."""
    from imfoc import example
    return example.run(duration_s=2.5)
