#!/usr/bin/env bash
# A rank killed mid-render (SIGKILL: the out-of-memory killer, a node lost) must end every rank
# within a bounded time, with a non-zero status, the output as it was before and nothing left
# beside it. Open MPI's launcher sees the death and ends the job; this test holds it to that.
# Usage: killed_rank.sh MPIEXEC "MPIEXEC_FLAGS" SPHRAY_MPI WORK_DIR DISTRIBUTION VICTIM_RANK
set -u
mpiexec=$1 flags=$2 sphray_mpi=$3 dir=$4 distribution=$5 victim=$6
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
echo "an earlier image" >out.ppm
# rtiow-final path traced at 4096 samples per pixel: minutes, so the kill lands mid-render.
# shellcheck disable=SC2086
$mpiexec $flags -n 2 "$sphray_mpi" render -q -s rtiow-final -m path --spp 4096 -W 160 -H 90 \
  --distribution "$distribution" -o out.ppm &
launcher=$!

# The launcher's children, from /proc (no procps on a minimal system): field 4 of stat is the
# parent's pid (the command name, field 2, has no spaces here).
children() {
  local stat
  for stat in /proc/[0-9]*/stat; do
    read -r pid_ _ _ ppid_ _ <"$stat" 2>/dev/null && [ "$ppid_" = "$1" ] && echo "$pid_"
  done
}

# The victim: the launcher's child whose environment names it rank $victim (Open MPI sets
# OMPI_COMM_WORLD_RANK in each rank's).
pid=
for _ in $(seq 300); do
  for child in $(children "$launcher"); do
    if tr '\0' '\n' <"/proc/$child/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$victim"; then
      pid=$child
    fi
  done
  [ -n "$pid" ] && break
  sleep 0.1
done
[ -n "$pid" ] || { echo "FAIL: rank $victim never started"; kill -KILL "$launcher"; exit 1; }
sleep 2  # the ranks are tracing by now (the tree of 486 spheres takes milliseconds)
kill -KILL "$pid"
killed=$(date +%s)

for _ in $(seq 600); do
  kill -0 "$launcher" 2>/dev/null || break
  sleep 0.1
done
if kill -0 "$launcher" 2>/dev/null; then
  echo "FAIL: the job still runs 60 s after rank $victim was killed"
  for child in $(children "$launcher"); do kill -KILL "$child"; done
  kill -KILL "$launcher"
  exit 1
fi
wait "$launcher"
status=$?
echo "the job ended $(($(date +%s) - killed)) s after rank $victim was killed, status $status"
[ "$status" -ne 0 ] || { echo "FAIL: status 0"; exit 1; }
[ "$(cat out.ppm)" = "an earlier image" ] || { echo "FAIL: out.ppm changed"; exit 1; }
left=$(ls -A | grep -v '^out\.ppm$')
[ -z "$left" ] || { echo "FAIL: left behind: $left"; exit 1; }
echo "PASS"
