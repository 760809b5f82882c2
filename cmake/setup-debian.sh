#!/usr/bin/env bash
# Installs what BeamContact needs from Debian's packages. Idempotent: when everything is present it
# only checks and returns (a second or two). It never removes a package you have: the Python VTK
# module is wanted, not a particular package, so a machine with ParaView's VTK (python3-paraview,
# which conflicts with python3-vtk9) keeps it; apt is asked to install nothing it would have to
# remove something for.
set -euo pipefail

PACKAGES=(
  build-essential cmake
  trilinos-all-dev libptscotch-dev libscotch-dev
  libopenmpi-dev openmpi-bin
  libsuitesparse-dev libopenblas0-serial   # UMFPACK, with an optimized BLAS for its dense kernels
  libmumps-dev   # MUMPS, the parallel Direct Solver (also a dependency of trilinos-all-dev)
  zlib1g-dev   # the VTK files' compression (Output/VTK Compression)
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-numpy python3-matplotlib
  procps util-linux   # pgrep, prlimit: the fault tests
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# VTK for Python (reading results back, render): any package that provides the module will do.
if ! /usr/bin/python3 -c "import vtk" >/dev/null 2>&1; then
  missing+=(python3-vtk9)
fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all packages present (Python's vtk module importable)"
  exit 0
fi

echo "setup: installing ${missing[*]} (apt's progress follows)"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
# --no-remove: apt stops with an error instead of removing a package of yours to make room.
$SUDO apt-get install -y --no-install-recommends --no-remove -o Dpkg::Progress-Fancy=0 "${missing[@]}"
echo "setup: done"
