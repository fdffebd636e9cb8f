#include "common/provenance.hpp"

#include "common/files.hpp"

#include "build_id.hpp"

#include <fmt/format.h>

#include <array>
#include <ctime>
#include <mutex>
#include <unistd.h>

namespace pldamp::harness {
namespace {

std::mutex command_lock;
std::vector<std::string> command_words{"pldamp"};

} // namespace

std::string_view build_id() {
  return PLDAMP_BUILD_ID;
}

void remember_command_line(const std::vector<std::string>& words) {
  const std::lock_guard guard(command_lock);
  command_words = words;
}

Provenance provenance_of(std::string_view scene_text) {
  Provenance made;
  made.build = std::string(build_id());
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  std::array<char, 32> date{};
  std::strftime(date.data(), date.size(), "%Y-%m-%dT%H:%M:%SZ", &utc);
  made.date = date.data();
  std::array<char, 256> host{};
  made.host = ::gethostname(host.data(), host.size() - 1) == 0 ? host.data() : "unknown";
  {
    const std::lock_guard guard(command_lock);
    made.command = command_words;
  }
  made.scene_checksum = fmt::format("{:016x}", fnv1a(scene_text));
  return made;
}

std::string provenance_line(const Provenance& made) {
  std::string command;
  for (const std::string& word : made.command) {
    const bool plain = !word.empty() && word.find_first_of(" \t\"'\\") == std::string::npos;
    command += (command.empty() ? "" : " ") + (plain ? word : fmt::format("'{}'", word));
  }
  return "pldamp " + made.build + " on " + made.host + ", " + made.date + ": " + command;
}

} // namespace pldamp::harness
