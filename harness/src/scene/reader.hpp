// The scene reader's tools (scene/*.cpp; what it reads is docs/scenes.md): toml++ behind one class
// that reports every problem as "file:line: message" at the node it concerns, with typed reads
// that word their refusals alike ("rtol must be in (0, 1) (got 2)", "unknown solver, expected
// a|b (got c)"), and the readers of each table.
#pragma once

#include "common/input.hpp"
#include "common/names.hpp"
#include "scene/keys.hpp"
#include "scene/scene.hpp"

#include "pldamp/solvers/registry.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace pldamp::harness::scene_reading {

// Where a number must lie, as a refusal words it: "in (0, 1]", "> 0", ">= 0", then `unit`
// (" seconds").
struct Range {
  double low, high; // high infinite: no upper end
  bool low_open, high_open;
  std::string_view unit = "";

  static constexpr Range above(double low) {
    return {low, std::numeric_limits<double>::infinity(), true, true};
  }
  static constexpr Range at_least(double low) {
    return {low, std::numeric_limits<double>::infinity(), false, true};
  }
  static constexpr Range open(double low, double high) { return {low, high, true, true}; }
  static constexpr Range closed(double low, double high) { return {low, high, false, false}; }
  static constexpr Range open_closed(double low, double high) { return {low, high, true, false}; }
  static constexpr Range closed_open(double low, double high) { return {low, high, false, true}; }
  constexpr Range with_unit(std::string_view text) const {
    Range out = *this;
    out.unit = text;
    return out;
  }
  bool contains(double x) const;
  std::string text() const;
};

// Reports problems at the line of the node they concern.
class Reader {
public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const toml::node& at, const std::string& what) const;
  [[noreturn]] void fail_at(std::size_t line, const std::string& what) const;
  // "unknown <what>, expected <expected> (got <got>)".
  [[noreturn]] void unknown(const toml::node& at, const std::string& what,
                            const std::string& expected, const std::string& got) const;

  // Every key of `table` must be one of `allowed` (the concatenation of its parts).
  void only(const toml::table& table, std::initializer_list<scene_keys::Keys> allowed,
            const std::string& where) const;

  double number(const toml::node& node, const std::string& what) const;
  // A number or a non-empty list of numbers.
  std::vector<double> numbers(const toml::node& node, const std::string& what) const;
  // A number in `range`, or "<what> must be <range> (got <value>)".
  double number_in(const toml::node& node, const std::string& what, const Range& range) const;
  // An integer in [low, high], or "<what> must be an integer in [low, high] (got <value>)".
  long integer_in(const toml::node& node, const std::string& what, long low, long high) const;
  // The same checks on a value read from `node` (a list's item).
  void check_in(const toml::node& node, const std::string& what, double value,
                const Range& range) const;
  long check_integer(const toml::node& node, const std::string& what, double value, long low,
                     long high) const;
  bool boolean(const toml::node& node, const std::string& what) const;
  std::string string(const toml::node& node, const std::string& what) const;
  std::vector<std::string> strings(const toml::node& node, const std::string& what) const;
  // A word of `table`, or "unknown <what>, expected a|b|c (got word)".
  template <class Enum, std::size_t N>
  Enum choice(const toml::node& node, const NameTable<Enum, N>& table,
              const std::string& what) const {
    return choice_of(node, string(node, what), table, what);
  }
  template <class Enum, std::size_t N>
  Enum choice_of(const toml::node& at, const std::string& word, const NameTable<Enum, N>& table,
                 const std::string& what) const {
    const std::optional<Enum> value = value_named(table, word);
    if (!value) {
      unknown(at, what, names_of(table), word);
    }
    return *value;
  }
  // The entries of an array of tables, [[key]].
  const toml::array& entries(const toml::node& node, const std::string& key) const;
  const toml::table& table(const toml::node& node, const std::string& what) const;

  // Checks a condition on a value read from `node`: "<what> (got <value>)".
  void require(bool ok, const toml::node& node, const std::string& what, double value) const;
  // Runs `check` (core/domain.hpp's, which throws std::invalid_argument) on what was read from
  // `node`: its message becomes the node's refusal. A refusal of the reader's own passes through.
  template <class Check>
  void within_domain(const toml::node& node, Check&& check) const {
    try {
      check();
    } catch (const SceneError&) {
      throw;
    } catch (const std::invalid_argument& e) {
      fail(node, e.what());
    }
  }

private:
  std::string path_;
};

// A list in which a value said twice would add nothing (a cell, a point, a report file twice):
// "<key> names <value> twice".
template <class T>
void refuse_repeated(const Reader& reader, const toml::node& node, const std::string& key,
                     const std::vector<T>& values) {
  // The first value met again, in order (a set: a list of 10^5 values took seconds compared
  // pairwise). Values equal by == are one: 0 and −0; a NaN equals none.
  std::set<T> seen;
  for (const T& value : values) {
    if constexpr (std::is_floating_point_v<T>) {
      if (value != value) {
        continue;
      }
    }
    if (!seen.insert(value).second) {
      if constexpr (std::is_arithmetic_v<T>) {
        reader.fail(node, key + " names " + to_string_full(value) + " twice");
      } else {
        reader.fail(node, key + " names " + value + " twice");
      }
    }
  }
}

// Refuses, before toml++ sees the text, what it handles badly (max_scene_nesting, bytes beyond
// ASCII).
void check_text(const Reader& reader, std::string_view text);

// --- the grid and the contact (grid.cpp) ---

// The grid lists of a [grid] or a claim or search (p, e, alpha, alpha_eff, v0, m, k) that `table`
// has, each value checked against the domain (core/domain.hpp); the others stay as they are in
// `grid`. e, alpha and alpha_eff replace its damping together.
void read_grid_lists(const Reader& reader, const toml::table& table, ClaimGrid& grid);
// The contact ends of an entry's `end` key (a word or a list), none when absent.
std::vector<std::optional<solvers::End>> read_ends(const Reader& reader, const toml::table& entry);
// The one contact end of an entry (`what`: "a claim's"), none when absent.
std::optional<solvers::End> read_end(const Reader& reader, const toml::table& entry,
                                     const std::string& what);
void read_grid(const Reader& reader, const toml::node& node, Scene& scene);
// [[contact]] (contacts.cpp): before [grid], which then takes no p, v0, m or k.
void read_contacts(const Reader& reader, const toml::node& node, Scene& scene);

void read_trajectories(const Reader& reader, const toml::node& node, Scene& scene);

// --- solvers (solvers.cpp) ---

// The solver (under `key`: name in [[solver]], solver in [[claim]], [[search]] and [[figure]]),
// precision, onset_phases and atol of an entry; tolerances and steps are the caller's.
SolverConfig base_config(const Reader& reader, const toml::table& entry, const char* key,
                         const std::string& where, const toml::node& at);
// rtol is in (0, 1); steps_per_contact an integer in [1, 1e9] (read_steps, check_steps).
inline constexpr Range rtol_range = Range::open(0, 1);
int read_steps(const Reader& reader, const toml::node& node);
int check_steps(const Reader& reader, const toml::node& node, double n);
// Refuses the sweep key a registered solver's traits (solvers/registry.hpp) say it ignores: rtol
// beside a fixed-step scheme ("...; " + `fixed_step_instead`), steps_per_contact beside an
// error-controlled one.
void refuse_untaken_step_keys(const Reader& reader, const toml::table& entry,
                              const solvers::SolverInfo& info,
                              std::string_view fixed_step_instead = "set steps_per_contact");
// A configuration's tolerances against the precision it runs in and the scales of every cell.
void check_config(const Reader& reader, const toml::node& node, const Scene& scene,
                  const SolverConfig& config);
void read_solvers(const Reader& reader, const toml::node& node, Scene& scene);

// --- claims and searches (claims.cpp, search.cpp) ---

// `bound` (absolute) or `bound_rel` (relative), one of them, and `quantile`.
ErrorBound read_error_bound(const Reader& reader, const toml::table& entry, const toml::node& item,
                            const std::string& where);
// An observable the scene wants, or "<what> observable must be one the scene wants: ...".
void require_wanted(const Reader& reader, const toml::node& node, const std::string& observable,
                    unsigned want, const std::string& what);
void read_claims(const Reader& reader, const toml::node& node, Scene& scene);
void read_searches(const Reader& reader, const toml::node& node, Scene& scene);

// --- figures (figures.cpp) ---

void read_figures(const Reader& reader, const toml::node& node, Scene& scene);

} // namespace pldamp::harness::scene_reading
