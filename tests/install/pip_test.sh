#!/bin/sh
# `pip install --no-build-isolation .` as docs/python.md says it: into a fresh venv made with
# --system-site-packages (Debian's numpy), from the repository, nothing downloaded (--no-index),
# then the module imported from the venv, not from the build tree. The CMake build directory is
# the one given (reused as configured), so that this test costs the module's link, not a build.
#
#   tests/install/pip_test.sh PYTHON BUILD_DIR SOURCE_DIR
set -eu
python=$1
build=$2
source=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$python" -m venv --system-site-packages "$work/venv"
PLDAMP_BUILD_DIR="$build" "$work/venv/bin/pip" install --no-build-isolation --no-index \
  --disable-pip-version-check --quiet "$source"
cd "$work"
"$work/venv/bin/python" -c '
import pldamp, sys
assert pldamp.__file__.startswith(sys.prefix), pldamp.__file__
print(pldamp.observables(p=1.5, e=0.5, v0=1.0)["delta_max"])'
