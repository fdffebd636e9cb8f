// Reads data/reference/analytic.csv (written by data/generate_reference.cpp) and rebuilds each
// row's contact in any precision from its exactly-representable double inputs.
#pragma once

#include "pldamp/analytic.hpp"

#include <array>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pldamp::testing {

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

struct ReferenceRow {
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
};

inline std::vector<ReferenceRow> read_reference() {
  std::ifstream in(PLDAMP_DATA_DIR "/reference/analytic.csv");
  if (!in) {
    throw std::runtime_error("cannot open " PLDAMP_DATA_DIR "/reference/analytic.csv");
  }
  std::vector<ReferenceRow> rows;
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, ',');) {
      cells.push_back(cell);
    }
    if (header.empty()) {
      header = cells;
      continue;
    }
    ReferenceRow row{std::stod(cells[0]),
                     std::stod(cells[2]),
                     std::stod(cells[3]),
                     std::stod(cells[4]),
                     std::stod(cells[5]),
                     cells[1],
                     {}};
    for (std::size_t i = 6; i < cells.size(); ++i) {
      row.expected[header[i]] = bin50(cells[i]);
    }
    rows.push_back(row);
  }
  return rows;
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
