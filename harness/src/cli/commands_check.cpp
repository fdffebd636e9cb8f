// `pldamp check TRAJECTORY.csv`: one contact's time series, dumped by a code that cannot be
// driven, measured between its samples and judged against the closed forms in Exact
// (judge/trajectory.hpp; MATH.md §10 "Measuring a sampled trajectory").
#include "cli/contact_args.hpp"
#include "common/observables.hpp"
#include "judge/trajectory.hpp"

#include <fmt/format.h>

namespace pldamp::harness {
namespace {

struct Row {
  const Observable* observable;
  const Extracted* measured;
  std::optional<Exact> truth;
  SampledJudgement judgement;
};

std::string columns_of(const TrajectoryColumns& c) {
  return std::string("t, delta") + (c.v ? ", v" : "") + (c.force ? ", F" : "");
}

Answer number_or_null(const std::optional<double>& value) {
  return value ? exact_number(*value) : Answer(nullptr);
}

Answer json_row(const Row& row) {
  Answer o;
  o["value"] = number_or_null(row.measured->value);
  o["sampling"] =
      number_or_null(row.measured->value ? std::optional(row.measured->sampling) : std::nullopt);
  o["truth"] = row.truth ? exact_number(*row.truth) : Answer(nullptr);
  o["error"] = number_or_null(row.judgement.error);
  o["rel_error"] = number_or_null(row.judgement.relative_error);
  o["rel_sampling"] = number_or_null(row.judgement.relative_sampling);
  if (row.judgement.explained) {
    o["verdict"] = verdict_name(row.judgement);
  } else {
    o["verdict"] = nullptr;
    o["why"] = row.judgement.why_not;
  }
  return o;
}

std::string text_of(const std::string& path, const TrajectoryColumns& columns,
                    const TrajectoryObservables& x, const analytic::Contact<Exact>& contact,
                    solvers::End end, const std::vector<Row>& rows) {
  auto general = [](const auto& value) { return fmt::format("{:.10g}", double(value)); };
  std::string out = fmt::format("pldamp check {}: {} rows ({}), {} in contact", path,
                                columns.t.size(), columns_of(columns), x.contact_samples);
  if (x.start.value && x.end.value) {
    out += fmt::format(", from t = {} to {}", general(*x.start.value), general(*x.end.value));
  }
  out += fmt::format("\np {}, alpha {}, v0 {}, m {}, k {}, end {}; truth: closed forms in {}\n\n",
                     double(contact.p()), double(contact.alpha()), double(contact.v0()),
                     double(contact.m()), double(contact.k()),
                     end == solvers::End::force ? "force" : "overlap", precision_name<Exact>());
  out += fmt::format("{:<10} {:>16} {:>16} {:>10} {:>9}  {}\n", "observable", "measured", "truth",
                     "rel error", "sampling", "verdict");
  std::string why;
  for (const Row& row : rows) {
    const std::string key(row.observable->key_at(end));
    const SampledJudgement& j = row.judgement;
    out += fmt::format("{:<10} {:>16} {:>16} {:>10} {:>9}  {}\n", key,
                       row.measured->value ? general(*row.measured->value) : "missing",
                       row.truth ? general(*row.truth) : "-",
                       j.relative_error ? fmt::format("{:+.2e}", *j.relative_error) : "-",
                       j.relative_sampling ? fmt::format("{:.2e}", *j.relative_sampling) : "-",
                       verdict_name(j));
    if (!j.explained) {
      why += fmt::format("{}: {}\n", key, j.why_not);
    }
  }
  out += why;
  for (const std::string& note : x.notes) {
    out += "note: " + note + "\n";
  }
  return out;
}

} // namespace

void run_check(const CheckArgs& args, std::ostream& out) {
  const analytic::Contact<Exact> contact = make_contact<Exact>(args.contact);
  const solvers::End end = parse_end(args.contact.end) == ContactEnd::force ? solvers::End::force
                                                                            : solvers::End::overlap;
  const TrajectoryColumns columns = load_trajectory(args.trajectory);
  ExtractOptions options;
  options.v0 = double(contact.v0());
  options.end = end;
  options.force_law = ForceLaw{double(contact.p()), double(contact.m()), double(contact.k()),
                               double(contact.alpha())};
  options.force_jumps_at_contact = contact.p() == 1 && contact.alpha() > 0;
  const TrajectoryObservables x = extract_observables(columns, options);

  const unsigned want =
      solvers::want_e | solvers::want_delta_max | solvers::want_t_peak | solvers::want_tau;
  const analytic::Observables<Exact> closed =
      analytic::observables(contact, analytic_want_of(want, end));
  std::vector<Row> rows;
  for (const auto& [key, measured] : {std::pair{"e", &x.e}, std::pair{"delta_max", &x.delta_max},
                                      std::pair{"t_peak", &x.t_peak}, std::pair{"tau", &x.tau}}) {
    const Observable* observable = find_observable(key);
    const std::optional<Exact> truth = observable->exact(closed, end);
    rows.push_back({observable, measured, truth, judge_extracted(*measured, truth)});
  }

  if (!args.contact.json) {
    out << text_of(args.trajectory, columns, x, contact, end, rows);
    return;
  }
  Answer o = describe(contact, args.contact);
  o["trajectory"] = args.trajectory;
  o["rows"] = columns.t.size();
  o["columns"] = columns_of(columns);
  o["contact_samples"] = x.contact_samples;
  o["t_start"] = number_or_null(x.start.value);
  o["t_end"] = number_or_null(x.end.value);
  for (const Row& row : rows) {
    o[std::string(row.observable->key_at(end))] = json_row(row);
  }
  o["notes"] = x.notes;
  emit(o, true, out);
}

} // namespace pldamp::harness
