// Reading a trajectory file (`pldamp check`, a scene's [[trajectory]]): the CSV format of
// docs/check.md, refused line by line with the file's name and line number.
#include "judge/trajectory.hpp"

#include "common/files.hpp"

#include "common/input.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

namespace pldamp::harness {
namespace {
// ---- Reading -----------------------------------------------------------------------------------

enum class Column { t, delta, v, force };

struct ColumnName {
  Column column;
  std::string_view name, alias;
};

constexpr std::array column_names{
    ColumnName{Column::t, "t", "time"}, ColumnName{Column::delta, "delta", "overlap"},
    ColumnName{Column::v, "v", "velocity"}, ColumnName{Column::force, "F", "force"}};

std::string_view trimmed(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (!text.empty() && blank(text.front())) {
    text.remove_prefix(1);
  }
  while (!text.empty() && blank(text.back())) {
    text.remove_suffix(1);
  }
  return text;
}

// A cell as quoted in a message: at most 60 characters.
// A cell or line in a message: one line of at most 60 bytes, a NUL or a byte that is not UTF-8
// escaped (a NUL cut the message at it, a UTF-16 file printed raw bytes).
std::string shown(std::string_view cell) {
  return one_line(cell, 60);
}

std::vector<std::string_view> cells_of(std::string_view line) {
  std::vector<std::string_view> cells;
  for (std::size_t from = 0;;) {
    const std::size_t comma = line.find(',', from);
    cells.push_back(trimmed(line.substr(from, comma - from)));
    if (comma == std::string_view::npos) {
      return cells;
    }
    from = comma + 1;
  }
}

std::optional<double> number_in(std::string_view cell) {
  if (!cell.empty() && cell.front() == '+') {
    cell.remove_prefix(1);
  }
  double value = 0;
  const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (cell.empty() || error != std::errc() || end != cell.data() + cell.size()) {
    return std::nullopt;
  }
  return value;
}

std::optional<Column> column_named(std::string_view name) {
  auto same = [&](std::string_view known) {
    return name.size() == known.size() &&
           std::equal(name.begin(), name.end(), known.begin(), [](char a, char b) {
             return std::tolower(static_cast<unsigned char>(a)) ==
                    std::tolower(static_cast<unsigned char>(b));
           });
  };
  for (const ColumnName& known : column_names) {
    if (same(known.name) || same(known.alias)) {
      return known.column;
    }
  }
  return std::nullopt;
}

int& digits_of(TrajectoryColumns& columns, Column column) {
  switch (column) {
  case Column::t:
    return columns.digits.t;
  case Column::delta:
    return columns.digits.delta;
  case Column::v:
    return columns.digits.v;
  case Column::force:
    break;
  }
  return columns.digits.force;
}

std::vector<double>& column_of(TrajectoryColumns& columns, Column column) {
  switch (column) {
  case Column::t:
    return columns.t;
  case Column::delta:
    return columns.delta;
  case Column::v:
    return *columns.v;
  case Column::force:
    break;
  }
  return *columns.force;
}
} // namespace

int significant_digits(std::string_view number) {
  int digits = 0;
  bool leading = true;
  for (const char c : number) {
    if (c == 'e' || c == 'E') {
      break;
    }
    if (c < '0' || c > '9') {
      continue; // sign, decimal point
    }
    leading = leading && c == '0';
    digits += leading ? 0 : 1;
  }
  return digits;
}

double resolution_of(int digits) {
  return std::max(0.5 * std::pow(10.0, 1 - std::max(digits, 1)),
                  std::numeric_limits<double>::epsilon());
}

std::string trajectory_column_names() {
  std::string names, aliases;
  for (const ColumnName& known : column_names) {
    if (!names.empty()) {
      names += '|';
      aliases += ", ";
    }
    names += known.name;
    aliases += known.alias;
  }
  return names + " (or " + aliases + ")";
}

TrajectoryColumns parse_trajectory_csv(std::string_view text, const std::string& name) {
  TrajectoryColumns columns;
  columns.digits = {.t = 0, .delta = 0, .v = 0, .force = 0}; // the largest seen, below
  std::vector<Column> order;
  std::size_t line_number = 0;
  std::size_t header_line = 0;
  double last_t = 0;
  auto fail = [&](const std::string& what) {
    throw InputError(name + ":" + std::to_string(line_number) + ": " + what);
  };
  for (std::size_t from = 0; from < text.size();) {
    const std::size_t newline = text.find('\n', from);
    std::string_view line = text.substr(from, newline - from);
    from = newline == std::string_view::npos ? text.size() : newline + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') {
      line.remove_suffix(1);
    }
    if (trimmed(line).empty() || trimmed(line).front() == '#') {
      continue;
    }
    const std::vector<std::string_view> cells = cells_of(line);
    if (order.empty()) { // the header
      header_line = line_number;
      if (number_in(cells.front())) {
        fail("the first line must name the columns, e.g. t,delta,v (got " + shown(line) + ")");
      }
      for (const std::string_view cell : cells) {
        const std::optional<Column> column = column_named(cell);
        if (!column) {
          fail("unknown column, expected " + trajectory_column_names() + " (got " + shown(cell) +
               ")");
        }
        if (std::find(order.begin(), order.end(), *column) != order.end()) {
          fail("a column is named twice (got " + shown(cell) + ")");
        }
        order.push_back(*column);
      }
      for (const Column required : {Column::t, Column::delta}) {
        if (std::find(order.begin(), order.end(), required) == order.end()) {
          fail(std::string("the header names no ") + (required == Column::t ? "t" : "delta") +
               " column (got " + shown(line) + ")");
        }
      }
      if (std::find(order.begin(), order.end(), Column::v) != order.end()) {
        columns.v.emplace();
      }
      if (std::find(order.begin(), order.end(), Column::force) != order.end()) {
        columns.force.emplace();
      }
      continue;
    }
    if (cells.size() != order.size()) {
      fail("a row has " + std::to_string(cells.size()) + " cells, the header names " +
           std::to_string(order.size()) + " (got " + shown(line) + ")");
    }
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string column(column_names[static_cast<std::size_t>(order[i])].name);
      const std::optional<double> value = number_in(cells[i]);
      if (!value) {
        fail(column + " is not a number (got " + shown(cells[i]) + ")");
      }
      if (!std::isfinite(*value)) {
        fail(column + " must be finite (got " + shown(cells[i]) + ")");
      }
      column_of(columns, order[i]).push_back(*value);
      int& digits = digits_of(columns, order[i]);
      digits = std::max(digits, significant_digits(cells[i]));
    }
    if (columns.t.size() > 1 && !(columns.t.back() > last_t)) {
      fail("t must increase from row to row (got " +
           shown(cells[static_cast<std::size_t>(std::find(order.begin(), order.end(), Column::t) -
                                                order.begin())]) +
           " after " + to_string_full(last_t) + ")");
    }
    last_t = columns.t.back();
  }
  if (order.empty()) {
    throw InputError(name + ": no header line naming the columns, e.g. t,delta,v (got " +
                     (text.empty() ? "an empty file" : "no line but comments") + ")");
  }
  if (columns.t.size() < 3) {
    throw InputError(name + ":" + std::to_string(header_line) +
                     ": at least 3 rows of numbers are needed after the header (got " +
                     std::to_string(columns.t.size()) + ")");
  }
  return columns;
}

TrajectoryColumns load_trajectory(const std::string& path) {
  if (const std::optional<std::string> why = unreadable_file(path)) {
    throw InputError("cannot read the trajectory: " + *why + " (got " + one_line(path) + ")");
  }
  std::error_code error;
  const auto too_large = [&] {
    return InputError("a trajectory file is at most " + std::to_string(max_trajectory_bytes) +
                      " bytes; this one is larger (got " + one_line(path) + ")");
  };
  if (const auto size = std::filesystem::file_size(path, error);
      !error && size > max_trajectory_bytes) {
    throw too_large();
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError("cannot read the trajectory: " + std::string(std::strerror(errno)) + " (got " +
                     one_line(path) + ")");
  }
  std::string text;
  std::array<char, 65536> buffer{};
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_trajectory_bytes) { // a pipe or a device: no size known beforehand
      throw too_large();
    }
  }
  return parse_trajectory_csv(text, path);
}

} // namespace pldamp::harness
