// `pldamp check TRAJECTORY.csv`: one contact's time series, dumped by a code that cannot be
// driven, measured between its samples and judged against the closed forms in Exact
// (judge/trajectory.hpp; MATH.md §10 "Measuring a sampled trajectory").
#include "ask/contact.hpp"
#include "cli/commands.hpp"
#include "common/observables.hpp"
#include "judge/trajectory_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>

namespace pldamp::harness {
namespace {

// --tolerance: one relative tolerance for every observable ("1e-3"), or some observables' own
// ("e=1e-3,tau=1e-2", named as the table names them under the contact end).
std::map<std::string, double> tolerances_of(const std::string& text,
                                            const std::vector<std::string>& keys) {
  std::string names;
  for (const std::string& key : keys) {
    names += (names.empty() ? "" : "|") + key;
  }
  const auto malformed = [&](const std::string& shown) {
    return InputError("--tolerance takes a relative tolerance T or " + names +
                      "=T,... with T > 0 (got " + shown + ")");
  };
  const auto value_of = [&](const std::string& number, const std::string& shown) {
    double value = 0;
    try {
      value = parse_real<double>("--tolerance", number);
    } catch (const InputError&) {
      throw malformed(shown);
    }
    if (!(value > 0 && value < 1)) { // a relative error of 1 or more says nothing
      throw InputError("a tolerance must be a relative one in (0, 1) (got " + shown + ")");
    }
    return value;
  };
  std::map<std::string, double> out;
  if (text.find('=') == std::string::npos) {
    for (const std::string& key : keys) {
      out[key] = value_of(text, text);
    }
    return out;
  }
  for (std::size_t from = 0; from <= text.size();) {
    const std::size_t comma = std::min(text.find(',', from), text.size());
    const std::string item = text.substr(from, comma - from);
    const std::size_t equals = item.find('=');
    const std::string name = item.substr(0, equals);
    if (item.empty()) { // "e=1e-3,," or a leading comma
      throw malformed(text);
    }
    if (std::find(keys.begin(), keys.end(), name) == keys.end()) {
      throw InputError("unknown observable in --tolerance, expected " + names + " (got " +
                       (equals == std::string::npos ? item : name) + ")");
    }
    if (out.count(name) != 0) {
      throw InputError("--tolerance names an observable twice (got " + name + ")");
    }
    out[name] = value_of(equals == std::string::npos ? "" : item.substr(equals + 1), item);
    from = comma + 1;
  }
  return out;
}

// A judged row passes when |rel error| <= its tolerance. The sampling estimate is not added to
// the tolerance (a coarse file would then pass any tolerance); an estimate larger than the
// tolerance fails the row instead: the file cannot tell the tolerance from its own sampling.
std::string failure_of(const CheckedRow& row, double tolerance) {
  const SampledJudgement& j = row.judgement;
  if (!j.relative_error) {
    return j.why_not;
  }
  if (!(std::abs(*j.relative_error) <= tolerance)) {
    return fmt::format("|rel error| {:.3g} > {:.3g}", std::abs(*j.relative_error), tolerance);
  }
  if (*j.relative_sampling > tolerance) {
    return fmt::format("its sampling estimate {:.3g} > {:.3g}: the file cannot resolve the "
                       "tolerance, dump more often",
                       *j.relative_sampling, tolerance);
  }
  return "";
}

std::string columns_of(const TrajectoryColumns& c) {
  return std::string("t, delta") + (c.v ? ", v" : "") + (c.force ? ", F" : "");
}

Answer exact_or_null(const std::optional<double>& value) {
  return value ? exact_number(*value) : Answer(nullptr);
}

Answer json_row(const CheckedRow& row) {
  Answer o;
  o["value"] = exact_or_null(row.measured.value);
  o["sampling"] =
      exact_or_null(row.measured.value ? std::optional(row.measured.sampling) : std::nullopt);
  o["truth"] = row.truth ? exact_number(*row.truth) : Answer(nullptr);
  o["error"] = exact_or_null(row.judgement.error);
  o["rel_error"] = exact_or_null(row.judgement.relative_error);
  o["rel_sampling"] = exact_or_null(row.judgement.relative_sampling);
  if (row.judgement.explained) {
    o["verdict"] = verdict_name(row.judgement);
  } else {
    o["verdict"] = nullptr;
    o["why"] = row.judgement.why_not;
  }
  if (row.tolerance) {
    o["tolerance"] = exact_number(*row.tolerance);
    o["pass"] = row.failure.empty();
    if (!row.failure.empty()) {
      o["failure"] = row.failure;
    }
  }
  return o;
}

// The judged rows that failed, by name: "t_peak, tau".
std::string failing_of(const std::vector<CheckedRow>& rows, solvers::End end) {
  std::string names;
  for (const CheckedRow& row : rows) {
    if (row.tolerance && !row.failure.empty()) {
      names += (names.empty() ? "" : ", ") + std::string(row.observable->key_at(end));
    }
  }
  return names;
}

// The judgement under --tolerance, after the table.
std::string tolerance_text(const std::vector<CheckedRow>& rows, solvers::End end) {
  std::string out = "\njudged: |rel error| <= tolerance (and the sampling estimate too)\n";
  for (const CheckedRow& row : rows) {
    if (row.tolerance) {
      out += fmt::format("{:<18} {:>9.3g}  {}\n", row.observable->key_at(end), *row.tolerance,
                         row.failure.empty() ? "pass" : "FAIL: " + row.failure);
    }
  }
  const std::string failing = failing_of(rows, end);
  return out + (failing.empty() ? "passed: every judged observable is within its tolerance\n"
                                : "FAILED: " + failing + "\n");
}

std::string text_of(const std::string& path, const TrajectoryColumns& columns,
                    const TrajectoryObservables& x, const analytic::Contact<Exact>& contact,
                    solvers::End end, const std::vector<CheckedRow>& rows) {
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
  out += fmt::format("{:<18} {:>16} {:>16} {:>10} {:>9}  {}\n", "observable", "measured", "truth",
                     "rel error", "sampling", "verdict");
  std::string why;
  for (const CheckedRow& row : rows) {
    const std::string key(row.observable->key_at(end));
    const SampledJudgement& j = row.judgement;
    out += fmt::format("{:<18} {:>16} {:>16} {:>10} {:>9}  {}\n", key,
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

int run_check(const CheckArgs& args, std::ostream& out) {
  std::map<std::string, double> tolerances;
  if (args.tolerance) { // refused before the file is read
    const solvers::End stated_end = parse_end(args.contact.end) == ContactEnd::force
                                        ? solvers::End::force
                                        : solvers::End::overlap;
    std::vector<std::string> keys;
    for (const char* key : checked_keys) {
      keys.emplace_back(find_observable(key)->key_at(stated_end));
    }
    tolerances = tolerances_of(*args.tolerance, keys);
  }
  CheckedTrajectory checked = check_trajectory_file(make_contact<Exact>(args.contact),
                                                    parse_end(args.contact.end) == ContactEnd::force
                                                        ? solvers::End::force
                                                        : solvers::End::overlap,
                                                    args.trajectory);
  const auto& [contact, end, columns, x, rows] = checked;
  if (args.tolerance) {
    for (CheckedRow& row : checked.rows) {
      const auto given = tolerances.find(std::string(row.observable->key_at(end)));
      if (given != tolerances.end()) {
        row.tolerance = given->second;
        row.failure = failure_of(row, given->second);
      }
    }
  }
  const bool passed = failing_of(rows, end).empty();
  if (!args.contact.json) {
    out << text_of(args.trajectory, columns, x, contact, end, rows);
    if (args.tolerance) {
      out << tolerance_text(rows, end);
    }
    return passed ? 0 : 1;
  }
  Answer o = describe(contact, args.contact);
  o["trajectory"] = args.trajectory;
  o["rows"] = columns.t.size();
  o["columns"] = columns_of(columns);
  o["contact_samples"] = x.contact_samples;
  o["t_start"] = exact_or_null(x.start.value);
  o["t_end"] = exact_or_null(x.end.value);
  for (const CheckedRow& row : rows) {
    o[std::string(row.observable->key_at(end))] = json_row(row);
  }
  o["notes"] = x.notes;
  if (args.tolerance) {
    o["passed"] = passed;
  }
  emit(o, true, out);
  return passed ? 0 : 1;
}

} // namespace pldamp::harness
