#!/usr/bin/env bash
# Install splinecraft into .venv and start the main job.
#   bash scripts/start.sh [JUPYTER-LAB-OPTIONS]       JupyterLab on notebooks/ (e.g. --no-browser --port 8890)
#   bash scripts/start.sh notebook [OPTIONS]          the same notebooks in the simpler Notebook 7 interface
#   bash scripts/start.sh app [NOTEBOOK] [OPTIONS]    classroom view (Voila): the notebooks as apps, code hidden
#   bash scripts/start.sh trace IN... -o OUT          headless: trace bitmaps to SVG/JSON from the command line
#   bash scripts/start.sh trace --help                all trace options
# As root (user id 0: a container, a lab machine) JupyterLab and Notebook get --allow-root, and say so.
set -euo pipefail
cd "$(dirname "$0")/.."
command="${1:-}"
case "$command" in
  -h|--help|help)
    sed -n '2,8p' "$0" | sed 's/^# //'
    exit 0 ;;
  app)
    shift
    bash scripts/bootstrap.sh app
    # The first argument names what to serve when it is not an option: a notebook or a folder.
    target=notebooks
    if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
      target="$1"
      shift
    fi
    exec .venv/bin/voila "$target" "$@" ;;
esac
bash scripts/bootstrap.sh lab
case "$command" in
  trace|--version)
    exec .venv/bin/splinecraft "$@" ;;
esac
frontend=lab
if [ "$command" = notebook ]; then
  frontend=notebook
  shift
fi
# Jupyter servers refuse to run as root unless told to.
as_root=()
if [ "$(id -u)" = 0 ]; then
  as_root=(--allow-root)
  echo "start.sh: running as root (user id 0), so Jupyter $frontend is started with --allow-root" >&2
fi
# The install enables splinecraft's TCP_NODELAY server extension (jupyter-config/): drags answer ~2x faster.
exec .venv/bin/jupyter "$frontend" --notebook-dir=notebooks "${as_root[@]}" "$@"
