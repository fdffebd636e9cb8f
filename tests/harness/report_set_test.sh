#!/bin/sh
# A report set is a set (docs/run.md "Reports"): a run whose reports cannot all be written leaves
# every report file of its folder as it was, says so in one line (exit 2), and leaves no temporary
# behind. Played with a file-size limit (ulimit -f) and, where this user may mount one, with a
# 1 MiB tmpfs as --out: a small scene's reports fit, quick.toml's (2.7 MB) do not.
#
#   tests/harness/report_set_test.sh PLDAMP SOURCE_DIR
set -eu
pldamp=$1
source=$2
work=$(mktemp -d)
trap 'umount "$work/mnt" 2>/dev/null || true; rm -rf "$work"' EXIT

cat >"$work/small.toml" <<'SCENE'
name = "small"
want = ["e"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "taylor"
SCENE

fail() {
  echo "FAILED: $*" >&2
  exit 1
}

# Runs the small scene into $1, then quick.toml under the limits given after it, and checks that
# the second run failed with the documented line and left the folder byte for byte as it was.
play() {
  out=$1
  shift
  "$pldamp" run "$work/small.toml" --out "$out" >/dev/null 2>"$work/err" || fail "small run: $(cat "$work/err")"
  (cd "$out" && sha256sum report.*) >"$work/before"
  status=0
  (eval "$*"; exec "$pldamp" run "$source/data/scenes/quick.toml" --out "$out") >/dev/null \
    2>"$work/err" || status=$?
  [ "$status" -eq 2 ] || fail "$*: exit $status, not 2: $(cat "$work/err")"
  grep -q "no report file was changed: .* holds the previous run's, if any" "$work/err" ||
    fail "$*: the message does not say what is on disk: $(cat "$work/err")"
  # One line of its own; a run past 1 s also reports its progress ("1 s: 793/810 records, ...",
  # docs/run.md), as quick.toml did under the sanitizers on a loaded machine: those are not counted.
  [ "$(grep -v -E '^[0-9]+ s: [0-9]+/[0-9]+ records, ' "$work/err" | grep -c .)" -eq 1 ] ||
    fail "$*: more than one line: $(cat "$work/err")"
  (cd "$out" && sha256sum report.*) | cmp -s - "$work/before" ||
    fail "$*: the folder changed: $(cd "$out" && sha256sum report.*)"
  leftover=$(ls -A "$out" | grep -v '^report\.' || true)
  [ -z "$leftover" ] || fail "$*: left behind: $leftover"
  echo "ok: $* -> $(cat "$work/err")"
}

play "$work/limited1" "ulimit -f 200"  # the records' file is cut first
play "$work/limited2" "ulimit -f 1500" # the records and report.csv fit, report.json does not

mkdir "$work/mnt"
if mount -t tmpfs -o size=1m tmpfs "$work/mnt" 2>/dev/null; then
  play "$work/mnt" ":"
else
  echo "skipped: a 1 MiB tmpfs (this user cannot mount one)"
fi
