#!/usr/bin/env bash
# Ctrl-C (SIGINT) during a long render: wavevcm finishes the iteration in
# flight, writes the image rendered so far, and exits with 130; no partial
# file is left behind.
#   interrupt.sh WAVEVCM WORKDIR
set -u
wavevcm=$1
mkdir -p "$2" && cd "$2" || exit 1
rm -f interrupted.exr render.log
"$wavevcm" render -t 60 --width 64 --height 64 -o interrupted.exr 2> render.log &
pid=$!
# The setup line is printed just before the first iteration starts.
for _ in $(seq 1200); do
  grep -q "setup" render.log && break
  sleep 0.1
done
sleep 1
kill -INT "$pid"
wait "$pid"
status=$?
cat render.log
fail() { echo "FAIL: $*"; exit 1; }
[ "$status" -eq 130 ] || fail "exit status $status, expected 130"
grep -q "interrupted (.*): writing the [0-9]* iterations rendered so far" render.log ||
  fail "no message saying what was written"
"$wavevcm" compare interrupted.exr interrupted.exr > /dev/null || fail "interrupted.exr is not a readable image"
ls -a | grep -q "partial" && fail "a partial file was left"
echo "ok: interrupted render wrote its image and exited with 130"
