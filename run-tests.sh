#!/usr/bin/env bash
# Quick start 2: installs what is needed, builds, and runs the whole test suite (unit, regression
# and the 2-rank MPI cases) with CTest.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bash "$here/cmake/build.sh"
cd "$here/build"
ctest --output-on-failure "$@"
