// The records of two reports paired by key as they are read (diff and diff --exact): a pair of
// one key is compared as soon as both have come, so two reports in one order (a scene's plan
// order, as pldamp writes them) are compared as they stream, holding nothing; only records out of
// step wait for their match, and what still waits at the end is in one report alone.
#pragma once

#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace pldamp::harness::diff {

template <class Record>
class MatchByKey {
public:
  // The next record of each report (none where it has ended), with its key; `compare(was, now)`
  // for every pair whose two records have both come.
  template <class Compare>
  void take(std::optional<Record> was, const std::string& was_key, std::optional<Record> now,
            const std::string& now_key, Compare&& compare) {
    if (was && now && was_key == now_key && waiting_old_.empty() && waiting_new_.empty()) {
      compare(*was, *now); // in step: nothing waits
      ++taken_;
      return;
    }
    if (was) {
      if (const auto match = waiting_new_.find(was_key); match != waiting_new_.end()) {
        compare(*was, match->second.second);
        waiting_new_.erase(match);
      } else {
        waiting_old_.insert_or_assign(was_key, std::pair(taken_, std::move(*was)));
      }
    }
    if (now) {
      if (const auto match = waiting_old_.find(now_key); match != waiting_old_.end()) {
        compare(match->second.second, *now);
        waiting_old_.erase(match);
      } else {
        waiting_new_.insert_or_assign(now_key, std::pair(taken_, std::move(*now)));
      }
    }
    ++taken_;
    most_waiting_ = std::max(most_waiting_, waiting_old_.size() + waiting_new_.size());
  }

  // After the last records: those no match came for, each report's in the order they came.
  std::vector<const Record*> only_in_old() const { return in_order(waiting_old_); }
  std::vector<const Record*> only_in_new() const { return in_order(waiting_new_); }
  // The most records that waited at once for the other report's of their key.
  std::size_t most_waiting() const { return most_waiting_; }

private:
  using Waiting = std::unordered_map<std::string, std::pair<std::size_t, Record>>;
  static std::vector<const Record*> in_order(const Waiting& waiting) {
    std::vector<const std::pair<std::size_t, Record>*> sorted;
    sorted.reserve(waiting.size());
    for (const auto& [key, record] : waiting) {
      sorted.push_back(&record);
    }
    std::sort(sorted.begin(), sorted.end(),
              [](const auto* a, const auto* b) { return a->first < b->first; });
    std::vector<const Record*> out;
    out.reserve(sorted.size());
    for (const auto* record : sorted) {
      out.push_back(&record->second);
    }
    return out;
  }
  Waiting waiting_old_, waiting_new_;
  std::size_t taken_ = 0, most_waiting_ = 0;
};

} // namespace pldamp::harness::diff
