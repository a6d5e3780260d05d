#!/usr/bin/env bash
# Install splinecraft into .venv and start the main job.
#   scripts/start.sh                 JupyterLab on notebooks/
#   scripts/start.sh trace IN -o OUT  headless: trace bitmaps to SVG/JSON from the command line
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/bootstrap.sh lab
if [ "${1:-lab}" = "lab" ]; then
  [ $# -gt 0 ] && shift
  exec .venv/bin/jupyter lab --notebook-dir=notebooks "$@"
fi
exec .venv/bin/splinecraft "$@"
