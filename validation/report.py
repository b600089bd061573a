"""Prints the table of a validation run and writes docs/validation.md.

Usage: report.py RESULTS_JSON OUTPUT_MD
Exit status 1 when any check failed or a test failed without a row.
"""

import datetime
import json
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent


def git(*args):
    try:
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "?"


def fmt(x):
    return f"{x:.2e}"


def main(results_path, out_path):
    results = json.loads(pathlib.Path(results_path).read_text())
    rows = list(results["rows"])
    outcomes = results["outcomes"]
    # A test that failed (or errored) is a failed row, whether or not it recorded one.
    with_rows = {r["test"] for r in rows}
    for r in rows:
        if outcomes.get(r["test"]) == "failed":
            r["passed"] = False
    # A test skipped for missing shared data, or where Dr.Jit's LLVM backend does not run
    # (test_mitsuba_envmap.py; packages are installed), is listed as skipped, neither
    # passed nor failed.
    for test, outcome in sorted(outcomes.items()):
        if test not in with_rows and outcome != "passed":
            rows.append({"test": test, "check": f"{test} ({outcome}, no figure)",
                         "anchor": "-", "version": "-", "measure": "-",
                         "measured": float("nan"), "tolerance": float("nan"),
                         "passed": False, "skipped": outcome == "skipped", "detail": ""})
    skipped = [r for r in rows if r.get("skipped")]
    rows = [r for r in rows if not r.get("skipped")]
    failed = [r for r in rows if not r["passed"]]
    skip_text = "".join(f"; skipped (shared data or LLVM backend missing): {r['test']}"
                        for r in skipped)

    def cell(text):
        return str(text).replace("|", "\\|")

    lines = ["| check | anchor | measure | measured | tolerance | result |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        anchor = f"{r['anchor']} {r['version']}" if r["anchor"] != "-" else "-"
        measure = r["measure"] + (f" ({r['detail']})" if r["detail"] else "")
        lines.append(f"| {cell(r['check'])} | {anchor} | {cell(measure)} | {fmt(r['measured'])} | "
                     f"{fmt(r['tolerance'])} | {'pass' if r['passed'] else '**FAIL**'} |")
    table = "\n".join(lines)

    width = max(len(r["check"]) for r in rows)
    print()
    print(f"{'check':<{width}}  {'anchor':<18} {'measured':>9} {'tolerance':>9}  result")
    for r in rows:
        anchor = f"{r['anchor']} {r['version']}"
        print(f"{r['check']:<{width}}  {anchor:<18} {fmt(r['measured']):>9} "
              f"{fmt(r['tolerance']):>9}  {'pass' if r['passed'] else 'FAIL'}")

    versions = ", ".join(f"{k} {v}" for k, v in results["versions"].items())
    commit = git("rev-parse", "--short", "HEAD")
    dirty = " (with uncommitted changes)" if git("status", "--porcelain", "--untracked-files=no") else ""
    doc = f"""# External cross-validation

psh against the field's independent Python packages: every figure below compares numbers
psh printed (`psh eval ...`) with numbers an anchor package computed, after the
convention mapping stated in the second part. Written by `bash validation/run.sh`
(`validation/setup.sh` makes the virtual environment `validation/.venv`; the checks are
`validation/test_*.py`, the mappings `validation/mappings.py`). Each tolerance is set from
the measured figure and the precision of the two methods; the reasoning is in the
comment above each check in the test files.

- Run: {datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}, psh commit {commit}{dirty},
  {len(rows)} checks in {results['seconds']:.0f} s (pytest), Python {results['python']}
  on {results['platform']}.
- Anchors: {versions}.
- Result: {len(rows) - len(failed)} passed, {len(failed)} failed{skip_text}.

{table}

"""
    doc += (HERE / "conventions.md").read_text()
    pathlib.Path(out_path).write_text(doc)
    print(f"\nwrote {out_path}")
    print(f"validation: {len(rows) - len(failed)} passed, {len(failed)} failed, "
          f"{len(skipped)} skipped")
    return 1 if failed or not rows else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
