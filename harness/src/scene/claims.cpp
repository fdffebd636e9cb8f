// [[claim]]: what every claim says of itself, then its kind's own keys (scene.hpp, BoundClaim to
// StabilityClaim).
#include "scene/reader.hpp"

#include "common/observables.hpp"

#include "pldamp/analytic/conventions.hpp"
#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace pldamp::harness::scene_reading {
namespace {

// The external [[solver]] a [[claim]]'s `solver` names by its label, or nullptr.
const SolverConfig* external_named(const Reader& reader, const toml::table& entry,
                                   const Scene& scene) {
  const toml::node* solver = entry.get("solver");
  if (solver == nullptr) {
    return nullptr;
  }
  const std::string name = reader.string(*solver, "solver");
  for (const SolverConfig& config : scene.configs) {
    if (config.external() && config.name == name) {
      return &config;
    }
  }
  return nullptr;
}

// denser = true: the claim judged again on its grid with each list of more than one value refined
// (judge/claim_grid.hpp, denser_grid); an asymptotic claim draws only on p. A grid with nothing
// to refine would judge the same cells twice.
void read_denser(const Reader& reader, const toml::table& entry, Claim& claim) {
  const toml::node* denser = entry.get("denser");
  if (denser == nullptr || !(claim.denser = reader.boolean(*denser, "denser"))) {
    return;
  }
  const ClaimGrid& grid = claim.grid;
  if (std::holds_alternative<AsymptoticClaim>(claim.kind)) {
    if (grid.p.size() < 2) {
      reader.fail(*denser, "denser has no effect on an asymptotic claim with one p: its grid is "
                           "refined in p");
    }
    return;
  }
  const auto of_kind = [&](Damping::Kind kind) {
    return std::count_if(grid.damping.begin(), grid.damping.end(),
                         [&](const Damping& d) { return d.kind == kind; });
  };
  const bool refinable = grid.p.size() > 1 || grid.v0.size() > 1 || grid.m.size() > 1 ||
                         grid.k.size() > 1 || of_kind(Damping::Kind::e) > 1 ||
                         of_kind(Damping::Kind::alpha) > 1 || of_kind(Damping::Kind::alpha_eff) > 1;
  if (!refinable) {
    reader.fail(*denser, "denser has no effect: the claim's grid has one value in every list, "
                         "nothing to refine");
  }
}

// The configuration a bound claim names of an external solver: the [[solver]]'s own (its atol,
// onset phases, end list, in double), at the value of its sweep the claim gives (rtol or
// steps_per_contact; a [[solver]] without a sweep: either, or neither for its one
// configuration). What the claim cannot change is refused rather than ignored.
void read_external_configuration(const Reader& reader, const toml::table& entry,
                                 const toml::node& item, const SolverConfig& external,
                                 SolverConfig& config) {
  const std::string& label = external.name;
  if (const toml::node* precision = entry.get("precision")) {
    reader.fail(*precision,
                "precision has no effect on external solver " + label + ": it answers in double");
  }
  for (const char* key : {"atol", "onset_phases"}) {
    if (const toml::node* node = entry.get(key)) {
      reader.fail(*node, std::string(key) + " has no effect on external solver " + label +
                             ": a claim takes its configuration from its [[solver]] (set " + key +
                             " there)");
    }
  }
  if (external.dt) {
    reader.fail(*entry.get("solver"),
                "a claim cannot name a configuration of external solver " + label +
                    ", which sweeps dt: it names one by rtol or steps_per_contact");
  }
  const toml::node* rtol = entry.get("rtol");
  const toml::node* steps = entry.get("steps_per_contact");
  const char* swept = external.steps_per_contact ? "steps_per_contact"
                      : external.rtol            ? "rtol"
                                                 : nullptr;
  if (swept != nullptr) {
    const bool by_steps = external.steps_per_contact.has_value();
    if (const toml::node* other = by_steps ? rtol : steps) {
      reader.fail(*other, std::string(by_steps ? "rtol" : "steps_per_contact") +
                              " has no effect on external solver " + label + ", which sweeps " +
                              swept + ": name its configuration by " + swept);
    }
    if ((by_steps ? steps : rtol) == nullptr) {
      reader.fail(item, std::string("[[claim]] needs the ") + swept + " of its solver");
    }
  } else if (rtol != nullptr && steps != nullptr) {
    reader.fail(*steps,
                "a claim on external solver " + label +
                    " gives at most one of rtol and steps_per_contact, as a [[solver]] sweeps one");
  }
  if (steps != nullptr) {
    config.steps_per_contact = read_steps(reader, *steps);
  }
  if (rtol != nullptr) {
    config.rtol = reader.number_in(*rtol, "rtol", rtol_range);
  }
}

// A claim on a DEM code's calibration: the e it gives for the grid's target e (needs them, and a
// p the code has a model for).
ConventionClaim read_convention_claim(const Reader& reader, const toml::table& entry,
                                      const toml::node& item, const toml::node& node,
                                      const std::string& observable, const Claim& claim) {
  reader.only(entry, {scene_keys::claim, scene_keys::convention_claim}, "[[claim]]");
  ConventionClaim stated;
  stated.convention = reader.string(node, "convention");
  const analytic::Convention* convention = analytic::find_convention(stated.convention);
  if (convention == nullptr) {
    reader.unknown(node, "convention", analytic::convention_names(), stated.convention);
  }
  if (observable != "e") {
    reader.fail(*entry.get("observable"),
                "a convention's claim is about the e it gives: observable must be e (got " +
                    observable + ")");
  }
  if (const toml::node* limit = entry.get("limit_damping")) {
    stated.limit_damping = reader.boolean(*limit, "limit_damping");
    // The cap is an option of some codes only (analytic::capped): elsewhere the switch is idle.
    if (convention->cap != analytic::Cap::optional) {
      reader.fail(*limit, "limit_damping has no effect on convention " + stated.convention +
                              ", which " +
                              (convention->cap == analytic::Cap::never ? "never" : "always") +
                              " caps the force");
    }
  }
  const bool targets = std::any_of(claim.grid.damping.begin(), claim.grid.damping.end(),
                                   [](const Damping& d) { return d.kind == Damping::Kind::e; });
  const bool models = std::any_of(claim.grid.p.begin(), claim.grid.p.end(), [&](double p) {
    return (convention->linear && p == 1) || (convention->hertz && p == 1.5);
  });
  if (!targets || !models) {
    reader.fail(item, "[[claim]] " + claim.name + " needs target e and a p " + stated.convention +
                          " has a model for (" + (convention->linear ? "1 or 1.5" : "1.5") + ")");
  }
  return stated;
}

// kind = "bound": its observable and error bound, its grid (the scene's, or its own lists), then a
// convention's calibration or a solver configuration (one of an external solver's sweep).
void read_bound_claim(const Reader& reader, const toml::table& entry, const toml::node& item,
                      const Scene& scene, Claim& claim) {
  if (entry.get("observable") == nullptr) {
    reader.fail(item, "[[claim]] needs observable");
  }
  const std::string observable = reader.string(*entry.get("observable"), "observable");
  const ErrorBound error = read_error_bound(reader, entry, item, "[[claim]]");
  claim.grid = scene_grid(scene);
  read_grid_lists(reader, entry, claim.grid);
  const bool own_grid =
      std::any_of(scene_keys::bound_claim_grid.begin(), scene_keys::bound_claim_grid.end(),
                  [&](std::string_view key) { return entry.get(key) != nullptr; });
  read_denser(reader, entry, claim);
  const toml::node* allow_missing = entry.get("allow_missing");
  const bool missing_allowed =
      allow_missing != nullptr && reader.boolean(*allow_missing, "allow_missing");
  if (const toml::node* convention = entry.get("convention")) {
    ConventionClaim stated =
        read_convention_claim(reader, entry, item, *convention, observable, claim);
    stated.error = error;
    stated.own_grid = own_grid;
    claim.kind = stated;
    return;
  }
  reader.only(entry, {scene_keys::claim, scene_keys::bound_claim}, "[[claim]]");
  BoundClaim stated{.observable = observable,
                    .config = {},
                    .error = error,
                    .own_grid = own_grid,
                    .allow_missing = missing_allowed};
  SolverConfig& config = stated.config;
  const SolverConfig* external = external_named(reader, entry, scene);
  if (external != nullptr) {
    config = *external;
    config.rtol.reset();
    config.steps_per_contact.reset();
    config.dt.reset();
  } else {
    config = base_config(reader, entry, "solver", "[[claim]]", item);
  }
  config.end = read_end(reader, entry, "a claim's");
  require_wanted(reader, *entry.get("observable"), observable, scene.want, "claim");
  if (external != nullptr) {
    read_external_configuration(reader, entry, item, *external, config);
    claim.kind = stated;
    return;
  }
  const solvers::SolverInfo& info = solvers::solver_named(config.name);
  refuse_untaken_step_keys(reader, entry, info);
  const bool fixed_step = info.fixed_step;
  if (const toml::node* value = entry.get(fixed_step ? "steps_per_contact" : "rtol")) {
    if (fixed_step) {
      config.steps_per_contact = read_steps(reader, *value);
    } else {
      config.rtol = reader.number_in(*value, "rtol", rtol_range);
    }
  } else if (info.default_tolerance != solvers::DefaultTolerance::epsilon || fixed_step) {
    reader.fail(item, std::string("[[claim]] needs the ") +
                          (fixed_step ? "steps_per_contact" : "rtol") + " of its solver");
  }
  check_config(reader, item, with_cells(scene, claim.grid), config);
  claim.kind = stated;
}

// The solver of a claim of the other kinds, in double (the seed's own runs were double): name,
// rtol (error-controlled) or steps_per_contact (fixed-step; stability needs none), atol.
SolverConfig claim_solver(const Reader& reader, const toml::table& entry, const toml::node& item,
                          const Scene& scene, ClaimKind kind) {
  SolverConfig config = base_config(reader, entry, "solver", "[[claim]]", item);
  const solvers::SolverInfo& info = solvers::solver_named(config.name);
  if (kind == ClaimKind::stability) {
    if (!info.fixed_step) {
      reader.fail(*entry.get("solver"), "a stability claim is about a fixed-step scheme (got " +
                                            config.name + ", which controls its error)");
    }
    return config;
  }
  refuse_untaken_step_keys(reader, entry, info);
  if (info.fixed_step) {
    const toml::node* steps = entry.get("steps_per_contact");
    config.steps_per_contact = steps ? read_steps(reader, *steps) : 50;
  } else if (const toml::node* rtol = entry.get("rtol")) {
    config.rtol = reader.number_in(*rtol, "rtol", rtol_range);
  } else if (info.default_tolerance != solvers::DefaultTolerance::epsilon) {
    reader.fail(item, "[[claim]] needs the rtol of its solver");
  }
  check_config(reader, item, scene, config);
  return config;
}

scene_keys::Keys keys_of(ClaimKind kind) {
  switch (kind) {
  case ClaimKind::relation:
    return scene_keys::relation_claim;
  case ClaimKind::asymptotic:
    return scene_keys::asymptotic_claim;
  case ClaimKind::recovered_parameter:
    return scene_keys::recovered_parameter_claim;
  case ClaimKind::stability:
    return scene_keys::stability_claim;
  case ClaimKind::bound:
    break;
  }
  return scene_keys::bound_claim;
}

// relation, asymptotic, recovered_parameter, stability: a claim judged on a grid of its own.
void read_grid_claim(const Reader& reader, const toml::table& entry, const toml::node& item,
                     const Scene& scene, ClaimKind kind, Claim& claim) {
  const std::string kind_name(name_of(claim_kinds, kind));
  auto need = [&](const char* key) -> const toml::node& {
    if (entry.get(key) == nullptr) {
      reader.fail(item, "[[claim]] " + claim.name + " (" + kind_name + ") needs " + key);
    }
    return *entry.get(key);
  };
  auto formula = [&]() {
    const toml::node& node = need("formula");
    const std::string name = reader.string(node, "formula");
    const analytic::seed::FormulaInfo* found = analytic::seed::find_formula(name);
    if (found == nullptr) {
      std::string names;
      for (const analytic::seed::FormulaInfo& info : analytic::seed::formulas) {
        names += names.empty() ? "" : "|";
        names += info.name;
      }
      reader.unknown(node, "formula", names, name);
    }
    return found->formula;
  };
  const bool solver = entry.get("solver") != nullptr;
  // relation, asymptotic: the quantity, the formula, and whose quantity (the solver's is read
  // with the claim's grid).
  auto quantity_and_formula = [&](auto& stated) {
    stated.of.quantity = reader.choice(need("quantity"), quantities, "quantity");
    stated.formula = formula();
    if (const toml::node* of = entry.get("of")) {
      if (reader.string(*of, "of") != "truth" || solver) {
        reader.fail(*of, "of = \"truth\" (the closed forms) or a solver = NAME, not both");
      }
    } else if (!solver) {
      reader.fail(item, "[[claim]] " + claim.name + " needs of = \"truth\" or a solver");
    }
  };
  switch (kind) {
  case ClaimKind::relation: {
    RelationClaim stated;
    quantity_and_formula(stated);
    stated.relation = reader.choice(need("relation"), relations, "relation");
    // The truth's own accuracy in float128 when no tolerance is given.
    stated.tolerance = 1e-25;
    if (const toml::node* tolerance = entry.get("tolerance")) {
      stated.tolerance = reader.number_in(*tolerance, "tolerance", Range::closed_open(0, 1e300));
    } else if (solver || stated.relation == Relation::equal_within) {
      need("tolerance");
    }
    if (const toml::node* absolute = entry.get("absolute")) {
      stated.absolute = reader.boolean(*absolute, "absolute");
    }
    claim.kind = stated;
    break;
  }
  case ClaimKind::asymptotic: {
    AsymptoticClaim stated;
    quantity_and_formula(stated);
    stated.order = reader.number_in(need("order"), "order", Range::open_closed(0, 20));
    if (const toml::node* range = entry.get("range")) {
      const std::vector<double> ends = reader.numbers(*range, "range");
      if (ends.size() != 2 || !(ends[0] > 0 && ends[1] < 1 && ends[1] >= 100 * ends[0])) {
        reader.fail(*range, "range must be [from, to] in alpha_eff with 0 < from, to < 1 and at "
                            "least two decades (to >= 100 from)");
      }
      stated.range = {ends[0], ends[1]};
    }
    if (const toml::node* points = entry.get("points")) {
      stated.points = static_cast<int>(reader.integer_in(*points, "points", 3, 1000));
    }
    claim.kind = stated;
    break;
  }
  case ClaimKind::recovered_parameter:
    claim.kind = RecoveredParameterClaim{
        .config = {}, .bound = reader.number_in(need("bound"), "bound", Range::above(0))};
    need("solver");
    break;
  case ClaimKind::stability: {
    StabilityClaim stated;
    stated.formula = formula();
    if (const toml::node* fraction = entry.get("fraction")) {
      stated.fraction = reader.number_in(*fraction, "fraction", Range::open_closed(0, 10));
    }
    if (stated.formula != analytic::seed::Formula::dt_crit) {
      reader.fail(*entry.get("formula"), "a stability claim compares with a time step: formula "
                                         "must be seed_dt_crit");
    }
    claim.kind = stated;
    need("solver");
    break;
  }
  case ClaimKind::bound:
    break;
  }
  reader.only(entry, {scene_keys::claim, keys_of(kind)}, "[[claim]] of kind " + kind_name);
  claim.grid = scene_grid(scene);
  read_grid_lists(reader, entry, claim.grid);
  if (kind == ClaimKind::asymptotic) { // judged at one contact scale (judge/claims.cpp)
    for (const auto& [key, values] :
         {std::pair{"v0", &claim.grid.v0}, std::pair{"m", &claim.grid.m},
          std::pair{"k", &claim.grid.k}}) {
      if (const toml::node* node = entry.get(key); node != nullptr && values->size() > 1) {
        reader.fail(*node, fmt::format("an asymptotic claim is judged at one {} (got {} values)",
                                       key, values->size()));
      }
    }
  }
  if (!solver) { // of = "truth": the closed forms, which take no solver's settings
    for (const char* key : {"rtol", "atol", "steps_per_contact"}) {
      if (const toml::node* node = entry.get(key)) {
        reader.fail(*node, std::string(key) +
                               " has no effect on the truth (of = \"truth\", the closed forms): "
                               "it is a solver's setting");
      }
    }
  }
  if (solver) { // recovered_parameter and stability need one
    // The solver's tolerances are checked against the claim's own cells.
    const SolverConfig config =
        claim_solver(reader, entry, item, with_cells(scene, claim.grid), kind);
    std::visit(
        [&](auto& stated) {
          if constexpr (requires { stated.of.solver; }) {
            stated.of.solver = config;
          } else if constexpr (requires { stated.config; }) {
            stated.config = config;
          }
        },
        claim.kind);
  }
  const bool targets =
      std::all_of(claim.grid.damping.begin(), claim.grid.damping.end(),
                  [](const Damping& d) { return d.kind == Damping::Kind::e && d.value < 1; });
  if (kind == ClaimKind::recovered_parameter && !targets) {
    reader.fail(item, "[[claim]] " + claim.name +
                          " recovers alpha for target e: its grid needs "
                          "e in (0, 1), not alpha or alpha_eff");
  }
  read_denser(reader, entry, claim);
}

} // namespace

ErrorBound read_error_bound(const Reader& reader, const toml::table& entry, const toml::node& item,
                            const std::string& where) {
  const toml::node* absolute = entry.get("bound");
  const toml::node* relative = entry.get("bound_rel");
  if ((absolute == nullptr) == (relative == nullptr)) {
    reader.fail(absolute != nullptr ? *absolute : item,
                where + " needs one of bound (absolute error) and bound_rel (relative error)");
  }
  ErrorBound out;
  out.relative = relative != nullptr;
  out.bound = out.relative ? reader.number_in(*relative, "bound_rel", Range::above(0))
                           : reader.number_in(*absolute, "bound", Range::above(0));
  if (const toml::node* quantile = entry.get("quantile")) {
    out.quantile = reader.number_in(*quantile, "quantile", Range::open_closed(0, 1));
  }
  return out;
}

void require_wanted(const Reader& reader, const toml::node& node, const std::string& observable,
                    unsigned want, const std::string& what) {
  const std::vector<const Observable*> wanted = observables_of(want);
  if (std::none_of(wanted.begin(), wanted.end(),
                   [&](const Observable* o) { return o->key == observable; })) {
    std::string names;
    for (const Observable* o : wanted) {
      names += names.empty() ? "" : "|";
      names += o->key;
    }
    reader.fail(node, what + " observable must be one the scene wants: " + names + " (got " +
                          observable + ")");
  }
}

void read_claims(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "claim")) {
    const toml::table& entry = reader.table(item, "[[claim]]");
    Claim claim;
    if (entry.get("name") == nullptr) {
      reader.fail(item, "[[claim]] needs name");
    }
    claim.name = reader.string(*entry.get("name"), "claim name");
    // A claim's name is its identity in report.json and `pldamp diff`: two of one name would be
    // judged apart and compared as one.
    if (std::any_of(scene.claims.begin(), scene.claims.end(),
                    [&](const Claim& earlier) { return earlier.name == claim.name; })) {
      reader.fail(*entry.get("name"), "[[claim]] " + claim.name + " is named twice");
    }
    const toml::node* kind_node = entry.get("kind");
    const ClaimKind kind =
        kind_node ? reader.choice(*kind_node, claim_kinds, "claim kind") : ClaimKind::bound;
    for (const char* key : {"where", "quote"}) {
      if (const toml::node* text = entry.get(key)) {
        (key[0] == 'w' ? claim.where : claim.quote) = reader.string(*text, key);
      }
    }
    if (const toml::node* figure = entry.get("figure")) {
      claim.figure =
          std::string(name_of(figure_kinds, reader.choice(*figure, figure_kinds, "figure")));
    }
    if (const toml::node* expect = entry.get("expect")) {
      const std::string word = reader.string(*expect, "expect");
      if (word != "holds" && word != "fails") {
        reader.fail(*expect, "expect must be holds or fails (got " + word + ")");
      }
      claim.expect_holds = word == "holds";
    }
    if (kind == ClaimKind::bound) {
      read_bound_claim(reader, entry, item, scene, claim);
    } else {
      read_grid_claim(reader, entry, item, scene, kind, claim);
    }
    scene.claims.push_back(std::move(claim));
  }
}

} // namespace pldamp::harness::scene_reading
