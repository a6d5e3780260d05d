#!/usr/bin/env bash
# Install splinecraft into .venv and start the main job.
#   bash scripts/start.sh [JUPYTER-LAB-OPTIONS]     JupyterLab on notebooks/ (e.g. --no-browser --port 8890)
#   bash scripts/start.sh trace IN... -o OUT        headless: trace bitmaps to SVG/JSON from the command line
#   bash scripts/start.sh trace --help              all trace options
# As root (user id 0: a container, a lab machine) the Jupyter server gets --allow-root, and says so.
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  -h|--help|help)
    sed -n '2,6p' "$0" | sed 's/^# //'
    exit 0 ;;
esac
bash scripts/bootstrap.sh lab
case "${1:-}" in
  trace|--version)
    exec .venv/bin/splinecraft "$@" ;;
esac
# Jupyter servers refuse to run as root unless told to.
as_root=()
if [ "$(id -u)" = 0 ]; then
  as_root=(--allow-root)
  echo "start.sh: running as root (user id 0), so JupyterLab is started with --allow-root" >&2
fi
# The install enables splinecraft's TCP_NODELAY server extension (jupyter-config/): drags answer ~2x faster.
exec .venv/bin/jupyter lab --notebook-dir=notebooks "${as_root[@]}" "$@"
