#!/usr/bin/env bash
# Strong scaling of a scene's run (docs/scaling.md): the serial run, then mpirun with 1, 2 and 4
# ranks (4 oversubscribed on a 2-core machine), each the fastest of REPEATS, with every rank's
# peak memory.
#     bench/scaling.sh [BUILD] [SCENE] [REPEATS]      (defaults: build, the nightly scene, 3)
# Run it on a quiet machine: it times whole runs.
set -euo pipefail
build=${1:-build}
scene=${2:-data/scenes/nightly.toml}
repeats=${3:-3}
cores=$(nproc)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mpi=(mpirun --oversubscribe --bind-to none)
[[ $(id -u) -ne 0 ]] || mpi+=(--allow-run-as-root)
# time_of LABEL COMMAND...: the fastest wall time of the repeats, and the largest peak RSS of any
# process of the fastest run (each rank writes its own, /usr/bin/time -f %M, in kB).
time_of() {
  local label=$1 best="" rss="" r start took
  shift
  for ((r = 0; r < repeats; r++)); do
    rm -f "$work"/rss.*
    start=$(date +%s.%N)
    "$@" >/dev/null
    took=$(echo "$(date +%s.%N) - $start" | bc)
    if [[ -z $best ]] || (($(echo "$took < $best" | bc))); then
      best=$took
      rss=$(cat "$work"/rss.* | sort -n | tail -1)
    fi
  done
  printf '%-34s %8.2f s   peak RSS per process %6.0f MB\n' "$label" "$best" "$(echo "$rss / 1024" | bc -l)"
}
# A rank's own RSS file: /usr/bin/time run through sh so that $$ is each process's pid.
rank() { echo "/usr/bin/time -o $work/rss.\$\$ -f %M $build/harness/pldamp run $scene --out $work/out --jobs $1"; }
echo "$scene on $cores cores, fastest of $repeats"
time_of "serial, --jobs $cores" sh -c "$(rank "$cores")"
time_of "mpirun -n 1, --jobs $cores" "${mpi[@]}" -n 1 sh -c "$(rank "$cores")"
time_of "mpirun -n 2, --jobs $((cores / 2 > 0 ? cores / 2 : 1))" "${mpi[@]}" -n 2 sh -c "$(rank $((cores / 2 > 0 ? cores / 2 : 1)))"
time_of "mpirun -n 4 (oversubscribed), --jobs 1" "${mpi[@]}" -n 4 sh -c "$(rank 1)"
