#!/usr/bin/env bash
# Install splinecraft into .venv and start the main job.
#   bash scripts/start.sh [JUPYTER-LAB-OPTIONS]     JupyterLab on notebooks/ (e.g. --no-browser --port 8890)
#   bash scripts/start.sh trace IN... -o OUT        headless: trace bitmaps to SVG/JSON from the command line
#   bash scripts/start.sh trace --help              all trace options
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/bootstrap.sh lab
case "${1:-}" in
  trace|--version)
    exec .venv/bin/splinecraft "$@" ;;
  -h|--help|help)
    sed -n '2,5p' "$0" | sed 's/^# //'
    exit 0 ;;
esac
# The install enables splinecraft's TCP_NODELAY server extension (jupyter-config/): drags answer ~2x faster.
exec .venv/bin/jupyter lab --notebook-dir=notebooks "$@"
