#!/usr/bin/env bash
# Install Debian packages the project needs for a purpose: browser (chromium), potrace (benchmark peer).
# Usage: scripts/system-deps.sh chromium potrace
set -euo pipefail
need=()
for pkg in "$@"; do
  case "$pkg" in
    chromium) [ -x /usr/bin/chromium ] || need+=(chromium fonts-dejavu-core) ;;
    potrace) command -v potrace >/dev/null || need+=(potrace) ;;
    *) need+=("$pkg") ;;
  esac
done
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
fi
