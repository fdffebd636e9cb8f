#!/usr/bin/env bash
# The nightly accuracy gate of docs/ci.md, end to end, on two checkouts of HEAD:
#   A  the checkout this script is in, already built (its pldamp is passed in);
#   B  a git clone of HEAD in a temporary directory with two lines changed on purpose: odeint-rkf78
#      handed a relative tolerance 1000 times looser than asked (its errors grow, nothing fails),
#      and verlet-predicted solving every batch three times over (3x its cost, the same
#      answers), built here as A was built (the pldamp target only, through A's ccache if A used
#      one).
#   scripts/ci_gate_test.sh [BUILD_DIR | PLDAMP]      (default: build)
# Nights are played with quick.toml, as docs/ci.md plays them with nightly.toml: a run --strict,
# a diff against the kept report.json, the gate on both exit codes, the report kept only when the
# gate passed. Checked: (a) A after A passes, with no finding at all; (b) B after A fails, its
# REGRESSION lines naming odeint-rkf78 and nothing else, and the baseline is not replaced (B again
# still fails); (c) a report of another scene is exit 2, compared with --allow-scene-change it is
# not; (d) run --strict exits 1 on a claim pinned wrongly. A must be built from HEAD as committed:
# uncommitted changes that move results show up as findings in (a)/(b).
#
# Time is judged as docs/ci.md judges it (the scene's [diff] defaults: time_factor 2, time_floor
# 0.005 s): per configuration the sum of its records' fastest repeats on the solving thread's CPU
# clock, against the larger of time_factor and the spread of both nights' repeats. Wall time was
# not judged here before (--time-floor 86400): beside three busy processes a quick.toml run
# against itself measured time_grew x2.2 to x3 in 6 of 6 tries. Everything else diff compares is
# deterministic: A against A must give "0 regressions, 0 changes".
#
# Cost: B's build, measured and printed (9 to 50 s through A's ccache; without one, a full build as
# A was configured), and 11 s for the rest on idle cores (4 quick.toml runs, the diffs).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
target=${1:-$root/build}
if [[ -d $target ]]; then
  target=$target/harness/pldamp
fi
if [[ ! -x $target ]]; then
  echo "usage: scripts/ci_gate_test.sh [BUILD_DIR | PLDAMP] (no pldamp at $target)" >&2
  exit 2
fi
pldamp_a=$(cd "$(dirname "$target")" && pwd)/$(basename "$target")
scene=$root/data/scenes/quick.toml

tmp=$(mktemp -d "${TMPDIR:-/tmp}/pldamp-gate.XXXXXX")
trap 'rm -rf -- "$tmp"' EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

started=$SECONDS
failures=0
pass() { echo "   ok: $*"; }
fail() {
  echo "   FAILED: $*" >&2
  failures=$((failures + 1))
}
show() { # show FILE: its lines, indented
  sed 's/^/     | /' "$1"
}

# night PLDAMP STATE NAME: one night of docs/ci.md's gate, in $tmp/NAME. STATE/report.json is
# yesterday's report (none the first night); tonight's replaces it only when the gate passes.
# Sets run_status, diff_status (-1 without a baseline) and gate (0 passed, 1 failed).
night() {
  local pldamp=$1 state=$2 dir=$tmp/$3
  mkdir -p "$dir" "$state"
  run_status=0
  # --jobs 2, as a CI runner's: the batches of quick.toml's verlet-predicted records, which the
  # injected cost is in, shrink on many cores (run_plan: fewer than four batches a thread).
  "$pldamp" run "$scene" --out "$dir/report" --strict --jobs 2 >"$dir/run.log" 2>&1 ||
    run_status=$?
  diff_status=-1
  if [[ -f $state/report.json ]]; then
    diff_status=0
    "$pldamp" diff "$state/report.json" "$dir/report/report.json" >"$dir/diff.txt" 2>&1 ||
      diff_status=$?
  fi
  gate=1
  if ((run_status == 0 && diff_status <= 0)); then
    gate=0
    cp "$dir/report/report.json" "$state/report.json"
  fi
}

echo "   A: $pldamp_a"

# --- B: a clone of HEAD with the regression, built ---------------------------------------------
head=$(git -C "$root" rev-parse HEAD)
if [[ -n $(git -C "$root" status --porcelain --untracked-files=no) ]]; then
  echo "   note: the working tree differs from HEAD; if A was built from it, (a) and (b) may show that"
fi
b=$tmp/b
# --shared: B reads A's objects (no copy), whatever branch or detached HEAD A is on.
git clone --quiet --shared --no-checkout "$root" "$b"
git -C "$b" checkout --quiet --detach "$head"
# inject FILE BEFORE AFTER: the one line of FILE holding BEFORE (once) rewritten to AFTER.
inject() {
  local file=$1 before=$2 after=$3
  if [[ $(grep -c -F -e "$before" "$b/$file") != 1 ]]; then
    echo "FAILED: the injected regression does not apply: '$before' is not once in $file" >&2
    exit 1
  fi
  BEFORE=$before AFTER=$after perl -0pi -e 's/\Q$ENV{BEFORE}\E/$ENV{AFTER}/' "$b/$file"
  if [[ $(grep -c -F -e "$after" "$b/$file") != 1 ]]; then
    echo "FAILED: the injected regression did not apply in $file" >&2
    exit 1
  fi
}
# Errors: RKF78's error checker handed 1000 x rtol.
inject solvers/src/odeint.cpp 'collision.options().rtol, 1, 0)),' \
  'collision.options().rtol * 1e3, 1, 0)),'
# Cost: verlet-predicted solving each batch three times, the last answers returned (quick.toml's
# verlet-predicted records, one phase each, are solved in batches of one configuration and p:
# run_plan, docs/performance.md "Batch mode").
batch_line='    return entry.batch(problems, options);'
inject solvers/src/registry.cpp "$batch_line" \
  "    for (int i = name == \"verlet-predicted\" ? 2 : 0; i > 0; --i) { (void)entry.batch(problems, options); } $batch_line"
if [[ $(git -C "$b" diff --numstat | tr '\n' ' ') != $'1\t1\tsolvers/src/odeint.cpp 1\t1\tsolvers/src/registry.cpp ' ]]; then
  echo "FAILED: the injected regressions are not one changed line in each of two files:" >&2
  git -C "$b" diff >&2
  exit 1
fi
echo "   B: $head with (RKF78's error checker; the registry's solve_batch):"
git -C "$b" diff -U0 | grep '^[-+] ' | sed 's/^/     /'
build_started=$SECONDS
# B is configured as A (the same compiler, build type and flags: their times are compared) and,
# when A was built through ccache (scripts/run.sh does), built through the same cache, with each
# checkout as its own CCACHE_BASEDIR so that the paths ccache hashes are the same: every unit but
# the two edited is a hit (9 s on 2 cores; in a unity build, as scripts/run.sh builds, the batch
# holding both edited units compiles: 50 s).
a_cache=$(dirname "$(dirname "$pldamp_a")")/CMakeCache.txt
a_setting() { # a_setting NAME: NAME's value in A's CMakeCache.txt, empty if absent
  if [[ -f $a_cache ]]; then # (not `&&`: a false test would end the script under set -e)
    sed -n "s/^$1:[A-Z]*=//p" "$a_cache" | head -n 1
  fi
}
b_options=(-DCMAKE_BUILD_TYPE=Release)
if [[ -f $a_cache ]]; then
  b_options=()
  for name in CMAKE_CXX_COMPILER CMAKE_CXX_COMPILER_LAUNCHER CMAKE_BUILD_TYPE CMAKE_CXX_FLAGS \
    CMAKE_CXX_FLAGS_RELEASE CMAKE_UNITY_BUILD PLDAMP_WERROR PLDAMP_WITH_QUAD PLDAMP_SANITIZE; do
    b_options+=("-D$name=$(a_setting "$name")")
  done
fi
if ! {
  cmake -S "$b" -B "$b/build" -DPLDAMP_BUILD_TESTS=OFF -DPLDAMP_BUILD_BENCHMARKS=OFF \
    "${b_options[@]}" &&
    CCACHE_BASEDIR=$b cmake --build "$b/build" -j "$(nproc)" --target pldamp
} >"$tmp/b-build.log" 2>&1; then
  tail -n 40 "$tmp/b-build.log" >&2
  echo "FAILED: B did not build" >&2
  exit 1
fi
build_seconds=$((SECONDS - build_started))
pldamp_b=$b/build/harness/pldamp
echo "   B built in ${build_seconds} s"

state=$tmp/state # what the CI cache or artifact store keeps between nights

echo "-- first night (A, no baseline): the run alone is the gate, its report is kept"
night "$pldamp_a" "$state" night1
if ((run_status == 0 && diff_status == -1 && gate == 0)) && [[ -f $state/report.json ]]; then
  pass "run --strict exit 0, no diff, report.json kept"
else
  fail "run exit $run_status, diff exit $diff_status, gate $gate, kept: $(ls "$state")"
  show "$tmp/night1/run.log"
fi

echo "-- (a) A tonight against A yesterday: diff exit 0, no finding (no false alarm)"
night "$pldamp_a" "$state" night2
if ((run_status == 0 && diff_status == 0 && gate == 0)) &&
  [[ $(cat "$tmp/night2/diff.txt") == "0 regressions, 0 changes" ]] &&
  cmp -s "$tmp/night2/report/report.json" "$state/report.json"; then
  pass "diff exit 0: $(tail -n 1 "$tmp/night2/diff.txt"); tonight's report.json kept"
else
  fail "run exit $run_status, diff exit $diff_status, gate $gate (expected 0, 0, 0 and no line but" \
    "'0 regressions, 0 changes')"
  show "$tmp/night2/diff.txt"
fi
echo "-- (b) B tonight against A yesterday: diff exit 1, REGRESSION lines on odeint-rkf78 and"
echo "   time_grew on verlet-predicted (3x its cost) only"
night "$pldamp_b" "$state" night3
regressions=$tmp/night3/regressions.txt
grep '^REGRESSION ' "$tmp/night3/diff.txt" >"$regressions" || true
# REGRESSION <what> | <configuration or claim> | <subject> | <n> <unit>s | <worst> at <cell>
owners=$(awk -F ' [|] ' '{ print $2 }' "$regressions" | sort -u)
others=$(grep -v -e '^REGRESSION [a-z_]* | odeint-rkf78 ' \
  -e '^REGRESSION time_grew | verlet-predicted n=[0-9]* | cpu_seconds | ' "$regressions" || true)
if ((run_status == 0 && diff_status == 1 && gate == 1)) &&
  grep -q '^REGRESSION error_grew | odeint-rkf78 ' "$regressions" &&
  grep -q '^REGRESSION time_grew | verlet-predicted ' "$regressions" && [[ -z $others ]]; then
  pass "diff exit 1: $(tail -n 1 "$tmp/night3/diff.txt"), all on $(paste -s -d ';' <<<"$owners")"
  grep '^REGRESSION time_grew ' "$regressions" | sed 's/^/     | /'
else
  fail "run exit $run_status, diff exit $diff_status, gate $gate (expected 0, 1, 1 with error_grew" \
    "on odeint-rkf78, time_grew on verlet-predicted, and no other configuration)"
  show "$tmp/night3/diff.txt"
fi
if cmp -s "$tmp/night2/report/report.json" "$state/report.json"; then
  pass "the failed night's report was not kept: the baseline is still (a)'s"
else
  fail "the failed night replaced the baseline"
fi
night "$pldamp_b" "$state" night4
if ((diff_status == 1 && gate == 1)); then
  pass "B the night after still fails (exit 1): the regression did not become the baseline"
else
  fail "B the night after: diff exit $diff_status, gate $gate (expected 1, 1)"
  show "$tmp/night4/diff.txt"
fi

# A scene of one cell whose only claim is pinned as failing, though it holds.
pinned=$tmp/pinned.toml
cat >"$pinned" <<'EOF'
name = "pinned"
want = ["e"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "arkode-dp5"
rtol = 1e-8
[[claim]]
name = "dp5 within 1e-5, pinned wrongly"
observable = "e"
solver = "arkode-dp5"
rtol = 1e-10
atol = 1e-13
bound = 1e-5
expect = "fails"
[report]
formats = ["json"]
EOF

echo "-- (c) a report of another scene: exit 2; with --allow-scene-change compared (exit 0 or 1)"
loose=0
"$pldamp_a" run "$pinned" --out "$tmp/pinned" >"$tmp/pinned.log" 2>&1 || loose=$?
other=0
"$pldamp_a" diff "$state/report.json" "$tmp/pinned/report.json" >"$tmp/other.txt" \
  2>"$tmp/other.err" || other=$?
allowed=0
"$pldamp_a" diff "$state/report.json" "$tmp/pinned/report.json" --allow-scene-change \
  >"$tmp/allowed.txt" 2>&1 || allowed=$?
if ((loose == 0 && other == 2)) && [[ ! -s $tmp/other.txt ]] &&
  grep -q 'different scenes' "$tmp/other.err"; then
  pass "exit 2, nothing on stdout, on stderr: $(cut -c 1-80 "$tmp/other.err")..."
else
  fail "the other scene's run exit $loose (expected 0), diff exit $other (expected 2, stdout empty)"
  show "$tmp/pinned.log"
  show "$tmp/other.txt"
  show "$tmp/other.err"
fi
if ((allowed == 0 || allowed == 1)) &&
  grep -q '^SCENE removed configuration | ' "$tmp/allowed.txt"; then
  pass "--allow-scene-change: exit $allowed, $(grep -c '^SCENE ' "$tmp/allowed.txt") SCENE lines," \
    "then $(tail -n 1 "$tmp/allowed.txt")"
else
  fail "--allow-scene-change: exit $allowed (expected 0 or 1, with SCENE lines)"
  show "$tmp/allowed.txt"
fi

echo "-- (d) run --strict on a scene whose claim is pinned wrongly: exit 1 (exit 0 without, in (c))"
strict=0
"$pldamp_a" run "$pinned" --out "$tmp/pinned-strict" --strict >"$tmp/pinned-strict.log" 2>&1 ||
  strict=$?
if ((strict == 1)) && grep -q '^--strict: ' "$tmp/pinned-strict.log" &&
  [[ -f $tmp/pinned-strict/report.json ]]; then
  pass "exit 1, report still written; $(grep '^--strict: ' "$tmp/pinned-strict.log")"
else
  fail "run --strict exit $strict (expected 1, with a report.json)"
  show "$tmp/pinned-strict.log"
fi

total=$((SECONDS - started))
if ((failures > 0)); then
  echo "FAILED: $failures of the gate's expectations (B's build ${build_seconds} s, all ${total} s)" >&2
  exit 1
fi
echo "   the gate behaves as docs/ci.md says (B's build ${build_seconds} s, all ${total} s)"
