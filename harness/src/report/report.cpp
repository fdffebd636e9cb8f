// Writing the reports: each format the scene asks for, each file in place atomically.
#include "report/report.hpp"

#include "common/files.hpp"
#include "common/parallel.hpp"

#include <filesystem>

namespace pldamp::harness {

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
                              [&report](const TextSink& put) { write_report_json(report, put); });
        break;
      case ReportFormat::csv:
        write_file_atomically(path,
                              [&report](const TextSink& put) { write_report_csv(report, put); });
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
