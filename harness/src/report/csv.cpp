// report.csv: one row per record, its columns named as report.json's fields
// (common/report_schema.hpp).
#include "report/sections.hpp"

#include <fmt/format.h>

#include <array>

namespace pldamp::harness {

namespace key = schema::key;

namespace {

// A text field as RFC 4180 writes it: quoted, its quotes doubled, when it holds a comma, a quote or
// a line break (a solver's label may: the scene accepts any), as it is otherwise.
std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) {
    return std::string(text);
  }
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c == '"' ? "\"\"" : std::string(1, c);
  }
  return quoted + "\"";
}

} // namespace

void write_report_csv(const RunReport& report, const TextSink& put, int jobs) {
  const Plan& plan = report.plan;
  constexpr std::array columns{key::solver,
                               key::precision,
                               key::rtol,
                               key::atol,
                               key::steps_per_contact,
                               key::config,
                               key::p,
                               key::damping,
                               key::alpha_eff,
                               key::alpha,
                               key::v0,
                               key::m,
                               key::k,
                               key::contact,
                               key::outcome,
                               key::steps,
                               key::rhs_evals,
                               key::wall_seconds,
                               key::wall_seconds_slowest};
  std::string header = fmt::format("{}", fmt::join(columns, ","));
  for (const Observable* observable : plan.observables) {
    const std::string_view name = observable->key;
    header += fmt::format(",{0},{0}_{1},{0}_{2},{0}_{3},{0}_{4}", name, key::reference, key::error,
                          key::abs_error, key::rel_error);
  }
  header += "\n";
  put(header);
  // Numbers in the shortest form that reads back to the same double (0.05, not
  // 0.050000000000000003); an empty field is a value absent.
  const auto number = [](const std::optional<double>& x) {
    return x ? fmt::format("{}", *x) : std::string();
  };
  put_record_lines(report.records, jobs, put, [&](const Record& record, std::size_t) {
    const SolverConfig& config = plan.configs[record.config];
    const Cell& c = plan.cells[record.cell];
    const Point& point = plan.points[c.point];
    // The scene's contact (materials) whose m and k the cell has, as report.json names it.
    const MaterialContact* contact = contact_of(plan.scene, c.m, c.k);
    std::string row = fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", csv_field(config.name),
        config.precision, number(config.rtol), number(config.atol),
        config.steps_per_contact ? std::to_string(*config.steps_per_contact) : "",
        // The configuration's label, its one name: two of one solver and tolerance differ by
        // their end or onset phases alone, which no column above shows.
        csv_field(config.label()), point.p, csv_field(point.damping.label()), point.alpha_eff,
        record.alpha, c.v0, c.m, c.k, contact != nullptr ? csv_field(contact->name) : "",
        record.outcome_name(), record.steps, record.rhs_evals, record.wall_seconds,
        record.wall_seconds_slowest);
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      row += fmt::format(",{},{},{},{},{}", number(record.value[o]), number(record.reference[o]),
                         number(record.error[o]), number(record.abs_error[o]),
                         number(record.rel_error[o]));
    }
    return row + "\n";
  });
}

std::string report_csv(const RunReport& report) {
  return gather_text([&report](const TextSink& put) { write_report_csv(report, put); });
}

} // namespace pldamp::harness
