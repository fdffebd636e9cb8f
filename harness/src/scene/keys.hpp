// The keys each table of a scene takes, in the order a refusal lists them ("unknown key in
// [grid], expected p|e|alpha|... (got q)"). The reader refuses any other key, and docs/scenes.md
// documents exactly these, table by table (tests/harness/scene_docs_test.cpp walks `tables`).
#pragma once

#include <array>
#include <span>
#include <string_view>

namespace pldamp::harness::scene_keys {

using Keys = std::span<const std::string_view>;

inline constexpr auto top_level = std::to_array<std::string_view>(
    {"name", "end", "want", "contact", "grid", "solver", "claim", "search", "figure", "trajectory",
     "report", "timing", "limits", "diff"});

inline constexpr auto contact = std::to_array<std::string_view>(
    {"name", "geometry", "radius", "young", "poisson", "density", "v0"});

inline constexpr auto grid = std::to_array<std::string_view>(
    {"p", "e", "alpha", "alpha_eff", "v0", "m", "k", "damping_exponent"});

inline constexpr auto solver = std::to_array<std::string_view>(
    {"name", "rtol", "atol", "precision", "steps_per_contact", "end", "onset_phases", "tau_as"});

inline constexpr auto external_solver = std::to_array<std::string_view>(
    {"command", "label", "options", "replica", "rtol", "atol", "steps_per_contact", "dt", "end",
     "onset_phases", "precision"});

// Every claim's; each kind's own keys follow them.
inline constexpr auto claim =
    std::to_array<std::string_view>({"name", "kind", "where", "quote", "figure", "expect"});

// The lists a bound claim may have of its own (any of them: `own_grid`).
inline constexpr auto bound_claim_grid =
    std::to_array<std::string_view>({"p", "e", "alpha", "alpha_eff", "v0", "m", "k"});

inline constexpr auto bound_claim =
    std::to_array<std::string_view>({"observable", "solver",
                                     "rtol",       "atol",
                                     "precision",  "steps_per_contact",
                                     "end",        "onset_phases",
                                     "tau_as",     "bound",
                                     "bound_rel",  "quantile",
                                     "denser",     "allow_missing",
                                     "p",          "e",
                                     "alpha",      "alpha_eff",
                                     "v0",         "m",
                                     "k"});

inline constexpr auto convention_claim =
    std::to_array<std::string_view>({"observable", "convention", "limit_damping", "bound",
                                     "bound_rel", "quantile", "p", "e", "denser"});

inline constexpr auto relation_claim = std::to_array<std::string_view>(
    {"denser", "p", "v0", "m", "k", "quantity", "formula", "of", "solver", "rtol", "atol",
     "steps_per_contact", "relation", "tolerance", "absolute", "e", "alpha_eff"});

inline constexpr auto asymptotic_claim = std::to_array<std::string_view>(
    {"denser", "p", "v0", "m", "k", "quantity", "formula", "of", "solver", "rtol", "atol",
     "steps_per_contact", "order", "range", "points"});

inline constexpr auto recovered_parameter_claim = std::to_array<std::string_view>(
    {"denser", "p", "v0", "m", "k", "solver", "rtol", "atol", "steps_per_contact", "bound", "e"});

inline constexpr auto stability_claim = std::to_array<std::string_view>(
    {"denser", "p", "v0", "m", "k", "solver", "formula", "fraction", "e", "alpha_eff"});

inline constexpr auto search =
    std::to_array<std::string_view>({"name",      "where",        "quote",      "solver",
                                     "precision", "atol",         "rtol",       "steps_per_contact",
                                     "parameter", "range",        "observable", "bound",
                                     "bound_rel", "quantile",     "group_by",   "p",
                                     "e",         "alpha_eff",    "v0",         "m",
                                     "k",         "onset_phases", "end",        "tau_as"});

inline constexpr auto figure =
    std::to_array<std::string_view>({"kind", "solver", "rtol", "atol", "p", "e", "alpha_eff"});

inline constexpr auto restitution_figure =
    std::to_array<std::string_view>({"kind", "p", "alpha_eff"});

inline constexpr auto trajectory = std::to_array<std::string_view>(
    {"file", "label", "contact", "p", "e", "alpha", "alpha_eff", "v0", "m", "k", "end"});

inline constexpr auto report = std::to_array<std::string_view>({"formats", "work_precision"});
inline constexpr auto timing = std::to_array<std::string_view>({"repeats", "repeat_below"});
inline constexpr auto limits =
    std::to_array<std::string_view>({"max_steps", "max_seconds", "max_runs"});
inline constexpr auto diff =
    std::to_array<std::string_view>({"error_factor", "work_factor", "time_factor", "time_floor"});

// A table of keys and the heading of docs/scenes.md that documents it. A claim takes the keys of
// "[[claim]]" and those of its kind.
struct KeyTable {
  std::string_view heading;
  Keys keys;
};

inline constexpr std::array tables{
    KeyTable{"the scene", top_level},
    KeyTable{"[[contact]]", contact},
    KeyTable{"[grid]", grid},
    KeyTable{"[[solver]]", solver},
    KeyTable{"[[solver]] with a command", external_solver},
    KeyTable{"[[claim]]", claim},
    KeyTable{"[[claim]] of kind bound", bound_claim},
    KeyTable{"[[claim]] of kind bound with a convention", convention_claim},
    KeyTable{"[[claim]] of kind relation", relation_claim},
    KeyTable{"[[claim]] of kind asymptotic", asymptotic_claim},
    KeyTable{"[[claim]] of kind recovered_parameter", recovered_parameter_claim},
    KeyTable{"[[claim]] of kind stability", stability_claim},
    KeyTable{"[[search]]", search},
    KeyTable{"[[figure]]", figure},
    KeyTable{"[[figure]] restitution_approximations", restitution_figure},
    KeyTable{"[[trajectory]]", trajectory},
    KeyTable{"[report]", report},
    KeyTable{"[timing]", timing},
    KeyTable{"[limits]", limits},
    KeyTable{"[diff]", diff},
};

} // namespace pldamp::harness::scene_keys
