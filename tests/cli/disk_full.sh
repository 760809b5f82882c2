#!/usr/bin/env bash
# A run whose results do not fit: a file size limit (set with prlimit once the run has started, so MPI
# starts normally; a write past it fails like one on a full disk) must end the run with exit 2, a
# one-line error naming the file and the reason, and status.txt saying "failed: ..."; every CSV holds
# whole lines only.
set -u
exe=$1; deck=$2; dir=$3
rm -rf "$dir"
"$exe" run "$deck" --output "$dir" --quiet > "$dir.log" 2>&1 &
pid=$!
for _ in $(seq 200); do [ -s "$dir/status.txt" ] && break; sleep 0.02; done
prlimit --pid "$pid" --fsize=40000 || { echo "FAIL: prlimit"; exit 1; }
wait "$pid"; code=$?
out=$(cat "$dir.log")
fail() { echo "FAIL: $*"; echo "$out" | tail -3; exit 1; }
[ "$code" = 2 ] || fail "exit code $code, expected 2"
grep -qE "output error: cannot write $dir/[a-z_./0-9]+: File too large" <<<"$out" || fail "message: $out"
[ "$(echo "$out" | grep -c beamcontact:)" = 1 ] || fail "more than one error line"
grep -q "^failed: cannot write .*File too large" "$dir/status.txt" || fail "status: $(cat "$dir/status.txt")"
[ ! -e "$dir/summary.csv" ] || fail "summary.csv written for a failed run"
for f in "$dir"/*.csv; do
  [ -z "$(tail -c1 "$f")" ] || fail "$f ends mid-line"
done
echo "ok: exit 2, $(grep beamcontact: <<<"$out")"
echo "status: $(cat "$dir/status.txt")"
