#!/usr/bin/env bash
# quick.toml run three ways beyond the serial run: on 3 MPI ranks (mpirun --oversubscribe), and in
# 3 shards merged; paper.toml's claims and search on 3 ranks. Each report must be the serial one
# record by record, times aside (compare_reports.py), and `pldamp diff` must find no change. Then a rank killed mid-run (kill -9)
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

same_as_serial() { # same_as_serial DIR WHAT [SERIAL_DIR]
  local serial=${3:-$work/serial}
  # The report files only: the records' file rank 0 and merge keep is unlinked as it is made.
  [[ $(ls -A "$1" | sort | tr '\n' ' ') == "report.csv report.html report.json report.md " ]] ||
    { ls -la "$1" >&2; echo "$2: the folder holds more than the reports" >&2; exit 1; }
  python3 "$here/compare_reports.py" "$serial/report.json" "$1/report.json" ||
    { echo "$2: the report differs from the serial one" >&2; exit 1; }
  # Times are not compared: 3 ranks share 2 cores in CI (--time-floor: no time is judged).
  "$pldamp" diff --time-floor 86400 "$serial/report.json" "$1/report.json" >"$work/diff.txt" ||
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

# The seed's claims, of every kind, on grids of their own and ten times denser, and its search
# (a group per p): the ranks judge them together, each piece once (run/workers.hpp).
"$pldamp" run "$scenes/paper.toml" --out "$work/paper-serial" --jobs 1 >/dev/null
"${mpi[@]}" -n 3 "$pldamp" run "$scenes/paper.toml" --out "$work/paper-mpi" --jobs 1 >/dev/null
same_as_serial "$work/paper-mpi" "paper.toml on 3 ranks" "$work/paper-serial"
echo "paper.toml on 3 ranks: the serial report"

# A rank that reads another scene (a node whose copy of the file differs: here one v0 changed,
# through mpirun's per-rank commands) is refused before any work, with exit code 2 and no report.
sed 's/^v0 = \[0.1, /v0 = [0.2, /' "$scenes/quick.toml" >"$work/quick-v0.toml"
! cmp -s "$scenes/quick.toml" "$work/quick-v0.toml" || { echo "quick.toml's v0 moved" >&2; exit 1; }
status=0
"${mpi[@]}" -n 1 "$pldamp" run "$scenes/quick.toml" --out "$work/mixed" --jobs 1 : \
  -n 1 "$pldamp" run "$work/quick-v0.toml" --out "$work/mixed" --jobs 1 >/dev/null \
  2>"$work/mixed.err" || status=$?
((status == 2)) && grep -q '^error: rank 1: this rank read another scene' "$work/mixed.err" &&
  [[ -z $(ls -A "$work/mixed") ]] ||
  { cat "$work/mixed.err" >&2; echo "another scene on rank 1: not refused (exit $status)" >&2; exit 1; }
echo "another scene on rank 1: refused"

# A scene's error reads as in a serial run (FILE:LINE: what), said once, exit code 2.
printf 'name = "broken"\n[grid]\np = [0.5]\ne = [0.5]\nv0 = [1.0]\n[[solver]]\nname = "cvode-bdf"\n' \
  >"$work/broken.toml"
status=0
"$pldamp" run "$work/broken.toml" --out "$work/broken" 2>"$work/broken-serial.err" || status=$?
((status == 2)) && grep -qx "$work/broken.toml:3: p must be in \[1, 1000\] (got 0.5)" \
  "$work/broken-serial.err" || { cat "$work/broken-serial.err" >&2; echo "serial: not refused" >&2; exit 1; }
status=0
"${mpi[@]}" -n 2 "$pldamp" run "$work/broken.toml" --out "$work/broken" --jobs 1 \
  2>"$work/broken-mpi.err" || status=$?
((status == 2)) && [[ $(grep -cxF -f "$work/broken-serial.err" "$work/broken-mpi.err") -eq 1 ]] ||
  { cat "$work/broken-mpi.err" >&2; echo "a scene's error under mpirun: not the serial line once" >&2; exit 1; }
echo "a scene's error under mpirun: the serial line, once"

for k in 1 2 3; do
  "$pldamp" run "$scenes/quick.toml" --shard "$k/3" --out "$work/shard-$k" --jobs 1 >/dev/null
done
"$pldamp" merge "$work/shard-3" "$work/shard-1" "$work/shard-2" --out "$work/merged" --jobs 1 \
  >/dev/null
same_as_serial "$work/merged" "3 shards merged"
echo "3 shards merged: the serial report"

# A grid that takes a while (3 360 Taylor contacts in 50 digits: about 10 s on 3 ranks sharing 2
# cores), ended early: once rank 0 has records (its first progress line), while the ranks solve.
long=$work/long.toml
cat >"$long" <<'SCENE'
name = "long"
want = ["e", "delta_max", "tau"]
[grid]
p = [1.5, 2.5]
e = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95]
v0 = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5,
      4.0, 4.5, 5.0, 5.5, 6.0, 6.5, 7.0, 7.5, 8.0, 8.5, 9.0, 9.5, 10.0, 11.0, 12.0,
      13.0, 14.0, 15.0, 16.0, 17.0, 18.0, 19.0, 20.0, 21.0, 22.0, 23.0, 24.0, 25.0, 26.0, 27.0,
      28.0, 29.0, 30.0, 31.0, 32.0, 33.0, 34.0, 35.0, 36.0, 37.0, 38.0, 39.0, 40.0, 41.0, 42.0,
      43.0, 44.0, 45.0, 46.0, 47.0, 48.0, 49.0, 50.0, 51.0, 52.0, 53.0, 54.0, 55.0, 56.0, 57.0,
      58.0, 59.0, 60.0, 61.0, 62.0, 63.0, 64.0, 65.0, 66.0, 67.0, 68.0, 69.0, 70.0, 71.0, 72.0,
      73.0, 74.0, 75.0, 76.0, 77.0, 78.0, 79.0, 80.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0, 87.0,
      88.0, 89.0, 90.0, 91.0, 92.0, 93.0, 94.0, 95.0, 96.0, 97.0, 98.0, 99.0, 100.0, 101.0, 102.0,
      103.0, 104.0, 105.0, 106.0, 107.0, 108.0, 109.0, 110.0, 111.0, 112.0, 113.0, 114.0, 115.0,
      116.0, 117.0, 118.0, 119.0, 120.0, 121.0, 122.0, 123.0, 124.0, 125.0, 126.0, 127.0, 128.0,
      129.0, 130.0, 131.0, 132.0, 133.0, 134.0, 135.0, 136.0, 137.0, 138.0, 139.0, 140.0, 141.0,
      142.0, 143.0, 144.0, 145.0, 146.0, 147.0, 148.0, 149.0, 150.0]
[[solver]]
name = "taylor"
precision = "50"
[report]
formats = ["json"]
SCENE
interrupted() { # interrupted WHAT: starts the run in the background; $run is mpirun's pid
  rm -rf "$work/$1" "$work/$1".status.*
  # Each rank's own exit status in WHAT.status.RANK (mpirun's is one rank's, whichever failed
  # first). With $2 = each-rank-ends, mpirun does not end the job at the first non-zero status, so
  # that every rank ends by itself and says how (a rank killed -9 would then hang the others).
  local abort=true
  [[ ${2:-} != each-rank-ends ]] || abort=false
  OMPI_MCA_orte_abort_on_non_zero_status=$abort "${mpi[@]}" -n 3 sh -c 'code=0; "$0" run "$1" --out "$2" --jobs 1 || code=$?
    echo "$code" >"$3.status.$OMPI_COMM_WORLD_RANK"; exit "$code"' \
    "$pldamp" "$long" "$work/$1" "$work/$1" >"$work/$1.out" 2>"$work/$1.err" &
  run=$!
  for _ in $(seq 300); do # until rank 0 has records (its first progress line)
    grep -q ' records, ' "$work/$1.err" 2>/dev/null && break
    sleep 0.1
  done
}
ended_cleanly() { # ended_cleanly WHAT [each-rank-ends]: mpirun ends within 60 s, non-zero, no report
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
  # (told to let each rank end, mpirun exits 0 whatever they did: their statuses say it)
  [[ ${2:-} == each-rank-ends ]] || ((status != 0)) || { echo "$1: exit status 0" >&2; exit 1; }
  [[ -z $(ls -A "$work/$1") ]] || { ls -la "$work/$1" >&2; echo "$1: a file was left" >&2; exit 1; }
  echo "$1: exit status $status, no report"
}

rank_one() { # the rank-1 process: the pldamp whose environment says OMPI_COMM_WORLD_RANK=1
  victim=""
  for pid in $(pgrep -f "pldamp run $long" || true); do
    if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
      victim=$pid
    fi
  done
  [[ -n $victim ]] || { echo "rank 1 not found" >&2; kill -9 "$run"; exit 1; }
}

interrupted killed
rank_one
kill -9 "$victim"
ended_cleanly killed

# SIGTERM to one rank alone: the run stops on every rank and exits 143, as a serial run does (it
# exited 130, SIGINT's code, from the ranks that learnt of the stop from another).
interrupted terminated each-rank-ends
rank_one
kill -TERM "$victim"
ended_cleanly terminated each-rank-ends
for rank in 0 1 2; do
  code=$(cat "$work/terminated.status.$rank" 2>/dev/null || echo none)
  [[ $code == 143 ]] || { echo "terminated: rank $rank exited $code, not 143" >&2; exit 1; }
done

interrupted interrupted
kill -INT "$run"
# mpirun passes the signal on as SIGTERM to every rank, which stops as a serial run does. (Rank 0's
# "stopped by a signal" line is often lost: mpirun stops forwarding output as it ends the job.)
ended_cleanly interrupted
# ... but no rank may take the stop for a failure (rank 0 once read the records it never got).
! grep -q 'error: internal' "$work/interrupted.err" ||
  { cat "$work/interrupted.err" >&2; echo "interrupted: an internal error" >&2; exit 1; }
