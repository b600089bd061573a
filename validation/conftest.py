"""Shared fixtures of the external cross-validation suite.

`psh` runs the psh binary (`$PSH_BIN`, else `target/release/psh`): psh's numbers come
only from it. `record` adds a row (check, anchor package, measured figure, tolerance) to
the table of `docs/validation.md`; a test passes only if every row it recorded is within
its tolerance, and a test that records nothing fails (a check must assert something).
"""

import importlib.metadata
import json
import os
import pathlib
import platform
import subprocess
import time

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
RESULTS = pathlib.Path(
    os.environ.get("PSH_VALIDATION_RESULTS", ROOT / "validation" / ".results.json")
)

_rows = []
_outcomes = {}
_started = time.time()


def psh_binary():
    path = pathlib.Path(os.environ.get("PSH_BIN") or ROOT / "target" / "release" / "psh")
    if not path.is_absolute():
        path = ROOT / path
    return path


class Psh:
    """The psh command line: JSON on stdout, big arrays through .npy files."""

    def __init__(self, binary, tmp):
        self.binary = str(binary)
        self.tmp = pathlib.Path(tmp)
        self.calls = 0

    def run(self, *args):
        self.calls += 1
        args = [str(a) for a in args]
        p = subprocess.run([self.binary, *args], capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"psh {' '.join(args)} failed ({p.returncode}): {p.stderr.strip()}")
        return json.loads(p.stdout)

    def values(self, *args):
        """Runs psh and returns the "values" array of its JSON as a float array (pairs
        [re, im] as a last axis of 2), parsed by numpy: `json` would need gigabytes for the
        16.8 million pairs of `psh eval sh --lmax 4096`."""
        self.calls += 1
        args = [str(a) for a in args]
        p = subprocess.run([self.binary, *args], capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"psh {' '.join(args)} failed ({p.returncode}): {p.stderr.strip()}")
        text = p.stdout
        start = text.index('"values":') + len('"values":')
        pairs = text[start:].lstrip().startswith("[[")
        end = text.index("]]" if pairs else "]", start) + (2 if pairs else 1)
        v = np.fromstring(text[start:end].translate(str.maketrans("[]", "  ")), sep=",")
        return v.reshape(-1, 2) if pairs else v

    def path(self, name):
        return self.tmp / name

    def save(self, name, array):
        path = self.path(name)
        np.save(path, np.ascontiguousarray(array, dtype=np.float64))
        return path

    def npy(self, *args, out):
        """Runs psh with `--output out` and returns (JSON, the array written)."""
        path = self.path(out)
        meta = self.run(*args, "--output", path)
        return meta, np.load(path)


@pytest.fixture(scope="session")
def psh(tmp_path_factory):
    binary = psh_binary()
    if not os.access(binary, os.X_OK):
        pytest.exit(
            f"no psh binary at {binary}: build it (cargo build --release --bin psh) "
            "or set PSH_BIN",
            returncode=2,
        )
    return Psh(binary, tmp_path_factory.mktemp("psh"))


def version(package):
    return importlib.metadata.version(package)


class Recorder:
    def __init__(self, nodeid):
        self.nodeid = nodeid
        self.rows = []

    def __call__(self, check, anchor, measured, tolerance, measure="max abs error", detail=""):
        """Records one comparison; `measured` and `tolerance` are non-negative figures,
        the check passes when measured <= tolerance (NaN fails)."""
        measured = float(measured)
        row = {
            "test": self.nodeid,
            "check": check,
            "anchor": anchor,
            "version": version(anchor),
            "measure": measure,
            "measured": measured,
            "tolerance": float(tolerance),
            "passed": bool(measured <= tolerance),
            "detail": detail,
        }
        self.rows.append(row)
        _rows.append(row)
        return row["passed"]


@pytest.fixture
def record(request):
    rec = Recorder(request.node.nodeid)
    yield rec
    if getattr(request.node, "_call_failed", True) or getattr(request.node, "_call_skipped", False):
        return  # the test itself failed, never ran or was skipped: that is its report
    assert rec.rows, f"{request.node.nodeid} recorded no comparison"
    failed = [r for r in rec.rows if not r["passed"]]
    assert not failed, "\n".join(
        f"{r['check']}: {r['measure']} {r['measured']:.3e} > tolerance {r['tolerance']:.1e}"
        for r in failed
    )


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    rep = outcome.get_result()
    if rep.when == "call":
        item._call_failed = rep.failed
        item._call_skipped = rep.skipped


def pytest_runtest_logreport(report):
    if report.failed:
        _outcomes[report.nodeid] = "failed"
    elif report.when == "call" and report.nodeid not in _outcomes:
        _outcomes[report.nodeid] = "skipped" if report.skipped else "passed"
    elif report.skipped:
        _outcomes.setdefault(report.nodeid, "skipped")


def pytest_sessionfinish(session, exitstatus):
    packages = ["numpy", "pytest", "spherical", "quaternionic", "sphericart", "ducc0",
                "mpmath", "mitsuba", "drjit"]
    RESULTS.write_text(json.dumps({
        "rows": _rows,
        "outcomes": _outcomes,
        "exitstatus": int(exitstatus),
        "seconds": time.time() - _started,
        "python": platform.python_version(),
        "platform": platform.platform(),
        "psh": str(psh_binary()),
        "versions": {p: version(p) for p in packages},
    }, indent=1))
