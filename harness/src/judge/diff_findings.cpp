// diff's output grammar (docs/ci.md): findings grouped into lines, and the two comparisons every
// comparator makes, of an error and of numbers that came or went.
#include "judge/diff_parts.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace pldamp::harness::diff {

void Findings::add(Finding finding) {
  const auto [at, fresh] = index_.try_emplace(
      std::tuple(finding.severity, finding.what, finding.owner, finding.subject), groups_.size());
  if (fresh) {
    groups_.push_back({.worst = finding, .count = 0, .details = {}});
  }
  Group& group = groups_[at->second];
  ++group.count;
  if (finding.rank > group.worst.rank) {
    group.worst = finding;
  }
  if (keep_details_) {
    group.details.push_back(finding.detail);
  }
}

void Findings::write(DiffResult& result, bool verbose) const {
  for (const Severity severity : {Severity::regression, Severity::change}) {
    for (const Group& group : groups_) {
      if (group.worst.severity != severity) {
        continue;
      }
      const Finding& f = group.worst;
      (severity == Severity::regression ? result.regressions : result.changes) += 1;
      result.lines.push_back(fmt::format(
          "{} {} | {} | {} | {} {}{} | {}{}",
          severity == Severity::regression ? "REGRESSION" : "CHANGE", f.what, field_text(f.owner),
          field_text(f.subject), group.count, f.unit, group.count == 1 ? "" : "s",
          field_text(f.worst), f.cell.empty() ? "" : " at " + field_text(f.cell)));
      if (verbose) {
        for (const std::string& detail : group.details) {
          result.lines.push_back("  " + field_text(detail, true));
        }
      }
    }
  }
}

std::string field_text(std::string_view text, bool keep_separators) {
  std::string out = one_line(text);
  for (std::size_t at = out.find(" | "); !keep_separators && at != std::string::npos;
       at = out.find(" | ", at + 3)) {
    out.replace(at, 3, " / ");
  }
  return out;
}

std::string number_text(double x) {
  return fmt::format("{:.3g}", x);
}

std::string factor_text(double before, double after) {
  if (before == 0) {
    return "";
  }
  return fmt::format(" (x{:.3g})", after / before);
}

double precision_noise(const std::string& precision) {
  double epsilon = 0;
  with_precision(precision, [&]<SupportedReal Real>() {
    epsilon = static_cast<double>(std::numeric_limits<Real>::epsilon());
  });
  return 16 * epsilon;
}

Noise::Noise(const json& report) {
  for (const json& config : array_in(member_or_null(report, key::scene), key::configs)) {
    by_label_[string_in(config, key::label)] = precision_noise(string_in(config, key::precision));
  }
}

double Noise::of(const std::string& label) const {
  const auto found = by_label_.find(label);
  return found != by_label_.end() ? found->second : precision_noise("double");
}

void compare_error(Findings& findings, const Finding& base, double before, double after,
                   double noise, double factor) {
  Finding f = base;
  f.worst = number_text(before) + " -> " + number_text(after) + factor_text(before, after);
  f.detail += ": " + f.worst;
  if (after > noise && after > factor * before) {
    f.severity = Severity::regression;
    f.what = base.what + "_grew";
    f.rank = before > 0 ? after / before : std::numeric_limits<double>::infinity();
    findings.add(f);
  } else if (after == 0 && before > noise) {
    f.severity = Severity::regression;
    f.what = base.what + "_vanished";
    f.rank = before;
    findings.add(f);
  } else if (before > noise && after * factor < before) {
    f.severity = Severity::change;
    f.what = base.what + "_fell";
    f.rank = after > 0 ? before / after : std::numeric_limits<double>::infinity();
    findings.add(f);
  }
}

Number Number::in(const json& object, std::string_view key) {
  const json& found = member_or_null(object, key);
  if (found.is_number()) {
    return {.state = State::number, .value = found.get<double>()};
  }
  return {.state = found.is_null() && object.is_object() && object.contains(key) ? State::null
                                                                                 : State::absent};
}

void compare_fields(Findings& findings, const Finding& base, const std::string& subject,
                    const std::vector<FieldNow>& fields) {
  std::string lost, appeared;
  for (const FieldNow& f : fields) {
    if (f.before.state == Number::State::number && !f.after) {
      lost +=
          fmt::format("{}{} {}", lost.empty() ? "" : ", ", f.field, number_text(f.before.value));
    } else if (f.before.state == Number::State::null && f.after) {
      appeared +=
          fmt::format("{}{} {}", appeared.empty() ? "" : ", ", f.field, number_text(*f.after));
    }
  }
  Finding f = base;
  f.subject = subject;
  if (!lost.empty()) {
    f.severity = Severity::regression;
    f.what = "number_lost";
    f.worst = lost + " -> null";
    f.rank = 1;
  } else if (!appeared.empty()) {
    f.severity = Severity::change;
    f.what = "number_appeared";
    f.worst = "null -> " + appeared;
  } else {
    return;
  }
  f.detail += ": " + f.worst;
  findings.add(f);
}

void compare_numbers(Findings& findings, const Finding& base, const json& was, const json& now,
                     const std::set<std::string>& removed) {
  if (!was.is_object()) {
    return;
  }
  for (const auto& [name, fields] : was.items()) {
    if (removed.contains(name) || !fields.is_object()) {
      continue;
    }
    std::vector<FieldNow> changes;
    for (const auto& [field, value] : fields.items()) {
      changes.push_back({.field = field,
                         .before = Number::in(fields, field),
                         .after = number_in(member_or_null(now, name), field)});
    }
    compare_fields(findings, base, name, changes);
  }
}

json field_of(const json& object, const std::string& subject, const std::string& field) {
  return json{{subject, {{field, member_or_null(object, field)}}}};
}

} // namespace pldamp::harness::diff
