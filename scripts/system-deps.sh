#!/usr/bin/env bash
# Install Debian packages the project needs for a purpose: browser (chromium), potrace (benchmark peer), the
# fonts of the held-out benchmark sets (fonts: benchmarks/heldout_shapes.py, bench_other_fonts.py).
# Usage: scripts/system-deps.sh chromium potrace fonts
set -euo pipefail
need=()
for pkg in "$@"; do
  case "$pkg" in
    chromium) [ -x /usr/bin/chromium ] || need+=(chromium fonts-dejavu-core) ;;
    potrace) command -v potrace >/dev/null || need+=(potrace) ;;
    fonts) for font in fonts-freefont-ttf fonts-liberation fonts-ebgaramond fonts-ebgaramond-extra fonts-hosny-amiri \
                       fonts-ipafont-mincho; do
             dpkg -s "$font" >/dev/null 2>&1 || need+=("$font")
           done ;;
    *) need+=("$pkg") ;;
  esac
done
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
fi
