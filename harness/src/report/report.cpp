// Writing the reports: each format the scene asks for, each file in place atomically.
#include "report/report.hpp"

#include "report/sections.hpp"

#include "common/files.hpp"
#include "common/parallel.hpp"

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <optional>

namespace pldamp::harness {

void put_record_lines(RecordRange records, int jobs, const TextSink& put,
                      const std::function<std::string(const Record&, std::size_t)>& line) {
  const std::size_t threads = static_cast<std::size_t>(std::max(jobs, 1));
  const std::size_t round = threads * record_lines_per_piece;
  for (std::size_t from = 0; from < records.size(); from += round) {
    const std::size_t to = std::min(records.size(), from + round);
    const std::size_t pieces = (to - from + record_lines_per_piece - 1) / record_lines_per_piece;
    const std::vector<std::string> texts =
        map_indices<std::string>(pieces, jobs, [&](std::size_t piece) {
          std::string text;
          std::optional<Record> holder;
          const std::size_t first = from + piece * record_lines_per_piece;
          for (std::size_t i = first; i < std::min(to, first + record_lines_per_piece); ++i) {
            text += line(records.at(i, holder), i);
          }
          return text;
        });
    for (const std::string& text : texts) {
      put(text);
    }
  }
}

std::string what_is_on_disk(const WrittenReports& files, const std::string& folder) {
  const auto names = [](const std::vector<std::string>& paths) {
    std::string text;
    for (const std::string& path : paths) {
      text += (text.empty() ? "" : ", ") + std::filesystem::path(path).filename().string();
    }
    return text;
  };
  if (files.written.empty()) {
    return unchanged_reports(folder);
  }
  return names(files.written) + (files.written.size() == 1 ? " is" : " are") + " this run's; " +
         names(files.kept) + (files.kept.size() == 1 ? " is" : " are") + " as before";
}

WrittenReports
write_reports(const RunReport& report, const std::string& folder, int jobs,
              const std::function<void(const std::filesystem::path&)>& before_stage) {
  namespace fs = std::filesystem;
  require_writable_folder(folder);
  const std::vector<ReportFormat>& formats = report.plan.scene.formats;
  const auto path_of = [&](ReportFormat format) {
    return fs::path(folder) / ("report." + std::string(name_of(report_formats, format)));
  };
  // Every format written whole under a temporary name first; none is put in place unless all
  // are, so the folder holds one run's reports (docs/run.md "Reports").
  std::vector<std::optional<StagedFile>> staged(formats.size());
  std::vector<std::string> failures(formats.size());
  for_each_index(formats.size(), jobs, [&](std::size_t i) {
    const fs::path path = path_of(formats[i]);
    try {
      // What a rename cannot replace, found before anything is put in place.
      if (fs::is_directory(fs::symlink_status(path))) {
        throw InputError("cannot write " + path.string() + " (Is a directory)");
      }
      if (before_stage) {
        before_stage(path);
      }
      switch (formats[i]) {
      case ReportFormat::json:
        staged[i].emplace(path, [&](const TextSink& put) { write_report_json(report, put, jobs); });
        break;
      case ReportFormat::csv:
        staged[i].emplace(path, [&](const TextSink& put) { write_report_csv(report, put, jobs); });
        break;
      case ReportFormat::md:
        staged[i].emplace(path, [&](const TextSink& put) { put(report_markdown(report)); });
        break;
      case ReportFormat::html:
        staged[i].emplace(path,
                          [&](const TextSink& put) { put(report_html(report, "gnuplot", jobs)); });
        break;
      }
    } catch (const InputError& e) {
      failures[i] = e.what();
    }
  });
  WrittenReports out;
  for (std::size_t i = 0; i < formats.size(); ++i) {
    if (!failures[i].empty()) {
      out.failures.push_back(failures[i]);
    }
  }
  // report.json last: the file a nightly diffs and merge reads is the new one only when every
  // other is. Renames alone remain, each atomic, microseconds apart; a machine that dies between
  // two of them leaves the formats before report.json new and report.json old.
  std::vector<std::size_t> order(formats.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_partition(order.begin(), order.end(),
                        [&](std::size_t i) { return formats[i] != ReportFormat::json; });
  std::vector<bool> committed(formats.size(), false);
  for (const std::size_t i : order) {
    if (!out.failures.empty()) {
      break;
    }
    try {
      staged[i]->commit();
      committed[i] = true;
    } catch (const InputError& e) {
      out.failures.push_back(e.what());
    }
  }
  for (std::size_t i = 0; i < formats.size(); ++i) { // listed in the scene's order
    (committed[i] ? out.written : out.kept).push_back(path_of(formats[i]).string());
  }
  return out;
}

} // namespace pldamp::harness
