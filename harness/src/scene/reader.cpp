#include "scene/reader.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace pldamp::harness::scene_reading {
namespace {

std::string type_of(const toml::node& node) {
  std::ostringstream out;
  out << node.type();
  return out.str();
}

// A range's end as a scene writes it: 1000, 1e9, 0.5.
std::string end_text(double x) {
  std::string text = fmt::format("{:g}", x);
  const std::size_t e = text.find('e');
  if (e == std::string::npos) {
    return text;
  }
  const bool negative = text[e + 1] == '-';
  std::string exponent = text.substr(e + 2);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

} // namespace

bool Range::contains(double x) const {
  return (low_open ? x > low : x >= low) && (high_open ? x < high : x <= high);
}

std::string Range::text() const {
  if (std::isinf(high)) {
    return (low_open ? "> " : ">= ") + end_text(low) + std::string(unit);
  }
  return fmt::format("in {}{}, {}{}{}", low_open ? '(' : '[', end_text(low), end_text(high),
                     high_open ? ')' : ']', unit);
}

void Reader::fail(const toml::node& at, const std::string& what) const {
  fail_at(at.source().begin.line, what);
}

void Reader::fail_at(std::size_t line, const std::string& what) const {
  throw SceneError(path_ + ":" + std::to_string(line) + ": " + what);
}

void Reader::unknown(const toml::node& at, const std::string& what, const std::string& expected,
                     const std::string& got) const {
  fail(at, "unknown " + what + ", expected " + expected + " (got " + got + ")");
}

void Reader::only(const toml::table& table, std::initializer_list<scene_keys::Keys> allowed,
                  const std::string& where) const {
  const auto known = [&](std::string_view key) {
    return std::any_of(allowed.begin(), allowed.end(), [&](scene_keys::Keys keys) {
      return std::find(keys.begin(), keys.end(), key) != keys.end();
    });
  };
  for (const auto& [key, node] : table) {
    if (!known(key.str())) {
      std::string names;
      for (const scene_keys::Keys keys : allowed) {
        for (const std::string_view name : keys) {
          names += names.empty() ? "" : "|";
          names += name;
        }
      }
      unknown(node, "key in " + where, names, std::string(key.str()));
    }
  }
}

double Reader::number(const toml::node& node, const std::string& what) const {
  // Numbers are decimal, as on the command line: TOML's 0x10, 0o20 and 0b10000 read as 16 (a v0
  // of 0x10 was a run at 16 m/s).
  if (const toml::value<std::int64_t>* integer = node.as_integer();
      integer != nullptr && integer->flags() != toml::value_flags::none) {
    const std::int64_t v = integer->get(); // TOML's are non-negative
    const std::string typed =
        integer->flags() == toml::value_flags::format_as_hexadecimal ? fmt::format("0x{:x}", v)
        : integer->flags() == toml::value_flags::format_as_octal     ? fmt::format("0o{:o}", v)
                                                                     : fmt::format("0b{:b}", v);
    fail(node, what + " must be written in decimal (got " + typed + ")");
  }
  if (const auto value = node.value<double>();
      value && (node.is_floating_point() || node.is_integer())) {
    if (!std::isfinite(*value)) {
      fail(node, what + " must be finite (got " + to_string_full(*value) + ")");
    }
    return *value;
  }
  if (const toml::value<std::int64_t>* integer = node.as_integer()) {
    // An integer beyond 2^53 has no double equal to it, so toml++ gives no value<double> (2^63 − 1
    // said "must be a number (got integer)"). Refused as what it is, with the digits typed.
    fail(node, what +
                   " is an integer beyond 2^53, which no double holds exactly: write it as a "
                   "float (got " +
                   std::to_string(integer->get()) + ")");
  }
  fail(node, what + " must be a number (got " + type_of(node) + ")");
}

std::vector<double> Reader::numbers(const toml::node& node, const std::string& what) const {
  std::vector<double> out;
  if (const toml::array* list = node.as_array()) {
    for (const toml::node& item : *list) {
      out.push_back(number(item, what));
    }
    if (out.empty()) {
      fail(node, what + " is an empty list");
    }
    return out;
  }
  return {number(node, what)};
}

double Reader::number_in(const toml::node& node, const std::string& what,
                         const Range& range) const {
  const double value = number(node, what);
  check_in(node, what, value, range);
  return value;
}

long Reader::integer_in(const toml::node& node, const std::string& what, long low,
                        long high) const {
  return check_integer(node, what, number(node, what), low, high);
}

void Reader::check_in(const toml::node& node, const std::string& what, double value,
                      const Range& range) const {
  require(range.contains(value), node, what + " must be " + range.text(), value);
}

long Reader::check_integer(const toml::node& node, const std::string& what, double value, long low,
                           long high) const {
  require(value >= double(low) && value <= double(high) && value == std::floor(value), node,
          what + " must be an integer " + Range::closed(double(low), double(high)).text(), value);
  return static_cast<long>(value);
}

bool Reader::boolean(const toml::node& node, const std::string& what) const {
  if (!node.is_boolean()) {
    fail(node, what + " must be true or false");
  }
  return *node.value<bool>();
}

std::string Reader::string(const toml::node& node, const std::string& what) const {
  if (const auto value = node.value<std::string>(); value && node.is_string()) {
    return *value;
  }
  fail(node, what + " must be a string (got " + type_of(node) + ")");
}

std::vector<std::string> Reader::strings(const toml::node& node, const std::string& what) const {
  std::vector<std::string> out;
  if (const toml::array* list = node.as_array()) {
    for (const toml::node& item : *list) {
      out.push_back(string(item, what));
    }
    return out;
  }
  return {string(node, what)};
}

const toml::array& Reader::entries(const toml::node& node, const std::string& key) const {
  if (const toml::array* list = node.as_array()) {
    return *list;
  }
  fail(node, key + " must be an array of tables ([[" + key + "]])");
}

const toml::table& Reader::table(const toml::node& node, const std::string& what) const {
  if (const toml::table* t = node.as_table()) {
    return *t;
  }
  fail(node, what + " must be a table (got " + type_of(node) + ")");
}

void Reader::require(bool ok, const toml::node& node, const std::string& what, double value) const {
  if (!ok) {
    fail(node, what + " (got " + to_string_full(value) + ")");
  }
}

// Refuses, before toml++ sees the text, what it handles badly (max_scene_nesting):
// - nesting it would recurse into without bound: arrays and inline tables inside each other,
//   table headers and dotted keys with many parts (counted together: a dotted key inside nested
//   arrays is as deep as both);
// - a byte beyond ASCII outside comments: toml++ 3.3.0 reaches __builtin_unreachable on such
//   bytes in keys, after a string's backslash and in its error paths (marzer/tomlplusplus#295,
//   #190), found by tests/fuzz; in a string, \uXXXX says the same.
// A lexical pass that skips strings and comments; a dot between two digits is a number's.
void check_text(const Reader& reader, std::string_view text) {
  // The file's limit holds for a text from elsewhere too (a shard's header carries its scene).
  if (text.size() > max_scene_bytes) {
    reader.fail_at(0, "a scene is at most " + std::to_string(max_scene_bytes) +
                          " bytes; this one is larger");
  }
  int depth = 0, dots = 0;
  std::size_t line = 1;
  auto deeper_than_allowed = [&](int levels) {
    if (levels > max_scene_nesting) {
      reader.fail_at(line, "nested deeper than " + std::to_string(max_scene_nesting) +
                               " levels (arrays, inline tables or dotted keys)");
    }
  };
  auto non_ascii = [](char c) { return static_cast<unsigned char>(c) >= 0x80; };
  const std::string beyond_ascii =
      "a character beyond ASCII outside a comment (in a string, write it as \\uXXXX)";
  auto digit = [&](std::size_t i) { return i < text.size() && text[i] >= '0' && text[i] <= '9'; };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      dots = 0;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') {
        ++i;
      }
    } else if (c == '"' || c == '\'') {
      const bool multiline = text.substr(i, 3) == std::string(3, c);
      const std::string_view close = multiline ? text.substr(i, 3) : text.substr(i, 1);
      i += close.size();
      while (i < text.size() && text.substr(i, close.size()) != close) {
        if (text[i] == '\n') {
          if (!multiline) {
            break; // an unterminated string: toml++ says so
          }
          ++line;
        } else if (non_ascii(text[i])) {
          reader.fail_at(line, beyond_ascii);
        } else if (c == '"' && text[i] == '\\') {
          ++i; // an escaped character
        }
        ++i;
      }
      i += close.size() - 1;
    } else if (non_ascii(c)) {
      reader.fail_at(line, beyond_ascii);
    } else if (c == '[' || c == '{') {
      deeper_than_allowed(++depth + dots);
    } else if (c == ']' || c == '}') {
      depth = std::max(depth - 1, 0);
    } else if (c == '.' && !(i > 0 && digit(i - 1) && digit(i + 1))) {
      deeper_than_allowed(depth + ++dots + 1);
    }
  }
}

} // namespace pldamp::harness::scene_reading
