#include "judge/claim_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace pldamp::harness {

std::string verdict_number(double x) {
  return fmt::format("{:.6g}", x);
}

std::vector<ClaimCell> cells_of(const ClaimGrid& grid) {
  std::vector<ClaimCell> cells;
  const std::vector<CellScale> scales = grid_scales(grid);
  for (const double p : grid.p) {
    for (const Damping& damping : grid.damping) {
      for (const auto& [v0, m, k] : scales) {
        cells.push_back({p, damping, v0, m, k});
      }
    }
  }
  return cells;
}

std::string cell_text(const ClaimGrid& grid, const ClaimCell& cell) {
  std::string out = "p = " + verdict_number(cell.p) + ", " + damping_text(cell.damping);
  const std::pair<const std::vector<double>*, const char*> scales[] = {
      {&grid.v0, "v0"}, {&grid.m, "m"}, {&grid.k, "k"}};
  const double values[] = {cell.v0, cell.m, cell.k};
  for (std::size_t i = 0; i < 3; ++i) {
    if (scales[i].first->size() > 1) {
      out += fmt::format(", {} = {}", scales[i].second, verdict_number(values[i]));
    }
  }
  return out;
}

std::string list_text(const std::vector<double>& values) {
  if (values.size() <= 6) {
    std::vector<std::string> parts;
    for (const double x : values) {
      parts.push_back(verdict_number(x));
    }
    return fmt::format("{{{}}}", fmt::join(parts, ", "));
  }
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return fmt::format("[{}, {}] ({} values)", verdict_number(*lo), verdict_number(*hi),
                     values.size());
}

namespace {

// A list refined by `between` points between each pair of neighbours.
std::vector<double> refined(const std::vector<double>& values, int between) {
  if (values.size() < 2) {
    return values;
  }
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  const bool logarithmic = *lo > 0 && *hi > 10 * *lo;
  std::vector<double> out;
  for (std::size_t i = 0; i + 1 < values.size(); ++i) {
    for (int j = 0; j <= between; ++j) {
      const double t = double(j) / (between + 1);
      const double a = values[i], b = values[i + 1];
      out.push_back(logarithmic ? a * std::pow(b / a, t) : a + (b - a) * t);
    }
  }
  out.push_back(values.back());
  return out;
}

// A grid's dampings by kind (targets e, α, α_eff), each list in the grid's order.
std::map<Damping::Kind, std::vector<double>> dampings_by_kind(const ClaimGrid& grid) {
  std::map<Damping::Kind, std::vector<double>> out;
  for (const Damping& d : grid.damping) {
    out[d.kind].push_back(d.value);
  }
  return out;
}
} // namespace

std::string grid_text(const ClaimGrid& grid) {
  std::string out = "p in " + list_text(grid.p);
  bool first = true;
  for (const auto& [kind, values] : dampings_by_kind(grid)) {
    out += (first ? " x " : " and ") + std::string(Damping{kind, 0}.key()) + " in " +
           list_text(values);
    first = false;
  }
  if (!grid.scales.empty()) {
    out += fmt::format(" x the contacts' {} (v0, m, k)", grid.scales.size());
  } else {
    const std::pair<const std::vector<double>*, const char*> scales[] = {
        {&grid.v0, "v0"}, {&grid.m, "m"}, {&grid.k, "k"}};
    for (const auto& [values, name] : scales) {
      if (values->size() > 1) {
        out += fmt::format(" x {} in {}", name, list_text(*values));
      }
    }
  }
  const std::size_t cells = grid.p.size() * grid.damping.size() * grid_scales(grid).size();
  return out + fmt::format(": {} cells", cells);
}

ClaimGrid denser_grid(const ClaimGrid& grid) {
  const std::map<Damping::Kind, std::vector<double>> dampings = dampings_by_kind(grid);
  // A scene's contacts stay as they are: only p and the damping are refined.
  const bool contacts = !grid.scales.empty();
  std::vector<const std::vector<double>*> lists{&grid.p};
  if (!contacts) {
    lists.insert(lists.end(), {&grid.v0, &grid.m, &grid.k});
  }
  for (const auto& [kind, values] : dampings) {
    lists.push_back(&values);
  }
  const auto varied = std::count_if(lists.begin(), lists.end(),
                                    [](const std::vector<double>* l) { return l->size() > 1; });
  // Each interval of each varied list cut into (between + 1): (between + 1)^varied ≥ 10 cells
  // per square of the grid.
  const int between =
      varied == 0 ? 0 : static_cast<int>(std::ceil(std::pow(10.0, 1.0 / double(varied)))) - 1;
  ClaimGrid out{refined(grid.p, between),
                contacts ? grid.v0 : refined(grid.v0, between),
                contacts ? grid.m : refined(grid.m, between),
                contacts ? grid.k : refined(grid.k, between),
                {},
                grid.scales};
  for (const auto& [kind, values] : dampings) {
    for (const double value : refined(values, between)) {
      out.damping.push_back({kind, value});
    }
  }
  return out;
}

std::string damping_text(const Damping& d) {
  return std::string(d.key()) + " = " + verdict_number(d.value);
}

} // namespace pldamp::harness
