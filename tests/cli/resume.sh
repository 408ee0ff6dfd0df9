#!/bin/bash
# SPDX-License-Identifier: MIT
# Kill and resume: `graphslam incremental` (or drivebot) with checkpoints is killed with SIGKILL at random
# moments (after a checkpoint of its own), resumed from its last checkpoint (run again from the start when none was written
# yet) until it finishes, and its outputs (the window's graph, the marginalised vertices,
# the final chi2) must equal those of an uninterrupted run bit for bit. Then corrupt,
# truncated and foreign checkpoints are refused naming what is wrong (exit 2).
# Usage: resume.sh TOOL WORK CASE   (CASE: window | full | drivebot)
t=$1
o=$2
case_name=$3
rm -rf "$o" && mkdir -p "$o" && cd "$o" || exit 1
fail() { echo "FAILED: $*"; exit 1; }

case "$case_name" in
window)
  "$t" simulate --poses 20000 --landmarks 100 --seed 5 -o in.g2o > /dev/null || fail simulate
  flags=(--window 50 --marginalised-out out.txt --checkpoint ck --checkpoint-every 500) ;;
full)
  "$t" simulate --poses 1500 --landmarks 30 --seed 6 -o in.g2o > /dev/null || fail simulate
  flags=(--checkpoint ck --checkpoint-every 100) ;;
drivebot)
  flags=() ;;
*) fail "unknown case $case_name" ;;
esac
run=("$t" incremental in.g2o -q --refine 1e-6 -o out.g2o "${flags[@]}")
# drivebot: a fixed-lag smoother over a simulated drive, its outputs in res/ (steps.csv
# compared without its two timing columns).
[ "$case_name" = drivebot ] && run=("$t" drivebot --scenario q2_c --sensors gps,laser
  --optimize-every 1 --seed 4 --out res -q --window 100 --window-slack 20 --keep-landmarks
  --marginalised-out out.txt --checkpoint ck --checkpoint-every 300)
collect() {
  [ "$case_name" = drivebot ] || return 0
  [ -e res/final.g2o ] || return 0
  cp res/final.g2o out.g2o && cut -d, -f1-20,23- res/steps.csv > out.steps && rm -rf res
}

# The uninterrupted run.
"${run[@]}" > ref.log || fail "reference run"
collect
[ ! -e out.steps ] || mv out.steps ref.steps
mv out.g2o ref.g2o
[ ! -e out.txt ] || mv out.txt ref.txt
grep -E "^(final chi2|after refine)" ref.log | sed "s| in [0-9.]* s||" > ref.chi2

kills=0 resumes=0
for attempt in $(seq 1 3); do
  rm -rf out.g2o out.txt out.steps ck res
  args=()
  # Three kills at random moments (each after the run has written a checkpoint of its own,
  # so that every kill can be resumed from; then 0-250 ms later), each run resumed from the
  # checkpoint the last one left, then a run to the end.
  for round in 1 2 3 4; do
    before=$(stat -c %i ck 2> /dev/null)
    "${run[@]}" "${args[@]}" > run.log 2>&1 &
    pid=$!
    if [ "$round" -lt 4 ]; then
      while kill -0 "$pid" 2> /dev/null && [ "$(stat -c %i ck 2> /dev/null)" = "$before" ]; do
        sleep 0.01
      done
      sleep "0.$(printf '%03d' $((RANDOM % 250)))"
      if kill -9 "$pid" 2> /dev/null; then
        wait "$pid" 2> /dev/null
        kills=$((kills + 1))
        if [ -e ck ]; then args=(--resume ck); resumes=$((resumes + 1)); else args=(); fi
        continue
      fi
    fi
    wait "$pid" || { cat run.log; fail "attempt $attempt round $round: the run failed"; }
    break
  done
  collect
  [ -e out.g2o ] || fail "attempt $attempt: no output"
  [ ! -e ref.steps ] || cmp -s out.steps ref.steps ||
    fail "attempt $attempt: steps.csv differs from the uninterrupted run's"
  cmp -s out.g2o ref.g2o || fail "attempt $attempt: out.g2o differs from the uninterrupted run's"
  [ ! -e ref.txt ] || cmp -s out.txt ref.txt ||
    fail "attempt $attempt: the marginalised vertices differ from the uninterrupted run's"
  grep -E "^(final chi2|after refine)" run.log | sed "s| in [0-9.]* s||" | cmp -s - ref.chi2 || fail "attempt $attempt: the final chi2 differs"
done
echo "killed $kills runs, resumed $resumes times; every finished run equals the uninterrupted one"
[ "$resumes" -gt 0 ] || fail "no run was resumed from a checkpoint"

if [ "$case_name" = drivebot ]; then
  # A checkpoint of a run with other settings, or of a replay, is refused.
  out=$("${run[@]}" --laser-range 12 --resume ck 2>&1) && fail "resumed with another laser range"
  echo "$out" | grep -q "ck: checkpoint refused: it was written by a run with other settings" ||
    fail "another laser range: $out"
  "$t" simulate --poses 300 --seed 1 -o replay.g2o > /dev/null &&
    "$t" incremental replay.g2o -q --no-batch --checkpoint replay.ck --checkpoint-every 100 > /dev/null ||
    fail "replay for a foreign checkpoint"
  out=$("${run[@]}" --resume replay.ck 2>&1) && fail "resumed from an incremental replay's checkpoint"
  echo "$out" | grep -q "replay.ck: checkpoint refused" || fail "replay checkpoint: $out"
  echo "checkpoints of other runs refused"
  exit 0
fi

# Refusals: exit 2 and a message naming the file and what is wrong.
refused() {
  want=$1; shift
  out=$("${run[@]}" --resume "$@" 2>&1); rc=$?
  [ $rc -eq 2 ] && echo "$out" | grep -q -- "$want" || { echo "$out"; fail "resume $*: expected '$want'"; }
}
cp ck good.ck
size=$(stat -c %s good.ck)
head -c $((size - 9)) good.ck > cut.ck
refused "cut.ck: checkpoint refused: truncated" cut.ck
cp good.ck flipped.ck
printf '\x55' | dd of=flipped.ck bs=1 seek=$((size / 2)) conv=notrunc 2> /dev/null
refused "flipped.ck: checkpoint refused: checksum mismatch" flipped.ck
refused "in.g2o: checkpoint refused: not a graphslam checkpoint" in.g2o
refused "missing.ck: cannot open the checkpoint" missing.ck
echo "corrupt, truncated and foreign checkpoints refused"
