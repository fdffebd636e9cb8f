// libFuzzer target: what other processes hand pldamp. The first byte picks the reader, the rest is
// its input:
//   0  an external program's handshake line (run/external.hpp, read_handshake)
//   1  an external program's reply line to problem 7 (read_reply), and, when it reads, the
//      invariants an answer is held to (run/answers.hpp, impossible_answer)
//   2  a shard file's bytes after its magic line (run/shard.hpp, read_shard_bytes), the checksum
//      appended here so that the fuzzer reaches past it (a hand-made file recomputes it too)
// A refusal is std::invalid_argument (InputError, ProtocolError: bad input, exit 2) or, for a
// reply, std::runtime_error (the record fails with the reason); anything else escaping (a
// nlohmann::json type error, a bad_alloc from a count no file could hold) aborts, as does a crash,
// a hang, a leak or an ASan/UBSan report. tests/fuzz/run.sh runs it beside the other targets.
#include "common/files.hpp"
#include "run/answers.hpp"
#include "run/external.hpp"
#include "run/shard.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

namespace {

using namespace pldamp::harness;
namespace solvers = pldamp::solvers;

void handshake(const std::string& line) {
  try {
    (void)read_handshake(line, "[[solver]] fuzz");
  } catch (const std::invalid_argument&) {
  }
}

void reply(const std::string& line) {
  solvers::Result<double> answer;
  try {
    answer = read_reply(line, 7);
  } catch (const std::runtime_error&) {
    return; // Skipped, ReportedError, or a reply that cannot be read: the record's reason
  }
  SolverConfig config;
  config.name = "fuzz";
  config.steps_per_contact = 50;
  const solvers::Problem<double> problem{1.5, 1.0, 1.0, 1.0, 0.5};
  solvers::Options<double> options;
  options.want = solvers::want_e | solvers::want_delta_max | solvers::want_tau;
  (void)impossible_answer(answer, config, problem, options);
}

void shard(std::string_view body) {
  std::string bytes("pldamp shard\n");
  bytes.append(body);
  const std::uint64_t sum = fnv1a(bytes);
  bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  try {
    std::size_t records = 0;
    (void)read_shard_bytes(bytes, "fuzz.pldamp", [&](Record&&, std::string_view) { ++records; });
  } catch (const std::invalid_argument&) {
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  switch (data[0] % 3) {
  case 0:
    handshake(std::string(rest));
    break;
  case 1:
    reply(std::string(rest));
    break;
  default:
    shard(rest);
    break;
  }
  return 0;
}
