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

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${PACKAGES[@]}"; do
  if ! installed "$p"; then
    missing+=("$p")
  fi
done
# VTK for Python (reading results back, render): any package that provides the module will do:
# python3-vtk9, or ParaView's python3-paraview (installed with paraview; it has its own vtk module and
# conflicts with python3-vtk9). Where python3-paraview is installed, python3-vtk9 is never asked for.
vtk_note="Python's vtk module importable"
if ! /usr/bin/python3 -c "import vtk" >/dev/null 2>&1; then
  vtk_note="but not Python's vtk module"
  if installed python3-paraview; then
    echo "setup: python3-paraview is installed but /usr/bin/python3 cannot import its vtk module;" \
         "python3-vtk9 conflicts with it and is not installed; reinstall it" \
         "(apt-get install --reinstall python3-paraview): until then render and the VTK tests fail" >&2
  else
    missing+=(python3-vtk9)
  fi
elif installed python3-paraview; then
  echo "setup: Python's vtk module from python3-paraview (ParaView's; python3-vtk9 is not needed)"
fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all packages present ($vtk_note)"
  exit 0
fi

echo "setup: installing ${missing[*]} (apt's progress follows)"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
# Only what is missing is asked for, and --no-remove: apt stops with an error instead of removing a
# package of yours to make room (this script never removes a package).
$SUDO apt-get install -y --no-install-recommends --no-remove -o Dpkg::Progress-Fancy=0 "${missing[@]}"
echo "setup: done"
