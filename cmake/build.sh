#!/usr/bin/env bash
# Installs the Debian packages the project needs (quick when present), configures and builds.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/cmake/setup-debian.sh"
cmake -S "$here" -B "$here/build" -DCMAKE_BUILD_TYPE=Release > "$here/build-configure.log" 2>&1 \
  || { cat "$here/build-configure.log"; exit 1; }
cmake --build "$here/build" -j "$(nproc)"
