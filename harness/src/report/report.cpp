// Writing the reports: each format the scene asks for, each file in place atomically.
#include "report/report.hpp"

#include "report/sections.hpp"

#include "common/files.hpp"
#include "common/parallel.hpp"

#include <filesystem>

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

WrittenReports write_reports(const RunReport& report, const std::string& folder, int jobs) {
  namespace fs = std::filesystem;
  require_writable_folder(folder);
  const std::vector<ReportFormat>& formats = report.plan.scene.formats;
  std::vector<std::string> paths(formats.size()), failures(formats.size());
  for_each_index(formats.size(), jobs, [&](std::size_t i) {
    const fs::path path =
        fs::path(folder) / ("report." + std::string(name_of(report_formats, formats[i])));
    try {
      switch (formats[i]) {
      case ReportFormat::json:
        write_file_atomically(path,
                              [&](const TextSink& put) { write_report_json(report, put, jobs); });
        break;
      case ReportFormat::csv:
        write_file_atomically(path,
                              [&](const TextSink& put) { write_report_csv(report, put, jobs); });
        break;
      case ReportFormat::md:
        write_file_atomically(path, report_markdown(report));
        break;
      case ReportFormat::html:
        write_file_atomically(path, report_html(report, "gnuplot", jobs));
        break;
      }
      paths[i] = path.string();
    } catch (const InputError& e) { // the other formats are still written
      failures[i] = e.what();
    }
  });
  WrittenReports out;
  for (std::size_t i = 0; i < formats.size(); ++i) {
    if (failures[i].empty()) {
      out.written.push_back(paths[i]);
    } else {
      out.failures.push_back(failures[i]);
    }
  }
  return out;
}

} // namespace pldamp::harness
