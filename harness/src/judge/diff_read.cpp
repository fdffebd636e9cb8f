// diff's fast reader: a report.json as pldamp writes it, a record per line, its records parsed by
// simdjson. Reading was most of diff's time: nlohmann's lexer and tree took about 40 ns a byte;
// with simdjson's DOM parser (validating, as nlohmann is) two nightly reports are diffed in 1.2 s
// of CPU instead of 3.8 (docs/performance.md, "The harness"). The general reader
// (schema::read_report, then RecordFacts::of) stays the authority: this one returns nothing
// whenever it is not sure to read exactly what that one reads, and a record it doubts is read by
// nlohmann; tests/fuzz/report_fuzz.cpp compares the two on arbitrary input. A record's numbers are
// held to each other here as check_record holds them (inconsistent_reported, on the same numbers),
// and one that fails is left to the general reader, which says what disagrees.
#include "judge/diff_parts.hpp"

#include "common/input.hpp"
#include "common/record_consistency.hpp"

#include <fmt/format.h>
#include <simdjson.h>

#include <algorithm>
#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pldamp::harness::diff {

namespace {

namespace dom = simdjson::dom;

// The fields of a record the reader looks at, each allowed once (a repeated one, which nlohmann
// would keep the last of, is left to it).
enum Field : unsigned {
  f_key,
  f_config,
  f_damping,
  f_p,
  f_v0,
  f_m,
  f_k,
  f_outcome,
  f_failure,
  f_failed,
  f_precision,
  f_rhs_evals,
  f_steps,
  f_cpu_seconds,
  f_cpu_seconds_slowest,
  f_wall_seconds,
  f_wall_seconds_slowest,
  f_phases,             // read for the check of its numbers alone (check_record's)
  f_replica_difference, // the same
  f_observed,           // + the index in observed_fields
};
constexpr std::array<std::pair<std::string_view, unsigned>, f_observed> scalar_fields{{
    {key::key, f_key},
    {key::config, f_config},
    {key::damping, f_damping},
    {key::p, f_p},
    {key::v0, f_v0},
    {key::m, f_m},
    {key::k, f_k},
    {key::outcome, f_outcome},
    {key::failure, f_failure},
    {key::failed, f_failed},
    {key::precision, f_precision},
    {key::rhs_evals, f_rhs_evals},
    {key::steps, f_steps},
    {key::cpu_seconds, f_cpu_seconds},
    {key::cpu_seconds_slowest, f_cpu_seconds_slowest},
    {key::wall_seconds, f_wall_seconds},
    {key::wall_seconds_slowest, f_wall_seconds_slowest},
    {key::phases, f_phases},
    {key::replica_difference, f_replica_difference},
}};

std::optional<unsigned> record_field_named(std::string_view name) {
  for (const auto& [field_name, field] : scalar_fields) {
    if (name == field_name) {
      return field;
    }
  }
  for (std::size_t f = 0; f < observed_fields.size(); ++f) {
    if (name == observed_fields[f]) {
      return f_observed + static_cast<unsigned>(f);
    }
  }
  return std::nullopt;
}

// A number as nlohmann reads it (none: not a number). Both read an integer as a 64-bit one, and
// "-0" as the integer 0, converted to double; a number with a fraction or an exponent correctly
// rounded (a subnormal too); both refuse one beyond double's range. An integer beyond 64 bits
// simdjson refuses and nlohmann reads as a double: such a record is read by nlohmann, as the
// general reader reads it.
std::optional<double> number_of(dom::element value) {
  switch (value.type()) {
  case dom::element_type::INT64:
    return static_cast<double>(value.get_int64().value_unsafe());
  case dom::element_type::UINT64:
    return static_cast<double>(value.get_uint64().value_unsafe());
  case dom::element_type::DOUBLE:
    return value.get_double().value_unsafe();
  default:
    return std::nullopt;
  }
}

// Number::in of a member present with this value.
Number number_field(dom::element value) {
  if (const std::optional<double> x = number_of(value)) {
    return {.state = Number::State::number, .value = *x};
  }
  return {.state = value.is_null() ? Number::State::null : Number::State::absent};
}

// A count as check_record accepts it: null, or an integer from 0 to 2^53; none otherwise (an
// integer simdjson reads as a double, "-0" perhaps, is left to nlohmann).
std::optional<Number> count_field(dom::element value) {
  constexpr std::int64_t largest = std::int64_t{1} << 53;
  if (value.is_null()) {
    return Number{.state = Number::State::null};
  }
  std::int64_t count = 0;
  if (value.type() != dom::element_type::INT64 || value.get(count) != simdjson::SUCCESS ||
      count < 0 || count > largest) {
    return std::nullopt;
  }
  return Number{.state = Number::State::number, .value = static_cast<double>(count)};
}

// An array or an object: what may hold a key named twice (most of a record's members are
// numbers, which are asked this inline rather than through keys_once).
bool structured(dom::element value) {
  const dom::element_type type = value.type();
  return type == dom::element_type::ARRAY || type == dom::element_type::OBJECT;
}

// Whether no object within `value` names a key twice, as read_report requires; `names` is room
// for the names of each object on the way down.
bool keys_once(dom::element value, std::vector<std::string_view>& names) {
  if (value.type() == dom::element_type::ARRAY) {
    const dom::array items = value.get_array().value_unsafe();
    return std::all_of(items.begin(), items.end(),
                       [&](dom::element item) { return keys_once(item, names); });
  }
  if (value.type() != dom::element_type::OBJECT) {
    return true;
  }
  const dom::object members = value.get_object().value_unsafe();
  const std::size_t from = names.size();
  for (const dom::key_value_pair member : members) {
    names.push_back(member.key);
  }
  std::sort(names.begin() + static_cast<std::ptrdiff_t>(from), names.end());
  bool once = std::adjacent_find(names.begin() + static_cast<std::ptrdiff_t>(from), names.end()) ==
              names.end();
  for (auto member = members.begin(); once && member != members.end(); ++member) {
    once = keys_once((*member).value, names);
  }
  names.resize(from);
  return once;
}

// Room facts_from_dom reuses from one record to the next.
struct Scratch {
  std::vector<std::string_view> names; // of the members it does not read, and for keys_once
  std::vector<unsigned> named;         // per observable, the observed fields naming it
  std::vector<std::pair<std::string_view, double>> replica; // its replica_difference's numbers
  std::vector<ObservedNumbers> numbers;                     // as check_record judges them
};

// The member of ObservedNumbers each of observed_fields holds (schema::observed_number_fields).
const std::array<std::optional<double> ObservedNumbers::*, observed_fields.size()>
    observed_members = [] {
      std::array<std::optional<double> ObservedNumbers::*, observed_fields.size()> members{};
      for (std::size_t f = 0; f < observed_fields.size(); ++f) {
        for (const auto& [name, member] : schema::observed_number_fields) {
          if (std::string_view(name) == observed_fields[f]) {
            members[f] = member;
          }
        }
      }
      return members;
    }();

// Whether a record's numbers are consistent as check_record judges them (schema::observed_in,
// inconsistent_reported), from its facts, its phases and its replica differences.
bool consistent(const RecordFacts& facts, std::optional<double> phases, Scratch& scratch) {
  std::vector<ObservedNumbers>& numbers = scratch.numbers;
  numbers.clear();
  for (const RecordFacts::Observed& observed : facts.observed) {
    ObservedNumbers& n = numbers.emplace_back(ObservedNumbers{.key = observed.name});
    for (std::size_t f = 0; f < observed_fields.size(); ++f) {
      n.*observed_members[f] = observed.fields[f].number();
    }
  }
  for (const std::pair<std::string_view, double>& replica : scratch.replica) {
    // Not a structured binding: Clang 14 (the fuzz build) lets no lambda capture one.
    auto at = std::find_if(numbers.begin(), numbers.end(),
                           [&](const ObservedNumbers& n) { return n.key == replica.first; });
    if (at == numbers.end()) {
      at = numbers.insert(numbers.end(), ObservedNumbers{.key = replica.first});
    }
    at->replica_difference = replica.second;
  }
  return inconsistent_reported(
             {.run = {.outcome = facts.outcome, .several_phases = phases && *phases > 1},
              .failed = facts.failed,
              .has_failure = !facts.failure.empty(),
              .observed = numbers})
      .empty();
}

// RecordFacts::of of a record read_report would accept, parsed by simdjson; none when the record
// is not one read_report accepts or the two readings could differ in any way.
std::optional<RecordFacts> facts_from_dom(dom::element record, Scratch& scratch) {
  dom::object object;
  if (record.get(object) != simdjson::SUCCESS) {
    return std::nullopt;
  }
  RecordFacts facts;
  std::optional<double> cpu, cpu_slowest, wall, wall_slowest, phases;
  unsigned seen = 0; // the fields read (a required one of the wrong kind returns none at once)
  std::vector<std::string_view>& names = scratch.names; // the other members', each once too
  names.clear();
  scratch.named.clear();
  scratch.replica.clear();
  for (const dom::key_value_pair member : object) {
    const dom::element value = member.value;
    const std::optional<unsigned> field = record_field_named(member.key);
    // A key named twice anywhere in the record is refused (an observed field's object: below).
    const bool observed =
        field && *field >= f_observed && value.type() == dom::element_type::OBJECT;
    if (!observed && structured(value) && !keys_once(value, names)) {
      return std::nullopt;
    }
    if (!field) {
      if (std::find(names.begin(), names.end(), member.key) != names.end()) {
        return std::nullopt;
      }
      names.push_back(member.key);
      continue;
    }
    if (seen & (1u << *field)) {
      return std::nullopt;
    }
    seen |= 1u << *field;
    std::string_view text;
    const bool is_string = value.get(text) == simdjson::SUCCESS;
    switch (*field) {
    case f_key:
    case f_outcome:
      if (!is_string) {
        return std::nullopt;
      }
      (*field == f_key ? facts.key : facts.outcome) = text;
      break;
    case f_config:
    case f_damping:
      if (is_string) {
        (*field == f_config ? facts.config : facts.damping) = std::string(text);
      }
      break;
    case f_failure:
      if (is_string) {
        facts.failure = text;
      }
      break;
    case f_failed:
      if (value.get(facts.failed) != simdjson::SUCCESS) {
        return std::nullopt;
      }
      break;
    case f_precision:
      if (!is_string || !schema::known_precision(text)) {
        return std::nullopt;
      }
      break;
    case f_rhs_evals:
    case f_steps: {
      const std::optional<Number> count = count_field(value);
      if (!count) {
        return std::nullopt;
      }
      (*field == f_steps ? facts.steps : facts.rhs_evals) = *count;
      break;
    }
    case f_p:
    case f_v0:
    case f_m:
    case f_k:
    case f_cpu_seconds:
    case f_cpu_seconds_slowest:
    case f_wall_seconds:
    case f_wall_seconds_slowest: {
      std::optional<double>& into = *field == f_p                     ? facts.p
                                    : *field == f_v0                  ? facts.v0
                                    : *field == f_m                   ? facts.m
                                    : *field == f_k                   ? facts.k
                                    : *field == f_cpu_seconds         ? cpu
                                    : *field == f_cpu_seconds_slowest ? cpu_slowest
                                    : *field == f_wall_seconds        ? wall
                                                                      : wall_slowest;
      into = number_of(value);
      const bool time = *field != f_p && *field != f_v0 && *field != f_m && *field != f_k;
      if (time && !value.is_null() && !(into && *into >= 0)) {
        return std::nullopt; // check_record requires null or a number >= 0
      }
      break;
    }
    case f_phases:
      phases = number_of(value);
      break;
    case f_replica_difference: { // an object of a number per observable (its keys checked above)
      dom::object values;
      if (value.get(values) == simdjson::SUCCESS) {
        for (const dom::key_value_pair item : values) {
          if (const std::optional<double> difference = number_of(item.value)) {
            scratch.replica.emplace_back(item.key, *difference);
          }
        }
      }
      break;
    }
    default: { // an observed field: an object of a number (or null) per observable
      const std::size_t f = *field - f_observed;
      dom::object values;
      if (value.get(values) != simdjson::SUCCESS) {
        if (f == rel_error_field) {
          return std::nullopt; // read_report requires an object
        }
        break;
      }
      for (const dom::key_value_pair item : values) {
        if (structured(item.value) && !keys_once(item.value, names)) {
          return std::nullopt;
        }
        const Number number = number_field(item.value);
        if (f == rel_error_field && (number.state == Number::State::absent ||
                                     (number.state == Number::State::number && number.value < 0))) {
          return std::nullopt; // read_report requires null or a number >= 0
        }
        auto at = std::find_if(facts.observed.begin(), facts.observed.end(),
                               [&](const RecordFacts::Observed& o) { return o.name == item.key; });
        if (at == facts.observed.end()) {
          facts.observed.push_back({.name = std::string(item.key), .fields = {}});
          scratch.named.push_back(0);
          at = facts.observed.end() - 1;
        }
        unsigned& named = scratch.named[static_cast<std::size_t>(at - facts.observed.begin())];
        if (named & (1u << f)) {
          return std::nullopt; // an observable named twice in one object
        }
        named |= 1u << f;
        at->fields[f] = number;
      }
      break;
    }
    }
  }
  constexpr unsigned required =
      1u << f_key | 1u << f_outcome | 1u << f_failed | 1u << (f_observed + rel_error_field);
  if ((seen & required) != required) {
    return std::nullopt;
  }
  std::sort(facts.observed.begin(), facts.observed.end(),
            [](const RecordFacts::Observed& a, const RecordFacts::Observed& b) {
              return a.name < b.name;
            });
  if (!consistent(facts, phases, scratch)) {
    return std::nullopt; // the general reader says what is inconsistent
  }
  facts.cpu = cpu.has_value();
  facts.seconds = facts.cpu ? cpu : wall;
  facts.seconds_slowest = facts.cpu ? cpu_slowest : wall_slowest;
  return facts;
}

} // namespace

std::string describe(const RecordFacts& facts) {
  const auto number = [](const Number& n) {
    return n.state == Number::State::number ? fmt::format("{}", n.value)
           : n.state == Number::State::null ? std::string("null")
                                            : std::string("absent");
  };
  const auto text = [](const std::optional<std::string>& x) {
    return x ? fmt::format("{:?}", *x) : "none";
  };
  const auto optional = [](const std::optional<double>& x) {
    return x ? fmt::format("{}", *x) : "none";
  };
  std::string out = fmt::format(
      "key={:?} config={} damping={} p={} v0={} m={} k={} outcome={:?} failure={:?} failed={} "
      "rhs_evals={} steps={} cpu={} seconds={} slowest={}",
      facts.key, text(facts.config), text(facts.damping), optional(facts.p), optional(facts.v0),
      optional(facts.m), optional(facts.k), facts.outcome, facts.failure, facts.failed,
      number(facts.rhs_evals), number(facts.steps), facts.cpu, optional(facts.seconds),
      optional(facts.seconds_slowest));
  for (const RecordFacts::Observed& observed : facts.observed) {
    out += fmt::format(" {:?}:", observed.name);
    for (const Number& field : observed.fields) {
      out += fmt::format(" {}", number(field));
    }
  }
  return out;
}

std::optional<json> stream_record_lines(std::istream& in, const std::string& path,
                                        const ReportLimits& limits, const HeadSink& at_records,
                                        const std::function<void(RecordFacts&&)>& each) {
  dom::parser parser;
  Scratch scratch; // for facts_from_dom
  return read_report_lines(
      in, path, limits, at_records,
      [&](std::string& line, std::size_t length, std::size_t index) -> std::optional<std::size_t> {
        std::optional<RecordFacts> facts;
        dom::element record;
        if (parser.parse(line.data(), length, false).get(record) == simdjson::SUCCESS) {
          facts = facts_from_dom(record, scratch);
        }
        if (!facts) { // a record simdjson refuses or doubts: read as the general reader reads it
          try {
            facts = RecordFacts::of(
                schema::read_record(std::string_view(line).substr(0, length), path,
                                    std::string(key::records) + "[" + std::to_string(index) + "]"));
          } catch (const std::exception&) {
            return std::nullopt; // the general reader says what is wrong
          }
        }
        const std::size_t key_hash = std::hash<std::string_view>{}(facts->key);
        each(std::move(*facts));
        return key_hash;
      });
}

std::optional<Report> read_record_lines(std::istream& in, const std::string& path,
                                        const ReportLimits& limits) {
  Report report;
  std::optional<json> rest =
      stream_record_lines(in, path, limits, nullptr,
                          [&](RecordFacts&& facts) { report.records.push_back(std::move(facts)); });
  if (!rest) {
    return std::nullopt;
  }
  report.rest = std::move(*rest);
  return report;
}

} // namespace pldamp::harness::diff
