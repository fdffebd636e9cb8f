#!/usr/bin/env bash
# The one entry point of the README's Quick start and of CI.
#   scripts/run.sh main   install what is missing, build the CLI and the Python module (so that
#                         `import pldamp` and `cmake --install build` work), run the main job
#                         (the nightly scene)
#   scripts/run.sh test   install what is missing, build with -Werror and run every test, play the
#                         nightly gate on a second checkout with an injected regression, rebuild
#                         and rerun the tests under ASan+UBSan, check the reference table
#                         regenerates bit for bit, that the sources are clang-formatted, fuzz the
#                         scene, report, external-reply and shard readers, and build the CLI by
#                         Clang without float128
set -euo pipefail
cd "$(dirname "$0")/.."

# Debian 12 packages; README "Dependencies" says why each is here. The tests also render
# report.html in a browser: chromium and libpng for them only; the fuzzing step needs Clang and
# its libFuzzer (clang, libclang-rt-14-dev); the external-solver tests run the adapters (Python)
# against the real LAMMPS, LIGGGHTS and YADE (python3, lammps, liggghts, yade). The Python module
# (python/) is built with the rest: python3-dev, python3-numpy, pybind11-dev; its tests use pytest,
# and pandas for Report.dataframe() (optional for users: the tests check it where users meet it);
# mpmath regenerates the viscoelastic reference table (data/reference/viscoelastic.py).
# Open MPI (libopenmpi-dev, openmpi-bin): `mpirun -n N pldamp run` (docs/cluster.md).
packages=(cmake make g++ ccache libboost-dev libsundials-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libsimdjson-dev libgtest-dev libbenchmark-dev libtomlplusplus-dev gnuplot-nox clang-format python3-dev python3-numpy pybind11-dev
  libopenmpi-dev openmpi-bin)
test_packages=(chromium libpng-dev clang libclang-rt-14-dev python3 python3-pytest python3-matplotlib
  python3-pandas python3-mpmath python3-venv python3-setuptools python3-wheel lammps liggghts yade)

install_missing() { # install_missing PACKAGE...
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    local sudo=""
    [[ $(id -u) -eq 0 ]] || sudo=sudo
    echo "installing: ${missing[*]}" >&2
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

# Every build goes through ccache, paths taken relative to the checkout: a rebuild after a small
# change, and the gate's second checkout (scripts/ci_gate_test.sh), compile only what changed.
# Precompiled headers (PLDAMP_PCH) are cached only under this sloppiness.
export CCACHE_BASEDIR=$PWD
export CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime

# build/ (the main job's and the tests' Release build) is a unity build: CMake batches each
# target's units, eight to a batch, so the headers' templates compile once per batch, not once
# per unit (the Release build 10.6 -> 6.9 min on 2 cores, cold). Both jobs pass it: they share the
# directory, and a flipped setting would rebuild it whole. That every unit includes what it uses is
# checked unit by unit by the Clang build without float128 below.
unity=-DCMAKE_UNITY_BUILD=ON

build() { # build DIR [cmake options...]: configure, then build every target (BUILD_TARGET: those)
  local dir=$1 targets=()
  shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache "$@" >/dev/null
  [[ -z ${BUILD_TARGET:-} ]] || read -ra targets <<<"$BUILD_TARGET"
  cmake --build "$dir" -j "$(nproc)" ${targets[@]:+--target "${targets[@]}"}
}

case "${1:-}" in
main)
  echo "== 1/3 installing what is missing (apt)"
  install_missing "${packages[@]}"
  echo "== 2/3 building pldamp and its Python module (about 2 minutes on 2 cores the first time; a line per target)"
  mkdir -p build
  set +o pipefail
  # The command line and the Python module: after this command, `import pldamp` from build/python
  # and `cmake --install build` (the libraries, headers, pldampConfig.cmake and the module) work.
  BUILD_TARGET="pldamp pldamp_python" build build "$unity" 2>&1 | tee build/build.log |
    grep --line-buffered -E '^\[ *[0-9]+%\] Built target'
  status=${PIPESTATUS[0]}
  set -o pipefail
  if ((status != 0)); then
    tail -n 40 build/build.log >&2
    echo "the build failed; the whole log is build/build.log" >&2
    exit "$status"
  fi
  echo "== 3/3 the nightly scene (about 30 s on 2 cores)"
  # The nightly scene; its last lines name the report files (report/report.html to read).
  build/harness/pldamp run data/scenes/nightly.toml --out report
  ;;
test)
  install_missing "${packages[@]}" "${test_packages[@]}"
  build build -DPLDAMP_WERROR=ON "$unity"
  ctest --test-dir build -j "$(nproc)" --output-on-failure
  echo "== the nightly gate of docs/ci.md on two checkouts, one with an injected regression"
  # A is build/; B, a clone of HEAD with one line of odeint.cpp changed, builds its pldamp in a
  # temporary directory through A's ccache (about a minute: only the batch of the edited units
  # compiles).
  scripts/ci_gate_test.sh build
  echo "== reference tables regenerate bit for bit"
  build/data/pldamp-generate-reference build/analytic.csv
  cmp build/analytic.csv data/reference/analytic.csv
  # mpmath's viscoelastic truths (ViscoelasticTruth in harness_test): 13 s with --quick on two
  # cores, which leaves out the second method (the full check takes two minutes on one).
  /usr/bin/python3 data/reference/viscoelastic.py --quick -j 2 | cmp - data/reference/viscoelastic.csv
  echo "== clang-format"
  git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run -Werror
  echo "== no source in harness/ or python/ over 600 lines (docs/design.md: split by what it does)"
  long_files=$(git ls-files harness python | grep -E '\.(cpp|hpp|py)$' | xargs wc -l |
    awk '$2 != "total" && $1 > 600 {print $2 " (" $1 " lines)"}')
  if [[ -n $long_files ]]; then
    echo "over 600 lines: $long_files" >&2
    exit 1
  fi
  echo "== tests under AddressSanitizer + UndefinedBehaviorSanitizer, with assertions"
  # -O1 -g1: half the compile time of -O2 -g on the multiprecision units, line numbers kept. A unity
  # build too (19 min -> 11 on 2 cores, cold). (Test programs at -O0 halved their compile but
  # doubled the tests' run: their weak copies of the libraries' templates replace the -O1 ones at
  # link.)
  # Without -DNDEBUG: this is the build whose tests run the code's assert()s (the internal
  # invariants of core, analytic, solvers and the harness; the Release build above drops them).
  # The analytic layer's typed numeric tests ran above; their code runs here through the others.
  # Without MPI (Open MPI's own allocations would be leak reports): every test passes in a build
  # without it, and the sharded runs (tests/harness/shard_test.cpp) run here.
  build build-sanitize -DPLDAMP_WERROR=ON -DPLDAMP_SANITIZE=ON -DPLDAMP_BUILD_BENCHMARKS=OFF \
    -DPLDAMP_ANALYTIC_TESTS=OFF -DPLDAMP_MPI=OFF "$unity" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1"
  # The adapters' tests drive LAMMPS, LIGGGHTS and YADE from Python (pldamp only for `solve`):
  # they ran above, and the protocol's C++ side runs here through tests/harness/external_test.cpp.
  # The installed package's consumer builds without the sanitizers: it ran above. So did the DEM
  # and viscoelastic scenes end to end (1.5 of the 4.3 minutes these tests took under the
  # sanitizers, 2026-11-28): what they run, the schemes' batches, the step study and the reference
  # solves, runs here in Timestep.*, Search.TheTimeStepStudyAnswersAsTheSearchDoes and Plan.*.
  # The nightly scene's diff against itself (half a minute in Release) too: diff reads every
  # record of the quick and paper scenes' reports here.
  # Peak memory (diff_memory_test) measures the sanitizers' shadow memory there: left out too.
  ctest --test-dir build-sanitize -j "$(nproc)" --output-on-failure -LE 'adapters|install|docs|memory' \
    -E 'EndToEnd\.(DemSceneGivesTheTableADemUserQuotes|ViscoelasticSceneJudgesEverythingAgainstTheReferenceSolve|EveryOtherShippedSceneDiffsCleanlyAgainstItself)'
  echo "== fuzzing the scene, report, external-reply and shard readers (libFuzzer)"
  # Clang, the three fuzz targets and what they link (the readers, the solvers) under ASan+UBSan
  # with libFuzzer's coverage, -O1 -g1 as above but with the libraries' assertions
  # (nlohmann::json's catch misuse), without float128 (Clang does not find GCC's quadmath.h); about
  # 4 minutes on 2 cores. Each target then runs for 30 s, side by side, over a copy of
  # tests/fuzz/corpus (tests/fuzz/run.sh; the input behind a finding is kept in
  # build-fuzz/fuzz-artifacts).
  CC=clang CXX=clang++ BUILD_TARGET=fuzz build build-fuzz -DPLDAMP_FUZZ=ON \
    -DPLDAMP_WITH_QUAD=OFF -DPLDAMP_WERROR=ON -DPLDAMP_BUILD_TESTS=OFF -DPLDAMP_BUILD_BENCHMARKS=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1"
  tests/fuzz/run.sh build-fuzz 30
  echo "== the CLI by Clang without float128"
  # The whole library and the CLI, warning-free under Clang, without MPI and without float128
  # (-DPLDAMP_WITH_QUAD=OFF, what a user without GCC's quadmath builds): -O0 and no sanitizers, as
  # a compile check it needs neither (under 3 minutes on 2 cores; the CLI under the fuzz build's
  # sanitizers took 7). Unit by unit: it checks that every unit includes what it uses, which the
  # unity builds above cannot. It answers in 50 digits and refuses quad with the documented line.
  CC=clang CXX=clang++ BUILD_TARGET=pldamp build build-noquad -DPLDAMP_WITH_QUAD=OFF -DPLDAMP_MPI=OFF \
    -DPLDAMP_WERROR=ON -DPLDAMP_BUILD_TESTS=OFF -DPLDAMP_BUILD_BENCHMARKS=OFF -DPLDAMP_PYTHON=OFF \
    -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O0
  build-noquad/harness/pldamp observables --p 1.5 --e 0.5 --v0 1 --precision 50 --json
  status=0
  build-noquad/harness/pldamp observables --p 1.5 --e 0.5 --v0 1 --precision quad 2>build-noquad/quad.err ||
    status=$?
  grep -qx 'error: precision quad is not in this build (PLDAMP_WITH_QUAD=OFF), expected double|long|50 (got quad)' \
    build-noquad/quad.err && ((status == 2)) ||
    { echo "without float128, --precision quad must be refused with exit code 2" >&2; exit 1; }
  ;;
*)
  echo "usage: scripts/run.sh main|test" >&2
  exit 2
  ;;
esac
