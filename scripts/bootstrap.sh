#!/usr/bin/env bash
# Create (or reuse) the project venv in .venv and install splinecraft with the given extras.
# Usage: scripts/bootstrap.sh [EXTRAS]   e.g. scripts/bootstrap.sh lab   or   scripts/bootstrap.sh test
# A stamp file .venv/.installed-EXTRAS records each install; it is redone when pyproject.toml is newer.
# The test extra includes lab and app (pyproject.toml), so a venv installed for the tests serves start.sh too.
set -euo pipefail
cd "$(dirname "$0")/.."
extras="${1:-}"
py="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  "$py" -m venv .venv
fi
stamp=".venv/.installed-${extras:-base}"
covering=("$stamp")
case "${extras:-base}" in
  base) covering+=(.venv/.installed-lab .venv/.installed-app .venv/.installed-test) ;;
  lab|app) covering+=(.venv/.installed-test) ;;
esac
for done_stamp in "${covering[@]}"; do
  if [ -f "$done_stamp" ] && [ ! pyproject.toml -nt "$done_stamp" ]; then
    exit 0
  fi
done
.venv/bin/python -m pip install --quiet --upgrade pip
if [ -n "$extras" ]; then
  .venv/bin/python -m pip install --quiet -e ".[${extras}]"
else
  .venv/bin/python -m pip install --quiet -e .
fi
# Compile the numba kernels into their on-disk cache now, so the first trace of a session does not wait
# for it (docs/capture.md, "Compiled kernels"); a failure here only means the first trace compiles them.
.venv/bin/python -c "from splinecraft.capture._jit import warm_up_all; warm_up_all()" || echo "bootstrap: warming the kernel cache failed; the first trace compiles the kernels" >&2
touch "$stamp"
