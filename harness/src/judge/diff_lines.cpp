// diff's reading of a report.json in pldamp's layout, a line at a time (judge/diff_parts.hpp,
// read_report_lines): the text outside the records kept and checked by the general reader
// (schema::read_report), each record line handed on as it comes, and nothing held that grows with
// the records but 8 bytes a record. What the lines are parsed into is diff_read.cpp's (the facts
// of the gate) or diff_exact.cpp's (whole records).
#include "judge/diff_parts.hpp"

#include "common/files.hpp"
#include "common/input.hpp"

#include <fmt/format.h>
#include <simdjson.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace pldamp::harness::diff {

namespace {

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
        where = Where::inside;
        if (at_records) {
          // Everything before the records, checked as the whole will be: what a reader of the
          // records needs first (the scene, its thresholds). Read only for such a reader.
          std::optional<json> head = checked(rest + "]}");
          if (!head) {
            return std::nullopt;
          }
          for (const auto& [name, value] : head->items()) {
            head_sections.push_back(name);
          }
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
    if (at_records && name != key::figures &&
        std::find(head_sections.begin(), head_sections.end(), name) == head_sections.end()) {
      return std::nullopt; // a section the head's reader did not get
    }
  }
  return whole;
}

std::ifstream open_report(const std::string& path) {
  if (const std::optional<std::string> why = unreadable_file(path)) {
    throw InputError("cannot read report: " + *why + " (got " + one_line(path) + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError("cannot read report (got " + one_line(path) + ")");
  }
  return in;
}

void read_again(std::istream& in, std::istream::pos_type start, const std::string& path) {
  in.clear();
  if (!in.seekg(start)) {
    throw InputError("cannot read " + path + " again");
  }
}

} // namespace pldamp::harness::diff
