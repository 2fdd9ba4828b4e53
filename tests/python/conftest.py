"""Shared fixtures of the Python module's tests: the CLI to compare with, the samples, and a
run of `gradmesh` that returns its exit code and standard error."""

import os
import pathlib
import subprocess

import pytest

SAMPLES = pathlib.Path(os.environ.get("GRADMESH_SAMPLES", pathlib.Path(__file__).parents[2] / "samples"))
EXE = os.environ.get("GRADMESH_EXE", "")

# Small budgets: each conversion takes about a second, and the CLI's is the same conversion.
FAST = {"max_patches": 60, "max_error": 6}
FAST_ARGS = ["--max-patches", "60", "--max-error", "6"]


def run_cli(*args):
    """Runs `gradmesh ARGS`; returns (exit code, standard error)."""
    assert EXE and os.path.exists(EXE), "GRADMESH_EXE must name the built gradmesh"
    p = subprocess.run([EXE, *map(str, args)], capture_output=True, text=True, timeout=600)
    return p.returncode, p.stderr


def cli_message(*args):
    """The CLI's error message for a failing run, without its "gradmesh <command>: " prefix."""
    code, err = run_cli(*args)
    assert code != 0, f"gradmesh {' '.join(map(str, args))} did not fail"
    line = err.strip().splitlines()[-1]
    prefix = f"gradmesh {args[0]}: "
    assert line.startswith(prefix), line
    return line[len(prefix):]


@pytest.fixture
def apple():
    return SAMPLES / "apple.jpg", SAMPLES / "apple_mask.png"
