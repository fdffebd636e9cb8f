// Writing the reports: each format the scene asks for, each file in place atomically.
#include "report/report.hpp"

#include "common/files.hpp"

#include <filesystem>

namespace pldamp::harness {

WrittenReports write_reports(const RunReport& report, const std::string& folder) {
  namespace fs = std::filesystem;
  require_writable_folder(folder);
  WrittenReports out;
  for (const ReportFormat format : report.plan.scene.formats) {
    const fs::path path =
        fs::path(folder) / ("report." + std::string(name_of(report_formats, format)));
    try {
      switch (format) {
      case ReportFormat::json:
        write_file_atomically(path, report_json_text(report));
        break;
      case ReportFormat::csv:
        write_file_atomically(path, report_csv(report));
        break;
      case ReportFormat::md:
        write_file_atomically(path, report_markdown(report));
        break;
      case ReportFormat::html:
        write_file_atomically(path, report_html(report, "gnuplot"));
        break;
      }
      out.written.push_back(path.string());
    } catch (const InputError& e) { // the other formats are still written
      out.failures.push_back(e.what());
    }
  }
  return out;
}

} // namespace pldamp::harness
