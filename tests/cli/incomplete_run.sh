#!/usr/bin/env bash
# A run whose second increment cannot converge: exit code 2, status "incomplete", and the converged
# first step kept intact in every output file.
set -u
exe=$1; deck=$2; dir=$3
rm -rf "$dir"
"$exe" run "$deck" --output "$dir"; code=$?
fail() { echo "FAIL: $*"; exit 1; }
[ "$code" = 2 ] || fail "exit code $code, expected 2"
grep -q "^incomplete: stopped at T = 0.02 after 1 converged steps" "$dir/status.txt" || fail "status: $(cat "$dir/status.txt")"
[ "$(wc -l < "$dir/steps.csv")" = 2 ] || fail "steps.csv should hold the header and one step"
[ "$(wc -l < "$dir/tracked_points.csv")" = 2 ] || fail "tracked_points.csv should hold the header and one step"
[ -f "$dir/vtk/step_00001.vtu" ] || fail "the converged step's VTK file is missing"
grep -q 'file="vtk/step_00001.vtu"' "$dir/results.pvd" || fail "results.pvd does not list step 1"
echo "ok: incomplete run kept its converged step"
