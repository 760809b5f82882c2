#!/usr/bin/env bash
# Runs a command and checks its exit code and that its output (stdout + stderr) matches a regex.
#   expect.sh EXIT_CODE REGEX command [args...]
set -u
want=$1; pattern=$2; shift 2
out=$("$@" 2>&1); got=$?
echo "$out" | tail -5
if [ "$got" != "$want" ]; then echo "FAIL: exit code $got, expected $want"; exit 1; fi
if ! grep -qE -- "$pattern" <<<"$out"; then echo "FAIL: output does not match: $pattern"; exit 1; fi
echo "ok: exit $got and output matches"
