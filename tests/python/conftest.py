"""Shared fixtures of the Python-module tests: where the sources and the CLI
are (ctest sets CHATTER_SOURCE_DIR and CHATTER_CLI; PYTHONPATH=build/python)."""
import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("CHATTER_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("CHATTER_CLI", str(SOURCE_DIR / "build" / "chatter"))
# The lobe configs (configs/grinding_*.toml are grinding configs: test_grinding.py).
CONFIGS = sorted(c for c in (SOURCE_DIR / "configs").glob("*.toml") if not c.name.startswith("grinding_"))
GRINDING_CONFIGS = sorted((SOURCE_DIR / "configs").glob("grinding_*.toml"))


def run_cli(*args, cwd=None):
    """Runs the chatter CLI; returns (exit status, stdout, stderr)."""
    p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    return p.returncode, p.stdout, p.stderr


def cli_error_lines(stderr):
    """The CLI's error message: its 'chatter: ' lines without the prefix."""
    return [l[len("chatter: "):] for l in stderr.splitlines() if l.startswith("chatter: ")]


def cli_json(*args):
    status, out, err = run_cli(*args)
    assert status in (0, 3), f"chatter {' '.join(map(str, args))}: exit {status}: {err}"
    return json.loads(out)


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE_DIR
