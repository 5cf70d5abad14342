"""What the Python tests share: the data folder, the command line they compare against, and a
scratch folder per test."""

import os
import subprocess
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[3]


def data_file(relative: str) -> Path:
    """A file of the test data (the repository's data/, or $POINTRAY_DATA); a failure, not a
    skip, when it is missing."""
    roots = [Path(os.environ["POINTRAY_DATA"])] if "POINTRAY_DATA" in os.environ else []
    roots.append(REPOSITORY / "data")
    for root in roots:
        if (root / relative).is_file():
            return root / relative
    pytest.fail(f"test data {relative} is missing (looked in {', '.join(map(str, roots))})")


@pytest.fixture
def bunny() -> Path:
    return data_file("points/bunny.ply")


@pytest.fixture
def autzen() -> Path:
    return data_file("scans/autzen_trim.las")


def pointray_cli(*args: str, cwd: Path) -> str:
    """Runs the command line built with the same profile as the package ($POINTRAY_BIN)."""
    binary = os.environ.get("POINTRAY_BIN", str(REPOSITORY / "target" / "release" / "pointray"))
    done = subprocess.run([binary, *map(str, args)], cwd=cwd, capture_output=True, text=True)
    assert done.returncode == 0, f"pointray {' '.join(map(str, args))} failed:\n{done.stdout}{done.stderr}"
    return done.stdout


@pytest.fixture
def ouster_sequence() -> Path:
    """Three consecutive Ouster OS-1-128 sweeps with their poses and sensor metadata."""
    return data_file("scans/real/ouster_os1_128_seq/poses_kitti.txt").parent
