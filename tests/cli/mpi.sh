#!/usr/bin/env bash
# `mpirun -n 2 wavevcm render` (host/cluster), on this machine's cores:
#   mpi.sh WAVEVCM MPIEXEC WORKDIR same_image ALG  2 ranks: the image of one process (same seed, same iterations)
#   mpi.sh WAVEVCM MPIEXEC WORKDIR checkpoint      2 ranks, -t with --checkpoint: images on the way, stats per rank
#   mpi.sh WAVEVCM MPIEXEC WORKDIR failing_rank    rank 1 cannot start: the job ends at once, naming it
#   mpi.sh WAVEVCM MPIEXEC WORKDIR interrupt       Ctrl-C on mpirun: the image so far is written
set -u
wavevcm=$1 mpiexec=$2
mkdir -p "$3" && cd "$3" || exit 1
test=$4
fail() { echo "FAIL: $*"; exit 1; }
# As root (CI) OpenMPI wants to be told; two ranks may share fewer cores.
mpirun=("$mpiexec" --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun+=(--allow-run-as-root)
small=(--width 48 --height 48)

case "$test" in
same_image)
  alg=$5
  rm -f one-$alg.exr two-$alg.exr
  "$wavevcm" render -a "$alg" -n 9 --seed 4 "${small[@]}" -q -o one-$alg.exr || fail "one process failed"
  "${mpirun[@]}" -n 2 "$wavevcm" render -a "$alg" -n 9 --seed 4 "${small[@]}" -o two-$alg.exr --stats two-$alg.json ||
    fail "mpirun failed"
  # Rank 0 sums the ranks' means × counts in double, one process keeps one
  # float running mean: they differ by float rounding, relMSE ~1e-14; a rank
  # that repeated another's iterations, or a wrong weight, gives noise (> 1e-4).
  "$wavevcm" compare two-$alg.exr one-$alg.exr --max-relmse 1e-10 || fail "2 ranks differ from one process"
  grep -q '"ranks": 2' two-$alg.json || fail "stats: no \"ranks\": 2"
  grep -q '"iterations": 9' two-$alg.json || fail "stats: the job's 9 iterations are not counted"
  echo "ok: 2 ranks give the image of one process ($alg)"
  ;;
checkpoint)
  rm -f cp.exr cp.json cp.log
  "${mpirun[@]}" -n 2 "$wavevcm" render -a pt -t 4 --checkpoint 1 "${small[@]}" -o cp.exr --stats cp.json 2> cp.log ||
    { cat cp.log; fail "mpirun failed"; }
  cat cp.log
  grep -q "checkpoint after .*iterations -> cp.exr" cp.log || fail "no checkpoint written"
  "$wavevcm" compare cp.exr cp.exr > /dev/null || fail "cp.exr is not a readable image"
  /usr/bin/python3 - <<'PY' || fail "stats"
import json
s = json.load(open("cp.json"))
ranks = s["rank_stats"]
assert s["ranks"] == 2 and len(ranks) == 2, s["ranks"]
assert all(r["iterations"] > 0 for r in ranks), ranks
assert s["iterations"] == sum(r["iterations"] for r in ranks), (s["iterations"], ranks)
assert s["render_seconds"] < 4 + 2, s["render_seconds"]  # the job's budget, plus an iteration
PY
  echo "ok: checkpoints written, each rank's share in the stats"
  ;;
failing_rank)
  # Rank 1 asks for a device that does not exist; rank 0 would render for a minute.
  start=$(date +%s)
  timeout 60 "${mpirun[@]}" -n 1 "$wavevcm" render -a pt -t 60 "${small[@]}" -o fail.exr : \
    -n 1 "$wavevcm" render -a pt -t 60 "${small[@]}" -o fail.exr -d nosuchdevice > fail.log 2>&1
  status=$?
  took=$(($(date +%s) - start))
  cat fail.log
  [ "$status" -ne 0 ] || fail "mpirun exited 0"
  [ "$status" -ne 124 ] || fail "the job hung (killed by timeout after 60 s)"
  [ "$took" -lt 30 ] || fail "the job took $took s to end"
  grep -q "rank 1 of 2 .*no device matches 'nosuchdevice'" fail.log || fail "no message naming rank 1 and its error"
  echo "ok: a failing rank ended the job in $took s with its message"
  ;;
interrupt)
  rm -f int.exr int.log
  # Checkpoints every second tell when an iteration has finished: before it,
  # the ranks may still be compiling kernels (PoCL builds work-group
  # functions at first launch, seconds on a cold cache), which no signal
  # interrupts, and mpirun sends SIGKILL a second after SIGINT.
  "${mpirun[@]}" -n 2 "$wavevcm" render -a vcm -t 120 --checkpoint 1 --width 256 --height 256 -o int.exr 2> int.log &
  pid=$!
  for _ in $(seq 1200); do grep -q "checkpoint after" int.log && break; sleep 0.1; done
  grep -q "checkpoint after" int.log || { kill -KILL "$pid"; cat int.log; fail "no checkpoint in 120 s"; }
  kill -INT "$pid"
  wait "$pid"
  cat int.log
  written=$(sed -n 's/.*interrupted (.*): writing the \([0-9]*\) iterations rendered so far.*/\1/p' int.log)
  [ -n "$written" ] || fail "no message saying what was written"
  checkpointed=$(sed -n 's/.*checkpoint after .*: \([0-9]*\) iterations.*/\1/p' int.log | tail -1)
  [ "$written" -ge "$checkpointed" ] || fail "wrote $written iterations, fewer than the checkpoint's $checkpointed"
  "$wavevcm" compare int.exr int.exr > /dev/null || fail "int.exr is not a readable image"
  echo "ok: Ctrl-C on mpirun wrote the image rendered so far"
  ;;
*)
  fail "unknown test $test"
  ;;
esac
