"""Fixtures of the binding's tests: the psh command line (the Rust results the binding
must reproduce: $PSH_BIN, else target/release/psh), the shared data (tests that need it
skip without it), and the convention mappings of the validation suite (validation/)."""

import os
import pathlib
import subprocess

import pytest

from support import DATA, ROOT


@pytest.fixture
def cli(tmp_path):
    """Runs the psh binary with arguments; returns its working directory."""
    binary = pathlib.Path(os.environ.get("PSH_BIN", ROOT / "target" / "release" / "psh"))
    if not binary.is_file():
        pytest.fail(f"no psh binary at {binary} (cargo build --release, or set PSH_BIN)")

    def run(*args):
        subprocess.run([str(binary), *map(str, args)], check=True, cwd=tmp_path,
                       stdout=subprocess.DEVNULL)
        return tmp_path

    return run


@pytest.fixture
def data():
    """The shared polarsh data directory (skips the test when absent)."""
    if not (DATA / "SHVec_sponza_1024_L100.npz").is_file():
        pytest.skip(f"shared data missing: {DATA} (set PSH_DATA_DIR)")
    return DATA
