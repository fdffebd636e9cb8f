// A scene's contacts from materials ([[contact]], MATH.md §13) in report.md and report.html: what
// each contact is, and at each of its cells the closed forms in SI units beside every
// configuration's error there (the Chung–Ooi tables: what a DEM code gives for each benchmark).
#include "report/sections.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <sstream>

namespace pldamp::harness {
namespace {

// The observables the truth table shows, in its order, with their units.
constexpr std::array<std::pair<std::string_view, std::string_view>, 4> shown_observables{
    {{"delta_max", "δ_max [m]"}, {"normal_force_max", "F_max [N]"}, {"tau", "τ [s]"}, {"e", "e"}}};

// What a configuration's label adds to its line: "n=50", "rtol=1e-08" (empty: a lone one).
std::string sweep_value(const SolverConfig& config) {
  const std::string line = config.line();
  std::string added;
  std::istringstream words(config.label());
  for (std::string word; words >> word;) {
    if (line.find(word) == std::string::npos) {
      added += (added.empty() ? "" : " ") + word;
    }
  }
  return added;
}

} // namespace

MapTable contacts_table(const RunReport& report) {
  MapTable table;
  table.header = {"contact", "geometry",    "R* [m]",   "E* [Pa]",
                  "m* [kg]", "k [N/m^1.5]", "v0 [m/s]", "Rayleigh time [s]"};
  for (const MaterialContact& contact : report.plan.scene.contacts) {
    std::string speeds;
    for (const double v0 : contact.v0) {
      speeds += (speeds.empty() ? "" : ", ") + short_number(v0, 4);
    }
    table.rows.push_back({contact.name, contact.geometry, short_number(contact.radius_eff, 4),
                          short_number(contact.modulus_eff, 4), short_number(contact.m, 4),
                          short_number(contact.k, 4), speeds,
                          short_number(contact.rayleigh_time, 4)});
  }
  return table;
}

MapTable contact_truth_table(const RunReport& report) {
  const Plan& plan = report.plan;
  MapTable table;
  if (plan.scene.contacts.empty()) {
    return table;
  }
  table.header = {"contact", "v0 [m/s]", "damping"};
  std::vector<std::size_t> columns;             // indices into plan.observables
  for (const auto& shown : shown_observables) { // (no structured binding: Clang 14 would not
                                                // let the lambda capture it)
    const auto found = std::find_if(plan.observables.begin(), plan.observables.end(),
                                    [&](const Observable* o) { return o->key == shown.first; });
    if (found != plan.observables.end()) {
      columns.push_back(static_cast<std::size_t>(found - plan.observables.begin()));
      table.header.emplace_back(shown.second);
    }
  }
  // One column per solver line (a configuration without its sweep value), its configurations'
  // errors "/"-separated in sweep order: the table stays as wide as the solvers, not their sweeps.
  std::vector<std::string> lines;
  std::vector<std::vector<std::size_t>> configs_of_line;
  for (std::size_t k = 0; k < plan.configs.size(); ++k) {
    const std::string line = plan.configs[k].line();
    const auto at = std::find(lines.begin(), lines.end(), line);
    if (at == lines.end()) {
      lines.push_back(line);
      configs_of_line.push_back({k});
    } else {
      configs_of_line[static_cast<std::size_t>(at - lines.begin())].push_back(k);
    }
  }
  for (std::size_t l = 0; l < lines.size(); ++l) {
    std::string sweep;
    for (const std::size_t k : configs_of_line[l]) {
      sweep += (sweep.empty() ? "" : " / ") + sweep_value(plan.configs[k]);
    }
    table.header.push_back(lines[l] + (sweep.empty() ? "" : " (" + sweep + ")"));
  }
  // Each contact cell's record as its table shows it, by (cell, configuration): records are read
  // one at a time (a merge's are decoded as they are read, run/record_store.hpp).
  std::map<std::pair<std::size_t, std::size_t>, std::string> by_cell;
  for (const Record& record : report.records) {
    const Cell& cell = plan.cells[record.cell];
    if (contact_of(plan.scene, cell.m, cell.k) == nullptr) {
      continue;
    }
    std::string& text = by_cell[{record.cell, record.config}];
    if (record.skipped()) {
      text = "skipped";
    } else if (record.failed()) {
      text = record.outcome_name();
    } else {
      std::optional<double> worst;
      for (const std::size_t o : columns) {
        if (record.rel_error[o] && (!worst || *record.rel_error[o] > *worst)) {
          worst = record.rel_error[o];
        }
      }
      text = short_number(worst);
    }
  }
  const SolverConfig scene_end{}; // the truth under the scene's end
  for (std::size_t c = 0; c < plan.cells.size(); ++c) {
    const Cell& cell = plan.cells[c];
    const MaterialContact* contact = contact_of(plan.scene, cell.m, cell.k);
    if (contact == nullptr) {
      continue;
    }
    std::vector<std::string> row{contact->name, short_number(cell.v0, 4),
                                 plan.points[cell.point].damping.label()};
    for (const std::size_t o : columns) {
      const std::optional<Exact> truth = reference_at(plan, cell, o, scene_end);
      row.push_back(truth ? short_number(static_cast<double>(*truth), 4) : "–");
    }
    for (const std::vector<std::size_t>& configs : configs_of_line) {
      std::string text;
      for (const std::size_t k : configs) {
        text += text.empty() ? "" : " / ";
        const auto found = by_cell.find({c, k});
        text += found == by_cell.end() ? "–" : found->second;
      }
      row.push_back(text);
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

std::string contacts_note(const RunReport& report) {
  return fmt::format(
      "Each contact is two bodies from materials (docs/MATH.md §13): m* = m1 m2/(m1 + m2), 1/R* = "
      "1/R1 + 1/R2, 1/E* = Σ (1 − ν²)/E and k = 4/3 E* √R* (p = 3/2), derived in {} and rounded "
      "to double once; a wall's mass and radius are infinite, a wall without a modulus rigid. "
      "The Rayleigh time is π R √(ρ/G)/(0.1631 ν + 0.8766), the smaller sphere's. The second table "
      "gives, at each contact, speed and damping, the closed forms under the scene's end ({}) in "
      "SI units, then per solver its configurations' largest relative error over those "
      "observables there, in the order its header lists them (each under its own end: one with "
      "end=force is compared with the force-end truth).",
      precision_name<Exact>(), name_of(contact_ends, report.plan.scene.end));
}

} // namespace pldamp::harness
