// libFuzzer target: pldamp::harness::parse_scene (scene/scene.hpp), the reader of a TOML scene,
// on arbitrary bytes, then the labels the CLI prints of what it read. A SceneError (an
// std::invalid_argument) is the answer to bad input; any other exception escapes and aborts, and
// libFuzzer reports it with a crash, a hang (-timeout), a leak or an ASan/UBSan report.
//
// Build (Clang; float128 off, Clang has no GCC quadmath.h) and run, from the source tree:
//   CC=clang CXX=clang++ cmake -S . -B /tmp/build-fuzz -DPLDAMP_FUZZ=ON -DPLDAMP_WITH_QUAD=OFF \
//       -DPLDAMP_BUILD_TESTS=OFF -DPLDAMP_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
//   cmake --build /tmp/build-fuzz --target fuzz             # scene_fuzz and report_fuzz
//   tests/fuzz/run.sh /tmp/build-fuzz 60      # both, 60 s each, on a copy of tests/fuzz/corpus
//   F=/tmp/build-fuzz/tests/fuzz/scene_fuzz; mkdir -p /tmp/scene-corpus
//   $F -dict=tests/fuzz/scene.dict /tmp/scene-corpus tests/fuzz/corpus/scene   # until Ctrl-C
//   $F tests/fuzz/corpus/scene/crash-...                  # replays one input
//
// toml++'s implementation is compiled here, instrumented (tests/fuzz/CMakeLists.txt says why),
// without its internal assertions: toml++ 3.3.0 (Debian 12) asserts a precondition of parse_key
// that a table header such as `[|` breaks (corpus/scene/crash-toml-table-header-assert; fixed
// upstream, marzer/tomlplusplus#301). The Debian library, built by GCC with NDEBUG, returns its
// parse error there; with the assertion on, every run would stop at that one known input. Its
// __builtin_unreachable on non-ASCII text outside strings (marzer/tomlplusplus#295) is left to
// UBSan: undefined in the shipped build too (corpus/scene/crash-toml-unreachable-*).
#define TOML_ASSERT(expr) static_cast<void>(0)
#define TOML_IMPLEMENTATION
#include <toml++/toml.h>

#include "scene/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // load_scene refuses a larger file before parsing it.
  if (size > pldamp::harness::max_scene_bytes) {
    return -1;
  }
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const pldamp::harness::Scene scene = pldamp::harness::parse_scene(text, "fuzz.toml");
    // What `pldamp run` prints and keys its records with, from the values just read (labels
    // format numbers; another translation unit's, so the calls stay).
    for (const pldamp::harness::Damping& damping : scene.damping) {
      (void)damping.label();
    }
    for (const pldamp::harness::SolverConfig& config : scene.configs) {
      (void)config.label();
      (void)config.line();
    }
    for (const pldamp::harness::Claim& claim : scene.claims) {
      std::visit(
          [](const auto& stated) {
            if constexpr (requires { stated.config; }) {
              (void)stated.config.label();
            }
          },
          claim.kind);
    }
    for (const pldamp::harness::FigureSpec& figure : scene.figures) {
      (void)figure.config.label();
    }
  } catch (const std::invalid_argument&) {
    // SceneError: a bad scene, the expected answer
  }
  return 0;
}
