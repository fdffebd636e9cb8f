// [[search]]: the loosest value of a configuration's sweep parameter that keeps an error bound.
#include "scene/reader.hpp"

#include "pldamp/solvers/registry.hpp"

#include <algorithm>
#include <cmath>

namespace pldamp::harness::scene_reading {

void read_searches(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "search")) {
    const toml::table& entry = reader.table(item, "[[search]]");
    reader.only(entry, {scene_keys::search}, "[[search]]");
    Search search;
    for (const char* key : {"name", "parameter", "range", "observable"}) {
      if (entry.get(key) == nullptr) {
        reader.fail(item, std::string("[[search]] needs ") + key);
      }
    }
    search.name = reader.string(*entry.get("name"), "search name");
    if (std::any_of(scene.searches.begin(), scene.searches.end(),
                    [&](const Search& earlier) { return earlier.name == search.name; })) {
      reader.fail(*entry.get("name"), "[[search]] " + search.name + " is named twice");
    }
    for (const char* key : {"where", "quote"}) {
      if (const toml::node* text = entry.get(key)) {
        (key[0] == 'w' ? search.where : search.quote) = reader.string(*text, key);
      }
    }
    search.config = base_config(reader, entry, "solver", "[[search]]", item);
    if (entry.get("onset_phases") != nullptr) { // read (and checked) by base_config
      search.onset_phases = search.config.onset_phases;
    }
    search.config.end = read_end(reader, entry, "a search's");
    const solvers::SolverInfo& info = solvers::solver_named(search.config.name);
    search.parameter = reader.choice(*entry.get("parameter"), search_parameters, "parameter");
    const bool fixed = search.parameter != SearchParameter::rtol;
    if (fixed != info.fixed_step) {
      reader.fail(*entry.get("parameter"),
                  search.config.name +
                      (info.fixed_step ? " takes a fixed step: search steps_per_contact or dt"
                                       : " controls its error: search rtol") +
                      " (got " + std::string(name_of(search_parameters, search.parameter)) + ")");
    }
    for (const char* key : {"rtol", "steps_per_contact"}) {
      if (entry.get(key) != nullptr) {
        reader.fail(*entry.get(key), std::string("[[search]] sets ") + key +
                                         " per trial: give its range, not a value");
      }
    }
    const toml::node& range = *entry.get("range");
    const std::vector<double> ends = reader.numbers(range, "range");
    // Each parameter's range, as its refusal words it.
    const bool steps = search.parameter == SearchParameter::steps_per_contact;
    const Range allowed = search.parameter == SearchParameter::rtol ? rtol_range
                          : steps                                   ? Range::closed(1, 1e9)
                                                                    : Range::open(0, 1e300);
    const auto valid = [&](double x) {
      return allowed.contains(x) && (!steps || x == std::floor(x));
    };
    if (ends.size() != 2 || !valid(ends[0]) || !valid(ends[1]) || ends[0] == ends[1]) {
      reader.fail(range, "range must be [from, to], two different values of " +
                             std::string(name_of(search_parameters, search.parameter)) +
                             (steps ? ", integers " : " ") + allowed.text());
    }
    // The scan steps by powers of their ratio (judge/search.cpp, search_scan).
    const double spread = std::max(ends[0], ends[1]) / std::min(ends[0], ends[1]);
    reader.require(spread <= 1e300, range,
                   "range must have its ends within a factor 1e300 of each other", spread);
    // Tightest first: the smaller rtol or Δt, the more steps per contact.
    const double tight = steps ? std::max(ends[0], ends[1]) : std::min(ends[0], ends[1]);
    search.range = {tight, ends[0] == tight ? ends[1] : ends[0]};
    search.observable = reader.string(*entry.get("observable"), "observable");
    require_wanted(reader, *entry.get("observable"), search.observable, scene.want, "search");
    const ErrorBound error = read_error_bound(reader, entry, item, "[[search]]");
    search.bound = error.bound;
    search.relative = error.relative;
    search.quantile = error.quantile;
    if (const toml::node* groups = entry.get("group_by")) {
      search.group_by = reader.choice(*groups, search_groups, "group_by");
    }
    search.grid = scene_grid(scene);
    read_grid_lists(reader, entry, search.grid);
    if (search.parameter == SearchParameter::rtol) { // the tightest rtol against the precision
      SolverConfig tightest = search.config;
      tightest.rtol = search.range[0];
      check_config(reader, item, with_cells(scene, search.grid), tightest);
    }
    scene.searches.push_back(search);
  }
}

} // namespace pldamp::harness::scene_reading
