#!/usr/bin/env bash
# The external cross-validation suite: sets up validation/.venv (setup.sh), runs the
# pytest checks against the psh binary ($PSH_BIN, else target/release/psh; this script
# builds nothing), prints the table and writes docs/validation.md.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
cd "$root"

bash "$here/setup.sh"

psh_bin="${PSH_BIN:-$root/target/release/psh}"
case "$psh_bin" in /*) ;; *) psh_bin="$root/$psh_bin" ;; esac
if [ ! -x "$psh_bin" ]; then
  echo "validation/run.sh: no psh binary at $psh_bin (cargo build --release --bin psh, or set PSH_BIN)" >&2
  exit 2
fi
export PSH_BIN="$psh_bin"

results="$here/.results.json"
rm -f "$results"
start=$(date +%s)
set +e
PYTHONDONTWRITEBYTECODE=1 "$here/.venv/bin/python" -m pytest "$here" -q -p no:cacheprovider \
  --rootdir "$here" -o console_output_style=classic
status=$?
set -e
echo "validation/run.sh: pytest exited $status after $(( $(date +%s) - start )) s"
if [ ! -f "$results" ]; then
  echo "validation/run.sh: pytest wrote no results" >&2
  exit 1
fi
report_status=0
"$here/.venv/bin/python" "$here/report.py" "$results" "$root/docs/validation.md" || report_status=$?
# pytest's 5 (no tests collected) is a failure too.
if [ "$status" -ne 0 ] || [ "$report_status" -ne 0 ]; then
  exit 1
fi
