#!/bin/sh
# The installed package as its users get it (docs/api.md): `cmake --install` into a prefix, the
# prefix moved elsewhere (the package is relocatable), its headers including nothing but the
# standard library, Boost and pldamp, and examples/cmake-consumer configured, built and tested
# against the moved tree alone; with PLDAMP_PYTHON set (the build has the Python module), the
# installed module imported from the moved prefix's site directory.
#
#   [PLDAMP_PYTHON=python3] tests/install/consumer_test.sh BUILD_DIR SOURCE_DIR
set -eu
build=$1
source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/installed" > /dev/null
mv "$work/installed" "$work/moved"

# Every <...> include of the installed headers: a standard header, Boost or pldamp.
foreign=$(grep -rhE '^[[:space:]]*#[[:space:]]*include[[:space:]]*<' "$work/moved/include" |
  sed -E 's/.*<([^>]*)>.*/\1/' | grep -vE '^(boost|pldamp)/|^[a-z_0-9]+$' | sort -u || true)
if [ -n "$foreign" ]; then
  echo "the installed headers include more than the standard library, Boost and pldamp:"
  echo "$foreign"
  exit 1
fi

cmake -S "$source/examples/cmake-consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/moved" ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} > /dev/null
cmake --build "$work/consumer" -j2
ctest --test-dir "$work/consumer" --output-on-failure

if [ -n "${PLDAMP_PYTHON:-}" ]; then
  site=$(ls -d "$work"/moved/lib/python3*/site-packages)
  PYTHONPATH="$site" "$PLDAMP_PYTHON" -c 'import pldamp; print(pldamp.observables(p=1.5, e=0.5, v0=1.0)["delta_max"])'
fi
