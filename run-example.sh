#!/usr/bin/env bash
# Quick start 1: installs what is needed, builds, and runs the example deck on one rank.
# Usage: ./run-example.sh [DECK.xml]   (default: input/example1.xml, the seed paper's Example 1)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bash "$here/cmake/build.sh"
deck="${1:-$here/input/example1.xml}"
name="$(basename "$deck" .xml)"
"$here/build/drivers/beamcontact" run "$deck" --output "$here/results/$name"
echo "results: $here/results/$name (status.txt, tracked_points.csv with points A and B, contact_points.csv, reactions.csv, steps.csv, results.pvd and contact.pvd for ParaView)"
