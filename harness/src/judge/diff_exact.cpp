#include "judge/diff_exact.hpp"

#include "common/input.hpp"
#include "common/report_schema.hpp"
#include "judge/bounded_queue.hpp"
#include "judge/diff_parts.hpp"
#include "judge/match_by_key.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <optional>
#include <string_view>
#include <utility>

namespace pldamp::harness {
namespace {

using nlohmann::json;
namespace key = schema::key;

// What timing decides, wherever it stands: times, the runs the repeats made, × analytic.
bool timing(const std::string& name) {
  return name.find("second") != std::string::npos || name == "runs" || name == "solver_runs" ||
         name == "x_analytic" || name == "generated";
}

void drop_timing(json& value) {
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end();) {
      if (timing(it.key())) {
        it = value.erase(it);
      } else {
        drop_timing(*it);
        ++it;
      }
    }
  } else if (value.is_array()) {
    for (json& item : value) {
      drop_timing(item);
    }
  }
}

// A number's text: JSON numbers are written in the shortest form that reads back to the same
// double, so equal text is equal bits (a zero keeps its sign).
std::string shown(const json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

// The paths at which two values differ, the first `most` of them.
void differing_paths(const json& a, const json& b, const std::string& path,
                     std::vector<std::string>& found, std::size_t most) {
  if (found.size() >= most) {
    return;
  }
  if (a.is_object() && b.is_object()) {
    for (const auto& [name, value] : a.items()) {
      const std::string where = path.empty() ? name : path + "." + name;
      if (!b.contains(name)) {
        found.push_back(where + ": " + one_line(shown(value), 80) + " -> none");
      } else {
        differing_paths(value, b.at(name), where, found, most);
      }
    }
    for (const auto& [name, value] : b.items()) {
      if (!a.contains(name) && found.size() < most) {
        found.push_back((path.empty() ? name : path + "." + name) + ": none -> " +
                        one_line(shown(value), 80));
      }
    }
    return;
  }
  if (a.is_array() && b.is_array() && a.size() == b.size()) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      differing_paths(a[i], b[i], path + "[" + std::to_string(i) + "]", found, most);
    }
    return;
  }
  if (a.dump() != b.dump()) { // dump: a number to its last bit, -0 apart from 0
    found.push_back((path.empty() ? "value" : path) + ": " + one_line(shown(a), 80) + " -> " +
                    one_line(shown(b), 80));
  }
}

using RecordQueue = diff::BoundedQueue<json>;

// The reading of a report, its records into a queue and the rest into `rest`. With `by_lines`, a
// report in pldamp's layout is read a record line at a time (diff::read_report_lines: each record
// checked as read_report checks it, its key's hash kept where read_report keeps the key: 23 MB
// for a 10^6-run map where the keys took 144 MB); the reading ends with Doubted where that
// reader declines.
diff::SideBySide<json>::Read reading_of(std::istream& in, const std::string& path, json& rest,
                                        const ReportLimits& limits, bool by_lines) {
  return [&in, &path, &rest, &limits, by_lines](RecordQueue& queue) {
    if (!by_lines) {
      rest = schema::read_report(
          in, path, [&](json&& record) { queue.push(std::move(record)); }, limits.values);
      return;
    }
    std::optional<json> read = diff::read_report_lines(
        in, path, limits, nullptr,
        [&](std::string& line, std::size_t length,
            std::size_t index) -> std::optional<std::size_t> {
          json record;
          try {
            record = schema::read_record(std::string_view(line).substr(0, length), path,
                                         fmt::format("{}[{}]", key::records, index));
          } catch (const std::exception&) {
            return std::nullopt; // the general reader says what is wrong
          }
          const std::size_t key_hash =
              std::hash<std::string_view>{}(record.at(key::key).get_ref<const std::string&>());
          queue.push(std::move(record));
          return key_hash;
        });
    if (!read) {
      throw diff::Doubted{};
    }
    rest = std::move(*read);
  };
}

std::string record_key(const json& record) {
  return record.contains(key::key) && record.at(key::key).is_string()
             ? record.at(key::key).get<std::string>()
             : "?";
}

// One reading of both reports; none when read `by_lines` and the fast reader declined either.
std::optional<ExactResult> exact_pass(std::istream& old_report, const std::string& old_path,
                                      std::istream& new_report, const std::string& new_path,
                                      bool verbose, const ReportLimits& limits, bool by_lines) {
  json old_rest, new_rest;
  diff::SideBySide<json> reading(reading_of(old_report, old_path, old_rest, limits, by_lines),
                                 reading_of(new_report, new_path, new_rest, limits, by_lines));
  RecordQueue& old_queue = reading.old_queue();
  RecordQueue& new_queue = reading.new_queue();
  ExactResult result;
  long record_differences = 0;
  const std::size_t shown_records = verbose ? SIZE_MAX : 20;
  std::exception_ptr failed;
  try {
    const auto differs = [&](const std::string& key, const std::vector<std::string>& paths) {
      ++record_differences;
      if (static_cast<std::size_t>(record_differences) <= shown_records) {
        for (const std::string& path : paths) {
          result.lines.push_back(fmt::format("DIFFERS record | {} | {}", one_line(key), path));
        }
      }
    };
    const auto compare = [&](json& a, json& b) {
      std::vector<std::string> paths;
      drop_timing(a);
      drop_timing(b);
      differing_paths(a, b, "", paths, 3);
      if (!paths.empty()) {
        differs(record_key(a), paths);
      }
    };
    // Records are matched by key (judge/match_by_key.hpp): a record gone or added is named alone
    // rather than shifting every record after it.
    diff::MatchByKey<json> matched;
    for (;;) {
      std::optional<json> a = old_queue.pop();
      std::optional<json> b = new_queue.pop();
      if (!a && !b) {
        break;
      }
      const std::string a_key = a ? record_key(*a) : "", b_key = b ? record_key(*b) : "";
      matched.take(std::move(a), a_key, std::move(b), b_key, compare);
    }
    for (const json* record : matched.only_in_old()) {
      differs(record_key(*record), {"only in old"});
    }
    for (const json* record : matched.only_in_new()) {
      differs(record_key(*record), {"only in new"});
    }
  } catch (...) {
    failed = std::current_exception();
  }
  reading.stop();
  if (failed) {
    if (diff::doubted(failed)) {
      return std::nullopt;
    }
    std::rethrow_exception(failed);
  }
  if (static_cast<std::size_t>(record_differences) > shown_records) {
    result.lines.push_back(
        fmt::format("  ... and {} more records (--verbose lists them)",
                    static_cast<std::size_t>(record_differences) - shown_records));
  }
  // Everything but the records, section by section, without timing and provenance.
  long other = 0;
  for (json* rest : {&old_rest, &new_rest}) {
    rest->erase(key::run);
    rest->erase(key::records);
    if (rest->contains(key::scene) && rest->at(key::scene).is_object()) {
      rest->at(key::scene).erase(key::path); // where the scene lay, not what it computes
    }
    drop_timing(*rest);
  }
  std::vector<std::string> sections;
  for (const auto& [name, value] : old_rest.items()) {
    sections.push_back(name);
  }
  for (const auto& [name, value] : new_rest.items()) {
    if (!old_rest.contains(name)) {
      sections.push_back(name);
    }
  }
  for (const std::string& section : sections) {
    const json none;
    const json& a = old_rest.contains(section) ? old_rest.at(section) : none;
    const json& b = new_rest.contains(section) ? new_rest.at(section) : none;
    // A list of named parts (claims, searches) or of parts: a line per part that differs.
    if (a.is_array() && b.is_array() && a.size() == b.size()) {
      for (std::size_t i = 0; i < a.size(); ++i) {
        std::vector<std::string> paths;
        differing_paths(a[i], b[i], "", paths, 3);
        const std::string part = a[i].is_object() && a[i].contains(key::name)
                                     ? one_line(shown(a[i].at(key::name)))
                                     : "[" + std::to_string(i) + "]";
        other += paths.empty() ? 0 : 1;
        for (const std::string& path : paths) {
          result.lines.push_back(fmt::format("DIFFERS {} | {} | {}", section, part, path));
        }
      }
      continue;
    }
    if (a.is_object() && b.is_object()) {
      for (const auto& [part, value] : a.items()) {
        std::vector<std::string> paths;
        differing_paths(value, b.contains(part) ? b.at(part) : none, "", paths, 3);
        other += paths.empty() ? 0 : 1;
        for (const std::string& path : paths) {
          result.lines.push_back(fmt::format("DIFFERS {} | {} | {}", section, part, path));
        }
      }
      for (const auto& [part, value] : b.items()) {
        if (!a.contains(part)) {
          ++other;
          result.lines.push_back(fmt::format("DIFFERS {} | {} | only in new", section, part));
        }
      }
      continue;
    }
    std::vector<std::string> paths;
    differing_paths(a, b, "", paths, 3);
    other += paths.empty() ? 0 : 1;
    for (const std::string& path : paths) {
      result.lines.push_back(fmt::format("DIFFERS {} | {}", section, path));
    }
  }
  result.differences = record_differences + other;
  result.lines.push_back(
      result.differences == 0
          ? std::string("0 differences: identical but for timings and provenance")
          : fmt::format("{} difference{} ({} record{}, {} other)", result.differences,
                        result.differences == 1 ? "" : "s", record_differences,
                        record_differences == 1 ? "" : "s", other));
  return result;
}

} // namespace

ExactResult diff_exact(std::istream& old_report, const std::string& old_path,
                       std::istream& new_report, const std::string& new_path, bool verbose,
                       const ReportLimits& limits) {
  // A record line at a time where both can be read again from their start.
  const std::istream::pos_type old_start = old_report.tellg(), new_start = new_report.tellg();
  if (old_start != std::istream::pos_type(-1) && new_start != std::istream::pos_type(-1)) {
    if (std::optional<ExactResult> result =
            exact_pass(old_report, old_path, new_report, new_path, verbose, limits, true)) {
      return std::move(*result);
    }
    diff::read_again(old_report, old_start, old_path);
    diff::read_again(new_report, new_start, new_path);
  }
  return *exact_pass(old_report, old_path, new_report, new_path, verbose, limits, false);
}

} // namespace pldamp::harness
