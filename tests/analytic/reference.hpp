// Reads data/reference/analytic.csv (written by data/generate_reference.cpp) and rebuilds each
// row's contact in any precision from its exactly-representable double inputs. Cells are looked
// up by their column's header name: a column added or moved by the generator cannot be read as
// another.
#pragma once

#include "pldamp/analytic.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::testing {

// A CSV file of data/: blank lines and lines starting with '#' skipped, the first other line the
// header naming the columns, then rows with one cell per column.
class CsvTable {
public:
  struct Row {
    std::size_t line; // in the file, from 1
    std::vector<std::string> cells;
  };

  explicit CsvTable(const std::string& path) : path_(path) {
    std::ifstream in(path);
    if (!in) {
      throw std::runtime_error("cannot open " + path);
    }
    std::size_t line_number = 0;
    for (std::string line; std::getline(in, line);) {
      ++line_number;
      if (line.empty() || line[0] == '#') {
        continue;
      }
      std::vector<std::string> cells;
      std::stringstream split(line);
      for (std::string cell; std::getline(split, cell, ',');) {
        cells.push_back(cell);
      }
      if (header_.empty()) {
        header_ = std::move(cells);
      } else if (cells.size() != header_.size()) {
        throw std::runtime_error(path + ":" + std::to_string(line_number) + ": " +
                                 std::to_string(cells.size()) + " cells under " +
                                 std::to_string(header_.size()) + " columns");
      } else {
        rows_.push_back({line_number, std::move(cells)});
      }
    }
  }

  const std::vector<std::string>& header() const { return header_; }
  const std::vector<Row>& rows() const { return rows_; }

  // The index of the column named `name`; throws when the header has none.
  std::size_t column(std::string_view name) const {
    const auto found = std::find(header_.begin(), header_.end(), name);
    if (found == header_.end()) {
      throw std::runtime_error(path_ + " has no column " + std::string(name));
    }
    return static_cast<std::size_t>(found - header_.begin());
  }
  const std::string& cell(const Row& row, std::string_view name) const {
    return row.cells[column(name)];
  }

private:
  std::string path_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
};

inline constexpr std::array<const char*, 16> observable_names{"e",
                                                              "log_e",
                                                              "delta_max",
                                                              "spring_force_max",
                                                              "normal_force_max",
                                                              "t_normal_force_max",
                                                              "t_peak",
                                                              "tau",
                                                              "tau0",
                                                              "tau_ratio",
                                                              "energy_load",
                                                              "energy_unload",
                                                              "dt_crit",
                                                              "dt_tangent",
                                                              "e_cap",
                                                              "t_cut"};

// The columns of a row's contact; every other column is an observable of observable_names.
inline constexpr std::array<const char*, 6> input_names{"p", "input", "value", "v0", "m", "k"};

struct ReferenceRow {
  std::size_t line; // in analytic.csv
  double p, value, v0, m, k;
  std::string input; // "alpha_eff" or "e"
  std::map<std::string, bin50> expected;

  template <SupportedReal Real>
  analytic::Contact<Real> contact() const {
    return input == "e"
               ? analytic::Contact<Real>::from_e(Real(p), Real(value), Real(v0), Real(m), Real(k))
               : analytic::Contact<Real>::from_alpha_eff(Real(p), Real(value), Real(v0), Real(m),
                                                         Real(k));
  }
  double z() const {
    return input == "e" ? static_cast<double>(analytic::damping_from_e(bin50(value)).z) : value;
  }
  bool unit_scales() const { return v0 == 1 && m == 1 && k == 1; }
  // "line 57: p=1.5 alpha_eff=0.2 v0=1 m=1 k=1", for reports.
  std::string label() const {
    return "line " + std::to_string(line) + ": p=" + to_string_full(p) + " " + input + "=" +
           to_string_full(value) + " v0=" + to_string_full(v0) + " m=" + to_string_full(m) +
           " k=" + to_string_full(k);
  }
};

// Throws when a column of observable_names or input_names is missing, or the header names one
// that is neither.
inline std::vector<ReferenceRow> read_reference(const std::string& path = PLDAMP_DATA_DIR
                                                "/reference/analytic.csv") {
  const CsvTable table(path);
  const auto known = [](const std::string& name) {
    const auto is = [&](const char* other) { return name == other; };
    return std::any_of(observable_names.begin(), observable_names.end(), is) ||
           std::any_of(input_names.begin(), input_names.end(), is);
  };
  for (const std::string& name : table.header()) {
    if (!known(name)) {
      throw std::runtime_error(path + ": unknown column " + name);
    }
  }
  std::vector<ReferenceRow> rows;
  for (const CsvTable::Row& cells : table.rows()) {
    const auto number = [&](const char* name) { return std::stod(table.cell(cells, name)); };
    ReferenceRow row{.line = cells.line,
                     .p = number("p"),
                     .value = number("value"),
                     .v0 = number("v0"),
                     .m = number("m"),
                     .k = number("k"),
                     .input = table.cell(cells, "input"),
                     .expected = {}};
    for (const char* name : observable_names) {
      row.expected[name] = bin50(table.cell(cells, name));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

// The regions of the reference grids (data/generate_reference.cpp, MATH.md §8), each with its own
// hazard: damping below 0.99; approaching critical, where e and τ are exponentials of arguments
// up to ~π/√(1 − z²) (ln e = −2221 at z = 1 − 1e−6) and so amplify the rounding of μ = 1 − z²;
// critical and just above; overdamped; e given instead of z; and v0, m, k far from 1.
inline std::string_view damping_region(double z) {
  if (z < 0.99) {
    return "z<0.99";
  }
  if (z <= 0.999) {
    return "0.99<=z<=0.999";
  }
  if (z < 1) {
    return "0.999<z<1";
  }
  return z <= 1.001 ? "1<=z<=1.001" : "z>1.001";
}

inline std::string_view region_of(const ReferenceRow& row) {
  if (!row.unit_scales()) {
    return "extreme_v0_m_k";
  }
  return row.input == "e" ? "from_e" : damping_region(row.value);
}

template <SupportedReal Real>
std::map<std::string, std::optional<Real>> as_map(const analytic::Observables<Real>& x) {
  return {{"e", x.e},
          {"log_e", x.log_e},
          {"delta_max", x.delta_max},
          {"spring_force_max", x.spring_force_max},
          {"normal_force_max", x.normal_force_max},
          {"t_normal_force_max", x.t_normal_force_max},
          {"t_peak", x.t_peak},
          {"tau", x.tau},
          {"tau0", x.tau0},
          {"tau_ratio", x.tau_ratio},
          {"energy_load", x.energy_load},
          {"energy_unload", x.energy_unload},
          {"dt_crit", x.dt_crit},
          {"dt_tangent", x.dt_tangent},
          {"e_cap", x.e_cap},
          {"t_cut", x.t_cut}};
}

} // namespace pldamp::testing
