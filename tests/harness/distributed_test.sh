#!/usr/bin/env bash
# quick.toml run three ways beyond the serial run: on 3 MPI ranks (mpirun --oversubscribe), and in
# 3 shards merged. Each report must be the serial one record by record, times aside
# (compare_reports.py), and `pldamp diff` must find no change. Then a rank killed mid-run (kill -9)
# and a SIGINT to mpirun: a non-zero exit, no report, no hang.
#   tests/harness/distributed_test.sh PLDAMP MPIEXEC SCENE_DIR
set -euo pipefail
pldamp=$1 mpiexec=$2 scenes=$3
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
root=()
[[ $(id -u) -ne 0 ]] || root=(--allow-run-as-root) # CI runs as root; Open MPI refuses it unasked
mpi=("$mpiexec" "${root[@]}" --oversubscribe)
# In a container without ptrace rights Open MPI's shared-memory transport cannot copy a large
# message (a chunk's records) in one go; its copy through a buffer works everywhere.
export OMPI_MCA_btl_vader_single_copy_mechanism=none

same_as_serial() { # same_as_serial DIR WHAT
  # The report files only: the records' file rank 0 and merge keep is unlinked as it is made.
  [[ $(ls -A "$1" | sort | tr '\n' ' ') == "report.csv report.html report.json report.md " ]] ||
    { ls -la "$1" >&2; echo "$2: the folder holds more than the reports" >&2; exit 1; }
  python3 "$here/compare_reports.py" "$work/serial/report.json" "$1/report.json" ||
    { echo "$2: the report differs from the serial one" >&2; exit 1; }
  # Times are not compared: 3 ranks share 2 cores in CI (--time-floor: no time is judged).
  "$pldamp" diff --time-floor 86400 "$work/serial/report.json" "$1/report.json" >"$work/diff.txt" ||
    { cat "$work/diff.txt" >&2; echo "$2: pldamp diff found a regression" >&2; exit 1; }
  grep -q '^0 regressions, 0 changes' "$work/diff.txt" ||
    { cat "$work/diff.txt" >&2; echo "$2: pldamp diff found changes" >&2; exit 1; }
}

"$pldamp" run "$scenes/quick.toml" --out "$work/serial" --jobs 1 >/dev/null

"${mpi[@]}" -n 3 "$pldamp" run "$scenes/quick.toml" --out "$work/mpi" --jobs 1 >"$work/mpi.out"
# One process prints: one plan line and one summary, not three.
[[ $(grep -c 'solver runs' "$work/mpi.out") -eq 2 ]] ||
  { cat "$work/mpi.out" >&2; echo "mpirun -n 3: expected rank 0's lines only" >&2; exit 1; }
same_as_serial "$work/mpi" "mpirun -n 3"
echo "mpirun -n 3: the serial report"

for k in 1 2 3; do
  "$pldamp" run "$scenes/quick.toml" --shard "$k/3" --out "$work/shard-$k" --jobs 1 >/dev/null
done
"$pldamp" merge "$work/shard-3" "$work/shard-1" "$work/shard-2" --out "$work/merged" --jobs 1 \
  >/dev/null
same_as_serial "$work/merged" "3 shards merged"
echo "3 shards merged: the serial report"

# A long run (the dem scene, ~15 s on 3 ranks), ended early. Waits for the ranks to be solving.
interrupted() { # interrupted WHAT: starts the run in the background; $run is mpirun's pid
  rm -rf "$work/$1"
  "${mpi[@]}" -n 3 "$pldamp" run "$scenes/dem.toml" --out "$work/$1" --jobs 1 \
    >"$work/$1.out" 2>"$work/$1.err" &
  run=$!
  for _ in $(seq 100); do
    grep -q 'solver runs' "$work/$1.out" 2>/dev/null && break
    sleep 0.1
  done
  sleep 1
}
ended_cleanly() { # ended_cleanly WHAT: mpirun ends within 60 s, non-zero, and no report exists
  local status=0
  for _ in $(seq 600); do
    kill -0 "$run" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$run" 2>/dev/null; then
    kill -9 "$run"
    echo "$1: mpirun still ran 60 s later (a hang)" >&2
    exit 1
  fi
  wait "$run" || status=$?
  ((status != 0)) || { echo "$1: exit status 0" >&2; exit 1; }
  [[ -z $(ls -A "$work/$1") ]] || { ls -la "$work/$1" >&2; echo "$1: a file was left" >&2; exit 1; }
  echo "$1: exit status $status, no report"
}

interrupted killed
# The rank-1 process: the pldamp whose environment says OMPI_COMM_WORLD_RANK=1.
victim=""
for pid in $(pgrep -f "pldamp run $scenes/dem.toml" || true); do
  if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
    victim=$pid
  fi
done
[[ -n $victim ]] || { echo "killed: rank 1 not found" >&2; kill -9 "$run"; exit 1; }
kill -9 "$victim"
ended_cleanly killed

interrupted interrupted
kill -INT "$run"
# mpirun passes the signal on as SIGTERM to every rank, which stops as a serial run does. (Rank 0's
# "stopped by a signal" line is often lost: mpirun stops forwarding output as it ends the job.)
ended_cleanly interrupted
