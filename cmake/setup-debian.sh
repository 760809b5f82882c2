#!/usr/bin/env bash
# Installs everything BeamContact needs from Debian's packages. Idempotent: when every package is
# already installed it only checks and returns (a second or two).
set -euo pipefail

PACKAGES=(
  build-essential cmake
  trilinos-all-dev libptscotch-dev libscotch-dev
  libopenmpi-dev openmpi-bin
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-vtk9 python3-numpy python3-matplotlib
  procps util-linux   # pgrep, prlimit: the fault tests
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
