#!/usr/bin/env bash
# The rows of docs/performance.md's table for one build directory, each from the command that
# measures it (run it on a quiet machine; two builds side by side give before and after):
#     bench/performance_table.sh build [kernels|scenes|all]
# Needs the targets taylor_bench, analytic_bench and pldamp built in BUILD. kernels: the solvers and
# closed forms (a few minutes); scenes: the nightly and paper scenes' wall time and peak memory.
set -euo pipefail
build=${1:-build}
part=${2:-all}
json() { "$@" --benchmark_format=json --benchmark_repetitions=5 --benchmark_min_time=0.2 2>/dev/null; }
# The fastest of the repetitions' CPU times, in the benchmark's own unit.
fastest() {
  python3 -c '
import json, sys
runs = json.load(sys.stdin)["benchmarks"]
for name in sys.argv[1:]:
    times = [r for r in runs if r.get("run_type") == "iteration" and r["run_name"] == name]
    best = min(times, key=lambda r: r["cpu_time"])
    print("%-32s %10.3f %s" % (name, best["cpu_time"], best["time_unit"]))
' "$@"
}
if [[ $part != scenes ]]; then
echo "== taylor, one collision at epsilon (taylor_bench, CPU time, fastest of 5)"
json "$build/bench/taylor_bench" --benchmark_filter='^taylor(_cold)?/(double|quad)/' |
  fastest taylor/double/p:1 taylor/double/p:1.5 taylor/double/p:2 taylor/double/p:3 \
    taylor/double/viscoelastic taylor_cold/double/p:1.5 taylor/quad/p:1 taylor/quad/p:1.5 \
    taylor/quad/p:2 taylor/quad/p:3 taylor/quad/viscoelastic taylor_cold/quad/p:1.5 \
    taylor_cold/quad/viscoelastic
echo "== taylor against the fastest other configuration reaching err <= 1e-12"
python3 bench/taylor_speedup.py "$build/bench/taylor_bench" --benchmark_min_time=0.2
echo "== pldamp solve --solver taylor as a user runs it (wall_seconds, 5 processes)"
for _ in 1 2 3 4 5; do
  "$build/harness/pldamp" solve --solver taylor --p 1.5 --e 0.61 --v0 0.42 --json |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["wall_seconds"])'
done | sort -g | tr '\n' ' '
echo
echo "== pldamp observables --damping-exponent 0.5 --precision quad, one process (the reference"
echo "   solve and its error estimate; wall time, fastest of 5 processes)"
python3 - "$build/harness/pldamp" <<'PY'
import subprocess, sys, time
for damping in (["--e", "0.61", "--v0", "0.42"], ["--alpha", "0.3", "--v0", "1"]):
    best = float("inf")
    for _ in range(5):
        started = time.perf_counter()
        subprocess.run([sys.argv[1], "observables", "--p", "1.5", *damping, "--damping-exponent",
                        "0.5", "--precision", "quad"], check=True, stdout=subprocess.DEVNULL)
        best = min(best, time.perf_counter() - started)
    print("%-24s %8.1f ms" % (" ".join(damping), best * 1e3))
PY
echo "== closed forms (analytic_bench, CPU time, fastest of 5)"
json "$build/bench/analytic_bench" --benchmark_filter='^(bundle_(double|quad)$|observable/)' |
  fastest bundle_double bundle_quad observable/t_peak/double observable/t_peak/quad \
    observable/all/double observable/all/quad
fi
if [[ $part != kernels ]]; then
  echo "== scenes on $(nproc) cores (wall seconds and peak RSS)"
  for scene in nightly paper; do
    /usr/bin/time -f "$scene: %e s, %M kB" "$build/harness/pldamp" run "data/scenes/$scene.toml" \
      --out "$(mktemp -d)" >/dev/null
  done
fi
