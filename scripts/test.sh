#!/usr/bin/env bash
# Install everything the tests need (venv, Debian chromium) and run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/system-deps.sh chromium
bash scripts/bootstrap.sh test
exec .venv/bin/python -m pytest "$@"
