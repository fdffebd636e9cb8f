#!/usr/bin/env bash
# Runs the three libFuzzer targets (tests/fuzz/*_fuzz.cpp) for SECONDS each, side by side (on two
# cores: the wall time of one), over a copy of their corpus: the seeds in tests/fuzz/corpus stay as they are, what the
# fuzzers add goes to a temporary directory, deleted at the end.
#   tests/fuzz/run.sh BUILD_DIR SECONDS
# BUILD_DIR was configured with -DPLDAMP_FUZZ=ON (CC=clang CXX=clang++) and has built the targets
# scene_fuzz, report_fuzz and exchange_fuzz. Exits non-zero when any finds a crash, a hang (an input slower than
# 10 s), a leak, an ASan/UBSan report or an exception other than std::invalid_argument; the input
# that did it is kept in BUILD_DIR/fuzz-artifacts/<target>/ (a crash- file to copy into
# tests/fuzz/corpus/<target>/), and its report is printed.
set -euo pipefail

if (($# != 2)) || ! [[ $2 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: tests/fuzz/run.sh BUILD_DIR SECONDS" >&2
  exit 2
fi
build=$(cd "$1" && pwd)
seconds=$2
here=$(cd "$(dirname "$0")" && pwd)

work=$(mktemp -d "${TMPDIR:-/tmp}/pldamp-fuzz.XXXXXX")
trap 'rm -rf "$work"' EXIT

# UBSan prints no stack of its own unless asked.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

start() { # start TARGET: the fuzzer in the background, its output in $work/TARGET.log
  local target=$1 binary=$build/tests/fuzz/$1
  if [[ ! -x $binary ]]; then
    echo "$binary is missing: build it with -DPLDAMP_FUZZ=ON (tests/fuzz/CMakeLists.txt)" >&2
    exit 2
  fi
  local name=${target%_fuzz}
  mkdir -p "$work/$name" "$build/fuzz-artifacts/$target"
  cp "$here/corpus/$name/"* "$work/$name/"
  # A watchdog on top of -max_total_time, which does not count reading the corpus.
  timeout --signal=KILL $((seconds + 120)) "$binary" "$work/$name" -dict="$here/$name.dict" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/fuzz-artifacts/$target/" >"$work/$target.log" 2>&1 &
}

finish() { # finish TARGET PID: waits, prints a summary or the finding; returns its status
  local target=$1 pid=$2 status=0
  wait "$pid" || status=$?
  local log=$work/$target.log
  if ((status == 0)); then
    # libFuzzer's last line of progress: runs, coverage, corpus, speed.
    echo "$target: no finding in $seconds s: $(grep -m1 -E '\sDONE\s' "$log" || tail -n1 "$log")"
  else
    echo "$target: FAILED (status $status); the start of its report:" >&2
    # The sanitizer's or libFuzzer's report from its first line, a run of frames of one function
    # (a stack overflow) as one; its summary and where the input is, if that cut them off.
    local first='ERROR: |runtime error|deadly signal|Killed|timeout after|out-of-memory|leak'
    sed -n "/${first//|/\\|}/,/Test unit written/p" "$log" | awk '
      { key = $0; sub(/^ *#[0-9]+ 0x[0-9a-f]+ /, "", key) }
      key == last && /^ *#[0-9]/ { ++same; next }
      { if (same) print "    ... the same frame " same " more times"; same = 0; last = key; print }
    ' | head -n 40 | cut -c 1-240 >"$work/$target.excerpt"
    [[ -s $work/$target.excerpt ]] || tail -n 30 "$log" >"$work/$target.excerpt"
    cat "$work/$target.excerpt" >&2
    local line
    for line in '^SUMMARY: ' 'Test unit written'; do
      grep -q "$line" "$work/$target.excerpt" || grep -m1 "$line" "$log" | cut -c 1-240 >&2 || true
    done
  fi
  return "$status"
}

start scene_fuzz
scene_pid=$!
start report_fuzz
report_pid=$!
start exchange_fuzz
exchange_pid=$!
failed=0
finish scene_fuzz "$scene_pid" || failed=1
finish report_fuzz "$report_pid" || failed=1
finish exchange_fuzz "$exchange_pid" || failed=1
if ((failed)); then
  echo "fuzzing found a problem: the inputs are in $build/fuzz-artifacts/ (replay one: " \
    "$build/tests/fuzz/<target> FILE)" >&2
fi
exit "$failed"
