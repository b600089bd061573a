#!/usr/bin/env bash
# Creates validation/.venv (python3 -m venv) and installs the anchors of
# requirements.txt into it. Idempotent: a venv that already satisfies the requirements
# is left as it is (pip then only checks them).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="$here/.venv"
python="${PYTHON:-python3}"

if [ ! -x "$venv/bin/python" ]; then
  echo "validation/setup.sh: creating $venv"
  "$python" -m venv "$venv"
fi
# A venv whose pip can't run (e.g. a broken copy) is made again.
if ! "$venv/bin/python" -m pip --version >/dev/null 2>&1; then
  echo "validation/setup.sh: recreating $venv (pip does not run)"
  rm -rf "$venv"
  "$python" -m venv "$venv"
fi

stamp="$venv/.requirements.sha256"
want="$(sha256sum "$here/requirements.txt" | cut -d' ' -f1)"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] \
   && "$venv/bin/python" -c "import numpy, pytest, spherical, quaternionic, sphericart, ducc0, mpmath, mitsuba, drjit" 2>/dev/null; then
  echo "validation/setup.sh: $venv is up to date"
  exit 0
fi

export PIP_DISABLE_PIP_VERSION_CHECK=1
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -r "$here/requirements.txt"
# Every anchor must import: a missing one is an error, never a skipped check.
"$venv/bin/python" - <<'PY'
import importlib, importlib.metadata
for name in ["numpy", "pytest", "spherical", "quaternionic", "sphericart", "ducc0", "mpmath", "mitsuba", "drjit"]:
    importlib.import_module(name)
    print(f"  {name} {importlib.metadata.version(name)}")
PY
echo "$want" > "$stamp"
echo "validation/setup.sh: $venv ready"
