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

// The nesting depth of a JSON text read so far, a line at a time: where a line that looks like
// the report's records (`"records": [` at the top level) really is.
class Depth {
public:
  void read(std::string_view line) {
    for (const char c : line) {
      if (in_string_) {
        in_string_ = escaped_ || c != '"';
        escaped_ = !escaped_ && c == '\\';
      } else if (c == '"') {
        in_string_ = true;
      } else if (c == '{' || c == '[') {
        ++depth_;
      } else if (c == '}' || c == ']') {
        --depth_;
      }
    }
  }
  bool top_level() const { return depth_ == 1 && !in_string_; }

private:
  long depth_ = 0;
  bool in_string_ = false, escaped_ = false;
};

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

std::optional<json> read_report_lines(std::istream& in, const std::string& path,
                                      const ReportLimits& limits, const HeadSink& at_records,
                                      const RecordLineSink& each) {
  // The lines report_json_text writes around the records, and each record's indent.
  constexpr std::string_view records_open = R"( "records": [)", record_indent = "  ";
  std::string rest; // the report without its records' lines: read_report checks it
  std::string line;
  // Lines are read a chunk at a time up to limits.line bytes: a longer one (a report on one line,
  // or no report at all) is not pldamp's layout, and is never held whole here. `too_long` says
  // why reading stopped before the end.
  std::array<char, 65536> chunk; // NOLINT: filled by getline before it is read
  bool too_long = false;
  const auto next_line = [&] {
    line.clear();
    for (;;) {
      in.getline(chunk.data(), static_cast<std::streamsize>(chunk.size()));
      const auto count = static_cast<std::size_t>(in.gcount());
      if (in.eof()) { // the last line, without a newline, or nothing
        line.append(chunk.data(), count);
        too_long = line.size() > limits.line;
        return !line.empty() && !too_long;
      }
      if (!in.fail()) { // the newline was read (and counted)
        line.append(chunk.data(), count - 1);
        return line.size() <= limits.line || !(too_long = true);
      }
      // A full chunk without a newline: the line goes on.
      in.clear(in.rdstate() & ~std::ios::failbit);
      line.append(chunk.data(), count);
      if (line.size() > limits.line) {
        too_long = true;
        return false;
      }
    }
  };
  // The general reader's words when the text outside the records holds too many values (the
  // records, read or not, were not amiss); none for any other refusal (it says what is wrong).
  const auto checked = [&](const std::string& text) -> std::optional<json> {
    try {
      return schema::read_report(text, path, limits.values);
    } catch (const std::exception& e) {
      if (schema::too_many_values(e)) {
        throw;
      }
      return std::nullopt;
    }
  };
  enum class Where { before, inside, after } where = Where::before; // the records
  Depth depth;                   // of the text before the records
  bool comma_after_last = false; // whether the last record line ended with one
  // Whether the schema comes before the records, as pldamp writes it: the general reader keeps
  // records read before it, which count among the values it holds at most (limits.values).
  bool schema_first = false;
  std::size_t records = 0;
  // Each record's key once, as the general reader requires, told by the keys' hashes: 8 bytes a
  // record rather than its key. Two equal hashes, of equal keys or not, are left to the general
  // reader (among the 4·10^6 records of a 10^7-run map, unequal keys share a hash with odds of
  // about 1 in 2 million).
  std::vector<std::size_t> key_hashes;
  // The sections before the records: a reader given them has all but the figures (what
  // follows the records in pldamp's layout); a report with more after its records is left to
  // the general reader.
  std::vector<std::string> head_sections;
  while (next_line()) {
    if (line.find('\0') != std::string::npos) {
      return std::nullopt; // nlohmann ends its input at a NUL, simdjson refuses it
    }
    if (where != Where::inside) {
      bool records_begin = false;
      if (where == Where::before) {
        records_begin = line == records_open && depth.top_level();
        schema_first = schema_first || (depth.top_level() && line.starts_with(R"( "schema":)"));
        depth.read(line);
      }
      // A line never begins inside a JSON string (a string holds no raw newline), so its
      // indentation and a blank line mean nothing: not kept.
      const std::size_t text = line.find_first_not_of(" \t\r");
      if (text != std::string::npos) {
        rest.append(line, text);
        rest += '\n';
      }
      if (rest.size() > limits.rest) {
        throw InputError(fmt::format("{}: its text outside the records is larger than {} MiB: "
                                     "not a report pldamp wrote",
                                     one_line(path), double(limits.rest) / (1 << 20)));
      }
      if (records_begin) {
        if (!schema_first) {
          return std::nullopt;
        }
        // Everything before the records, checked as the whole will be: what a reader of the
        // records needs first (the scene, its thresholds).
        std::optional<json> head = checked(rest + "]}");
        if (!head) {
          return std::nullopt;
        }
        where = Where::inside;
        for (const auto& [name, value] : head->items()) {
          head_sections.push_back(name);
        }
        if (at_records) {
          at_records(std::move(*head));
        }
      }
      continue;
    }
    if (line == " ]" || line == " ],") {
      if (comma_after_last) {
        return std::nullopt;
      }
      where = Where::after;
      rest += line.substr(1);
      rest += '\n';
      continue;
    }
    if (!line.starts_with(record_indent) || (records > 0 && !comma_after_last)) {
      return std::nullopt; // not pldamp's layout: the general reader reads it
    }
    comma_after_last = line.ends_with(',');
    const std::size_t length = line.size() - (comma_after_last ? 1 : 0);
    // simdjson reads up to SIMDJSON_PADDING bytes past the end.
    line.reserve(line.size() + simdjson::SIMDJSON_PADDING);
    const std::optional<std::size_t> key_hash = each(line, length, records);
    if (!key_hash) {
      return std::nullopt;
    }
    key_hashes.push_back(*key_hash);
    ++records;
  }
  if (where != Where::after || in.bad() || too_long) {
    return std::nullopt;
  }
  std::sort(key_hashes.begin(), key_hashes.end());
  if (std::adjacent_find(key_hashes.begin(), key_hashes.end()) != key_hashes.end()) {
    return std::nullopt;
  }
  std::optional<json> whole = checked(rest);
  if (!whole || !whole->at(key::records).empty()) {
    return std::nullopt; // another records array in the rest (a key named twice)
  }
  for (const auto& [name, value] : whole->items()) {
    if (name != key::figures &&
        std::find(head_sections.begin(), head_sections.end(), name) == head_sections.end()) {
      return std::nullopt;
    }
  }
  return whole;
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

void read_again(std::istream& in, std::istream::pos_type start, const std::string& path) {
  in.clear();
  if (!in.seekg(start)) {
    throw InputError("cannot read " + path + " again");
  }
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
