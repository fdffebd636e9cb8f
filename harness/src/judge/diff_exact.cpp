#include "judge/diff_exact.hpp"

#include "common/input.hpp"
#include "common/report_schema.hpp"

#include <fmt/format.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

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

// Records handed from a reading thread to the comparing one, a bounded number at a time.
class RecordQueue {
public:
  void push(json&& record) {
    std::unique_lock lock(mutex_);
    room_.wait(lock, [&] { return items_.size() < capacity || abandoned_; });
    items_.push_back(std::move(record));
    ready_.notify_one();
  }
  void close(std::exception_ptr failure = nullptr) {
    const std::lock_guard lock(mutex_);
    closed_ = true;
    failure_ = failure;
    ready_.notify_one();
  }
  void abandon() { // the reader stops waiting for room: nothing will be taken any more
    const std::lock_guard lock(mutex_);
    abandoned_ = true;
    room_.notify_one();
  }
  // The next record, or none at the end (rethrowing the reader's failure).
  std::optional<json> pop() {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [&] { return !items_.empty() || closed_; });
    if (!items_.empty()) {
      json record = std::move(items_.front());
      items_.pop_front();
      room_.notify_one();
      return record;
    }
    if (failure_) {
      std::rethrow_exception(failure_);
    }
    return std::nullopt;
  }

private:
  static constexpr std::size_t capacity = 256;
  std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<json> items_;
  bool closed_ = false, abandoned_ = false;
  std::exception_ptr failure_;
};

struct AbandonedRead {};

// Reads a report on a thread of its own, its records into `queue`, the rest into `rest`.
std::thread reader(std::istream& in, const std::string& path, RecordQueue& queue, json& rest,
                   std::atomic<bool>& abandoned, const ReportLimits& limits) {
  return std::thread([&in, &path, &queue, &rest, &abandoned, &limits] {
    try {
      rest = schema::read_report(
          in, path,
          [&](json&& record) {
            if (abandoned) {
              throw AbandonedRead{};
            }
            queue.push(std::move(record));
          },
          limits.values);
      queue.close();
    } catch (const AbandonedRead&) {
      queue.close();
    } catch (...) {
      queue.close(std::current_exception());
    }
  });
}

std::string record_key(const json& record) {
  return record.contains(key::key) && record.at(key::key).is_string()
             ? record.at(key::key).get<std::string>()
             : "?";
}

} // namespace

ExactResult diff_exact(std::istream& old_report, const std::string& old_path,
                       std::istream& new_report, const std::string& new_path, bool verbose,
                       const ReportLimits& limits) {
  RecordQueue old_queue, new_queue;
  json old_rest, new_rest;
  std::atomic<bool> abandoned{false};
  std::thread old_reader = reader(old_report, old_path, old_queue, old_rest, abandoned, limits);
  std::thread new_reader = reader(new_report, new_path, new_queue, new_rest, abandoned, limits);
  ExactResult result;
  long record_differences = 0;
  const std::size_t shown_records = verbose ? SIZE_MAX : 20;
  std::exception_ptr failed;
  try {
    for (;;) {
      std::optional<json> a = old_queue.pop();
      std::optional<json> b = new_queue.pop();
      if (!a && !b) {
        break;
      }
      std::vector<std::string> paths;
      std::string key;
      if (!a || !b) {
        key = record_key(a ? *a : *b);
        paths.push_back(std::string("only in ") + (a ? "old" : "new"));
      } else {
        key = record_key(*a);
        drop_timing(*a);
        drop_timing(*b);
        differing_paths(*a, *b, "", paths, 3);
      }
      if (!paths.empty()) {
        ++record_differences;
        if (static_cast<std::size_t>(record_differences) <= shown_records) {
          for (const std::string& path : paths) {
            result.lines.push_back(fmt::format("DIFFERS record | {} | {}", one_line(key), path));
          }
        }
      }
    }
  } catch (...) {
    failed = std::current_exception();
  }
  abandoned = true;
  old_queue.abandon();
  new_queue.abandon();
  old_reader.join();
  new_reader.join();
  if (failed) {
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

} // namespace pldamp::harness
