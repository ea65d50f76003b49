"""Shared fixtures: the `hedra` command (HEDRA_BIN from ctest, else build/cli/hedra) and the
repository's example scene."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CITY = str(ROOT / "examples" / "city-block.json")


def hedra_bin():
    return os.environ.get("HEDRA_BIN", str(ROOT / "build" / "cli" / "hedra"))


def run_cli(*args, check=True):
    """Runs the command; returns (exit code, stdout, stderr)."""
    p = subprocess.run([hedra_bin(), *map(str, args)], capture_output=True, text=True, timeout=120)
    if check and p.returncode != 0:
        raise AssertionError(f"hedra {' '.join(map(str, args))} failed: {p.stderr}")
    return p.returncode, p.stdout, p.stderr


@pytest.fixture(scope="session")
def city_path():
    return CITY


@pytest.fixture(scope="session")
def city():
    import hedra
    return hedra.read(CITY)


L_OUTLINE = [[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [0, 3]]
