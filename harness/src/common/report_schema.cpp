#include "common/report_schema.hpp"

#include "common/input.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <streambuf>
#include <unordered_map>
#include <vector>

namespace pldamp::harness::schema {

std::string cell_text(const RecordId& id) {
  return "p=" + to_string_full(id.p) + " " + id.damping + " v0=" + to_string_full(id.v0) +
         " m=" + to_string_full(id.m) + " k=" + to_string_full(id.k);
}

std::string record_key(const RecordId& id) {
  return id.config + " | " + cell_text(id);
}

std::optional<RecordId> read_record_id(const nlohmann::json& record) {
  const std::optional<double> p = number_in(record, key::p), v0 = number_in(record, key::v0),
                              m = number_in(record, key::m), k = number_in(record, key::k);
  const nlohmann::json& config = member_or_null(record, key::config);
  const nlohmann::json& damping = member_or_null(record, key::damping);
  if (!p || !v0 || !m || !k || !config.is_string() || !damping.is_string()) {
    return std::nullopt;
  }
  return RecordId{.config = config.get<std::string>(),
                  .p = *p,
                  .damping = damping.get<std::string>(),
                  .v0 = *v0,
                  .m = *m,
                  .k = *k};
}

nlohmann::ordered_json number_or_null(const std::optional<double>& x) {
  return x && std::isfinite(*x) ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
}

const nlohmann::json& member_or_null(const nlohmann::json& object, std::string_view key) {
  static const nlohmann::json null;
  if (!object.is_object()) {
    return null;
  }
  const auto found = object.find(key);
  return found != object.end() ? *found : null;
}

std::optional<double> number_in(const nlohmann::json& object, std::string_view key) {
  const nlohmann::json& found = member_or_null(object, key);
  return found.is_number() ? std::optional(found.get<double>()) : std::nullopt;
}

std::string string_in(const nlohmann::json& object, std::string_view key) {
  const nlohmann::json& found = member_or_null(object, key);
  return found.is_string() ? found.get<std::string>() : "";
}

const nlohmann::json& array_in(const nlohmann::json& object, std::string_view key) {
  static const nlohmann::json empty = nlohmann::json::array();
  const nlohmann::json& found = member_or_null(object, key);
  return found.is_array() ? found : empty;
}

namespace {

// A value for a message: a scalar as written (at most 40 characters), else its type. Never
// dump() a container: it recurses once per level, and 80 000 levels overflowed the stack.
std::string shown(const nlohmann::json& value) {
  if (value.is_structured()) {
    return std::string("an ") + value.type_name();
  }
  return value.dump(-1, ' ', true).substr(0, 40);
}

// `where` in `report` must hold a value `is` accepts; else "PATH: WHERE must be WHAT".
template <class Check>
void expect(const nlohmann::json& value, Check is, const std::string& path,
            const std::string& where, const std::string& what) {
  if (!is(value)) {
    throw InputError(path + ": " + where + " must be " + what + " (got " + shown(value) + ")");
  }
}

const nlohmann::json& member(const nlohmann::json& object, const char* key, const std::string& path,
                             const std::string& where) {
  const auto found = object.find(key);
  if (found == object.end()) {
    throw InputError(path + ": " + where + " has no \"" + key + "\"");
  }
  return *found;
}

// `value`, at `where`, must be an object whose members `names` are strings.
void expect_strings(const nlohmann::json& value, std::initializer_list<const char*> names,
                    const std::string& path, const std::string& where) {
  expect(
      value, [](const nlohmann::json& j) { return j.is_object(); }, path, where, "an object");
  for (const char* name : names) {
    expect(
        member(value, name, path, where), [](const nlohmann::json& j) { return j.is_string(); },
        path, where + "." + name, "a string");
  }
}

// An error or a time: unknown (null), or a number a measurement can be.
bool null_or_at_least_0(const nlohmann::json& j) {
  return j.is_null() || (j.is_number() && !(j.get<double>() < 0));
}

// A count diff holds exactly (as a double: up to 2^53) and shows as written: an integer, as
// pldamp writes one (never 1.5, nor 120.0).
bool null_or_count(const nlohmann::json& j) {
  constexpr std::uint64_t largest = std::uint64_t{1} << 53;
  return j.is_null() || (j.is_number_unsigned() && j.get<std::uint64_t>() <= largest) ||
         (j.is_number_integer() && j.get<std::int64_t>() == 0); // "-0"
}

// The claims as read_report checks them.
void check_claims(const nlohmann::json& claims, const std::string& path) {
  std::size_t i = 0;
  for (const nlohmann::json& claim : claims) {
    const std::string where = std::string(key::claims) + "[" + std::to_string(i++) + "]";
    expect_strings(claim, {key::name, key::verdict}, path, where);
    if (claim.contains(key::expect)) { // reports before the claim kinds have none
      expect(
          claim.at(key::expect),
          [](const nlohmann::json& j) { return j == word::holds || j == word::fails; }, path,
          where + "." + key::expect, "holds or fails");
    }
  }
}

} // namespace

bool known_precision(std::string_view name) {
  bool known = false;
  for_each_precision([&]<class Real>() { known = known || precision_name<Real>() == name; });
  return known;
}

void check_record(const nlohmann::json& record, const std::string& path, const std::string& where) {
  expect_strings(record, {key::key, key::outcome}, path, where);
  expect(
      member(record, key::failed, path, where),
      [](const nlohmann::json& j) { return j.is_boolean(); }, path, where + "." + key::failed,
      "true or false");
  const std::string errors_at = where + "." + key::rel_error;
  const nlohmann::json& errors = member(record, key::rel_error, path, where);
  expect(
      errors, [](const nlohmann::json& j) { return j.is_object(); }, path, errors_at, "an object");
  for (const auto& [name, error] : errors.items()) {
    expect(error, null_or_at_least_0, path, errors_at + "." + name, "null or a number >= 0");
  }
  if (const auto precision = record.find(key::precision); precision != record.end()) {
    expect(
        *precision,
        [](const nlohmann::json& j) {
          return j.is_string() && known_precision(j.get<std::string>());
        },
        path, where + "." + key::precision, "one of " + precision_names());
  }
  // What diff compares of a record's work and time: "-5" steps became "CHANGE 120 -> -5", 1.5 was
  // shown as 2, and a negative or a textual CPU time silently left the time unjudged.
  for (const char* name : {key::steps, key::rhs_evals}) {
    if (const auto count = record.find(name); count != record.end()) {
      expect(*count, null_or_count, path, where + "." + name,
             "null or a whole number from 0 to 2^53");
    }
  }
  for (const char* name :
       {key::cpu_seconds, key::cpu_seconds_slowest, key::wall_seconds, key::wall_seconds_slowest}) {
    if (const auto time = record.find(name); time != record.end()) {
      expect(*time, null_or_at_least_0, path, where + "." + name, "null or a number >= 0");
    }
  }
  // What its numbers say of each other (common/record_consistency.hpp): diff judges a record by
  // its rel_error, which an error or a value edited alone, or an unknown outcome, left silently
  // standing.
  const std::vector<ObservedNumbers> observed = observed_in(record);
  const std::optional<double> phases = number_in(record, key::phases);
  if (const std::string why = inconsistent_reported(
          {.run = {.outcome = record.at(key::outcome).get_ref<const std::string&>(),
                   .several_phases = phases && *phases > 1},
           .failed = record.at(key::failed).get<bool>(),
           .has_failure = !string_in(record, key::failure).empty(),
           .observed = observed});
      !why.empty()) {
    throw InputError(path + ": " + where + " (" +
                     one_line(record.at(key::key).get_ref<const std::string&>(), 200) +
                     "): " + why);
  }
}

std::vector<ObservedNumbers> observed_in(const nlohmann::json& record) {
  std::vector<ObservedNumbers> observed;
  for (const auto& [field, number_of] : observed_number_fields) {
    const nlohmann::json& values = member_or_null(record, field);
    if (!values.is_object()) {
      continue;
    }
    for (const auto& item : values.items()) {
      const std::string& name = item.key();
      auto at = std::find_if(observed.begin(), observed.end(),
                             [&](const ObservedNumbers& o) { return o.key == name; });
      if (at == observed.end()) {
        observed.push_back({.key = name});
        at = observed.end() - 1;
      }
      if (item.value().is_number()) {
        (*at).*number_of = item.value().get<double>();
      }
    }
  }
  return observed;
}

namespace {

using nlohmann::json;

// read_report's refusal of a text that holds too many values (too_many_values tells it apart).
struct TooManyValues : InputError {
  using InputError::InputError;
};

// What read_report does as nlohmann's SAX parser reads a report: the tree built as nlohmann's
// own DOM parser builds it, but
// - each record (an element of the top-level records array) in a tree of its own, checked and
//   handed to the sink as soon as it is whole, and never kept (one record in memory at a time);
//   a record read before the schema's version is known is kept in the report's tree until it is,
//   and a record of another version skipped;
// - in time linear in the text: nlohmann's callback parser (json::parse with a callback, used
//   before) looked through the parent container at each object's end, and 800 000 `{}` in an
//   array took minutes;
// - a key named twice in one object refused (nlohmann keeps the last: a record's field, or its
//   schema, would silently be the last one);
// - the values and keys kept in the report's tree counted, at most max_values of them: the tree
//   takes up to about 100 bytes each (docs/design.md §5), where the text of `[{},{},...]` takes 3.
// `where` set reads a lone record instead (read_record): no sections, nothing counted.
class Reader {
public:
  Reader(const std::string& path, const RecordSink& each, std::size_t max_values,
         const std::string* where = nullptr)
      : path_(path), each_(each), max_values_(max_values), where_(where) {}

  // nlohmann's SAX interface.
  bool null() { return scalar(json(nullptr)); }
  bool boolean(bool b) { return scalar(json(b)); }
  bool number_integer(json::number_integer_t x) { return scalar(json(x)); }
  bool number_unsigned(json::number_unsigned_t x) { return scalar(json(x)); }
  bool number_float(json::number_float_t x, const json::string_t& /*text*/) {
    return scalar(json(x));
  }
  bool string(json::string_t& s) { return scalar(json(std::move(s))); }
  bool binary(json::binary_t& /*bytes*/) { return false; } // never in a JSON text
  bool start_object(std::size_t /*unknown*/) { return open(json::value_t::object); }
  bool start_array(std::size_t /*unknown*/) { return open(json::value_t::array); }
  bool key(json::string_t& name);
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool parse_error(std::size_t /*at*/, const std::string& /*token*/,
                   const nlohmann::detail::exception& /*why*/) {
    return false;
  }

  // The report, once the parser read it whole (`parsed`), its last checks done and its records
  // read before its schema handed over.
  json finish(bool parsed);
  // The lone record read (read_record).
  json lone() { return std::move(tree_); }

private:
  // The top-level object of a report, open and not a record's.
  bool at_top() const { return where_ == nullptr && open_.size() == 1 && open_[0] == &tree_; }
  // A value begins: into the tree of the report (or of the lone record), of the record being
  // read, or nowhere (a record of another schema); the place it went, if a container.
  json* add(json&& value);
  bool scalar(json&& value) {
    if (skipping_ == 0) {
      (void)add(std::move(value));
    }
    return true;
  }
  bool open(json::value_t type);
  bool close();
  // One more value or key in the tree (of a report, not of a lone record).
  void keep() {
    if (where_ == nullptr && ++kept_ > max_values_) {
      throw TooManyValues(path_ + ": its text outside the records holds more than " +
                          std::to_string(max_values_) +
                          " JSON values and keys (records before its schema count too): not a "
                          "report pldamp wrote");
    }
  }
  void take(json&& record);
  std::string location() const;

  const std::string& path_;
  const RecordSink& each_;
  const std::size_t max_values_;
  const std::string* where_;
  json tree_;
  std::vector<json*> open_; // the containers open, outermost first
  json* member_ = nullptr;  // the value of the key just read
  // The record read apart from the tree (of this report's schema), whole when open_ is back to
  // record_depth_ containers.
  json record_;
  bool in_record_ = false;
  std::size_t record_depth_ = 0;
  std::size_t skipping_ = 0;    // the depth within a record of another schema
  std::string section_;         // the top-level member being read
  json* records_ = nullptr;     // the top-level records array, in the tree
  std::optional<bool> ours_;    // whether the schema is this version's (none: not yet read)
  bool claims_checked_ = false; // as soon as they are read (before the records, as pldamp writes)
  std::size_t kept_ = 0;        // the values and keys in the tree
  std::size_t taken_ = 0;       // the records handed over (or being read apart)
  std::unordered_map<std::string, std::size_t> keys_; // each record's key, and its index
};

json* Reader::add(json&& value) {
  if (!in_record_ && records_ != nullptr && !open_.empty() && open_.back() == records_ && ours_) {
    if (!*ours_) { // a record of another schema: refused at the end, never kept
      skipping_ = value.is_structured() ? 1 : 0;
      return nullptr;
    }
    record_ = std::move(value);
    if (!record_.is_structured()) {
      take(std::move(record_));
      return nullptr;
    }
    in_record_ = true;
    record_depth_ = open_.size();
    return &record_;
  }
  if (!in_record_) {
    keep();
  }
  json* at = nullptr;
  if (open_.empty()) {
    tree_ = std::move(value);
    at = &tree_;
  } else if (open_.back()->is_array()) {
    at = &open_.back()->get_ref<json::array_t&>().emplace_back(std::move(value));
  } else {
    *member_ = std::move(value);
    at = member_;
  }
  if (at_top()) {
    if (section_ == key::schema) {
      ours_ = *at == version;
    } else if (section_ == key::records && at->is_array()) {
      records_ = at;
    }
  }
  return at;
}

bool Reader::open(json::value_t type) {
  if (skipping_ > 0) {
    ++skipping_;
  } else if (json* at = add(json(type)); at != nullptr) {
    open_.push_back(at);
  }
  return true;
}

bool Reader::close() {
  if (skipping_ > 0) {
    --skipping_;
    return true;
  }
  json* closed = open_.back();
  open_.pop_back();
  if (in_record_ && open_.size() == record_depth_) {
    in_record_ = false;
    take(std::move(record_));
  } else if (at_top() && section_ == key::claims && closed->is_array() && ours_ == true) {
    check_claims(*closed, path_);
    claims_checked_ = true;
  }
  return true;
}

bool Reader::key(json::string_t& name) {
  if (skipping_ > 0) {
    return true;
  }
  if (at_top()) {
    section_ = name;
  }
  if (!in_record_) {
    keep(); // a member costs its key too: a map node (about 96 bytes)
  }
  auto [member, fresh] = open_.back()->get_ref<json::object_t&>().try_emplace(std::move(name));
  if (!fresh) {
    // Named twice, the tree would keep the last one while the records handed over (or dropped,
    // or the claims checked) were the first one's; in a record, diff would read the last one.
    throw InputError(path_ + ": " + location() + " names " + one_line(member->first, 200) +
                     " twice");
  }
  member_ = &member->second;
  return true;
}

// "records[3].rel_error", "scene.grid", "the report": where the innermost open object is (its
// first 200 characters or so: a path 10^5 levels deep is no message).
std::string Reader::location() const {
  std::size_t from = 0;
  std::string out = where_ != nullptr ? *where_ : "";
  if (in_record_) {
    from = record_depth_;
    out = std::string(key::records) + "[" + std::to_string(taken_) + "]";
  }
  for (std::size_t i = from + 1; i < open_.size(); ++i) {
    if (out.size() > 200) {
      return out + "...";
    }
    if (open_[i - 1]->is_array()) {
      const json::array_t& items = open_[i - 1]->get_ref<const json::array_t&>();
      out += "[" + std::to_string(open_[i] - items.data()) + "]";
      continue;
    }
    for (const auto& [name, value] : open_[i - 1]->get_ref<const json::object_t&>()) {
      if (&value == open_[i]) {
        out += (out.empty() ? "" : ".") + one_line(name, 200);
        break;
      }
    }
  }
  return out.empty() ? "the report" : out;
}

void Reader::take(json&& record) {
  const std::string where = std::string(key::records) + "[" + std::to_string(taken_) + "]";
  check_record(record, path_, where);
  // Two records of one key: diff would compare one of them and never see the other.
  const auto [earlier, fresh] =
      keys_.try_emplace(record.at(key::key).get_ref<const std::string&>(), taken_);
  if (!fresh) {
    throw InputError(path_ + ": " + where + " has the key of " + key::records + "[" +
                     std::to_string(earlier->second) + "] (" + one_line(earlier->first, 200) + ")");
  }
  ++taken_;
  each_(std::move(record));
}

json Reader::finish(bool parsed) {
  if (!parsed) {
    throw InputError("not a JSON report (got " + path_ + ")");
  }
  json report = std::move(tree_);
  if (!report.is_object() || !report.contains(key::schema) || !report.contains(key::records) ||
      !report.contains(key::claims)) {
    throw InputError("not a pldamp report.json (got " + path_ + ")");
  }
  if (report.at(key::schema) != version) {
    throw InputError(path_ + ": report schema " + shown(report.at(key::schema)) + " is not " +
                     std::to_string(version));
  }
  const auto is_array = [](const json& j) { return j.is_array(); };
  expect(report.at(key::claims), is_array, path_, key::claims, "an array");
  expect(report.at(key::records), is_array, path_, key::records, "an array");
  if (!claims_checked_) {
    check_claims(report.at(key::claims), path_);
  }
  for (json& record : report.at(key::records)) { // read before the schema
    take(std::move(record));
  }
  report.at(key::records) = json::array();
  return report;
}

// A stream's bytes up to its first NUL, which nlohmann's lexer takes for the end of its input
// ("{...}\0 anything" read as "{...}" while "{...} anything" was refused). A JSON text never holds
// one (a string holds no raw control character): a NUL met refuses the report.
class UpToNul : public std::streambuf {
public:
  explicit UpToNul(std::streambuf* source) : source_(source) {}
  bool met() const { return met_; }

protected:
  int_type underflow() override {
    if (met_ || source_ == nullptr) {
      return traits_type::eof();
    }
    const std::streamsize count =
        source_->sgetn(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    if (count <= 0) {
      return traits_type::eof();
    }
    char* end = buffer_.data() + count;
    if (void* nul = std::memchr(buffer_.data(), 0, static_cast<std::size_t>(count))) {
      met_ = true;
      end = static_cast<char*>(nul);
    }
    setg(buffer_.data(), buffer_.data(), end);
    return end == buffer_.data() ? traits_type::eof() : traits_type::to_int_type(buffer_[0]);
  }

private:
  std::streambuf* source_;
  std::array<char, 65536> buffer_{};
  bool met_ = false;
};

} // namespace

bool too_many_values(const std::exception& error) {
  return dynamic_cast<const TooManyValues*>(&error) != nullptr;
}

nlohmann::json read_report(std::string_view text, const std::string& path, std::size_t max_values) {
  json records = json::array();
  const RecordSink keep = [&](json&& record) { records.push_back(std::move(record)); };
  Reader reader(path, keep, max_values);
  const bool parsed = json::sax_parse(text, &reader);
  // nlohmann's lexer ends its input at a NUL as at the end: refused whatever follows it.
  json report = reader.finish(parsed && text.find('\0') == std::string_view::npos);
  report.at(key::records) = std::move(records);
  return report;
}

nlohmann::json read_report(std::istream& in, const std::string& path, const RecordSink& each,
                           std::size_t max_values) {
  UpToNul bytes(in.rdbuf());
  std::istream guarded(&bytes);
  Reader reader(path, each, max_values);
  const bool parsed = json::sax_parse(guarded, &reader);
  return reader.finish(parsed && !bytes.met());
}

nlohmann::json read_record(std::string_view text, const std::string& path,
                           const std::string& where) {
  const RecordSink none = [](json&&) {};
  Reader reader(path, none, 0, &where);
  if (!json::sax_parse(text, &reader) || text.find('\0') != std::string_view::npos) {
    throw InputError("not a JSON report (got " + path + ")");
  }
  json record = reader.lone();
  check_record(record, path, where);
  return record;
}

} // namespace pldamp::harness::schema
