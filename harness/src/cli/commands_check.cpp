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
  Extracted measured;
  std::optional<Exact> truth;
  SampledJudgement judgement;
};

// A file read, measured and judged against the closed forms of `args`.
struct Checked {
  analytic::Contact<Exact> contact;
  solvers::End end;
  TrajectoryColumns columns;
  TrajectoryObservables x;
  std::vector<Row> rows;
};

Checked check(const ContactArgs& args, const std::string& path) {
  Checked c{make_contact<Exact>(args),
            parse_end(args.end) == ContactEnd::force ? solvers::End::force : solvers::End::overlap,
            load_trajectory(path),
            {},
            {}};
  ExtractOptions options;
  options.v0 = double(c.contact.v0());
  options.end = c.end;
  options.force_law = ForceLaw{double(c.contact.p()), double(c.contact.m()), double(c.contact.k()),
                               double(c.contact.alpha())};
  options.force_jumps_at_contact = c.contact.p() == 1 && c.contact.alpha() > 0;
  c.x = extract_observables(c.columns, options);
  const unsigned want =
      solvers::want_e | solvers::want_delta_max | solvers::want_t_peak | solvers::want_tau;
  const analytic::Observables<Exact> closed =
      analytic::observables(c.contact, analytic_want_of(want, c.end));
  for (const auto& [key, measured] :
       {std::pair{"e", &c.x.e}, std::pair{"delta_max", &c.x.delta_max},
        std::pair{"t_peak", &c.x.t_peak}, std::pair{"tau", &c.x.tau}}) {
    const Observable* observable = find_observable(key);
    const std::optional<Exact> truth = observable->exact(closed, c.end);
    c.rows.push_back({observable, *measured, truth, judge_extracted(*measured, truth)});
  }
  return c;
}

std::string columns_of(const TrajectoryColumns& c) {
  return std::string("t, delta") + (c.v ? ", v" : "") + (c.force ? ", F" : "");
}

Answer number_or_null(const std::optional<double>& value) {
  return value ? exact_number(*value) : Answer(nullptr);
}

Answer json_row(const Row& row) {
  Answer o;
  o["value"] = number_or_null(row.measured.value);
  o["sampling"] =
      number_or_null(row.measured.value ? std::optional(row.measured.sampling) : std::nullopt);
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
                       row.measured.value ? general(*row.measured.value) : "missing",
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
  const Checked checked = check(args.contact, args.trajectory);
  const auto& [contact, end, columns, x, rows] = checked;
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

TrajectoryCheck check_trajectory(const TrajectorySpec& spec, solvers::End scene_end) {
  TrajectoryCheck out{spec.label, spec.file, "", "", {}, {}};
  ContactArgs args;
  args.p = to_string_full(spec.p);
  (spec.damping_key == "e"       ? args.e
   : spec.damping_key == "alpha" ? args.alpha
                                 : args.alpha_eff) = to_string_full(spec.damping);
  args.v0 = to_string_full(spec.v0);
  args.m = to_string_full(spec.m);
  args.k = to_string_full(spec.k);
  const solvers::End end = spec.end.value_or(scene_end);
  args.end = end == solvers::End::force ? "force" : "overlap";
  out.inputs = fmt::format("p = {:g}, {} = {:g}, v0 = {:g}, m = {:g}, k = {:g}, end {}", spec.p,
                           spec.damping_key, spec.damping, spec.v0, spec.m, spec.k, args.end);
  try {
    const Checked checked = check(args, spec.file);
    for (const Row& row : checked.rows) {
      out.rows.push_back({std::string(row.observable->key_at(end)), row.measured.value,
                          row.measured.value ? std::optional(row.measured.sampling) : std::nullopt,
                          row.truth ? std::optional(static_cast<double>(*row.truth)) : std::nullopt,
                          row.judgement});
    }
    out.notes = checked.x.notes;
  } catch (const InputError& e) { // this file only: the run goes on
    out.failure = e.what();
  }
  return out;
}

} // namespace pldamp::harness
