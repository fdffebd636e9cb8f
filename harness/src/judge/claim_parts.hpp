// What the judges of judge/claims.cpp (bound kinds solved for the claim, verdicts) and
// claims_relation.cpp (relations and asymptotics) share: a claim cell's contact in Exact, a
// claimed quantity's value there, and the largest or smallest value over a grid.
#pragma once

#include "judge/claims.hpp"
#include "run/workers.hpp"
#include "truth/plan.hpp"

#include "pldamp/analytic/observables.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness::claim_parts {

using analytic::Contact;

// The seed's contact of a claim's cell, in Exact.
Contact<Exact> truth_contact(const ClaimCell& cell);

// What a quantity asks of the closed forms and of a solver, and where a solver's result holds it.
struct QuantityWants {
  unsigned analytic, solver;
  std::optional<double> solvers::Result<double>::*value;
};
QuantityWants wants_of(Quantity quantity);

// A quantity's closed form in Exact.
Exact truth_value(Quantity quantity, const Contact<Exact>& c);

// The claim's quantity at a contact: the closed form in Exact, or the solver's in double (its
// τ(α)/τ(0) from two solves). Throws std::runtime_error when the solver gives none.
Exact quantity_value(const Scene& scene, const MeasuredQuantity& of, const Contact<Exact>& c);

// The largest (Most) or smallest (Least) value seen over a grid, and the cell it came from. NaN
// counts as the most extreme.
enum class Keep { most, least };
template <Keep keep>
class Extreme {
public:
  void see(double value, const std::string& where) {
    const bool beyond = keep == Keep::most ? !(value <= value_) : !(value >= value_);
    if (!seen_ || beyond) {
      seen_ = true;
      value_ = value;
      where_ = where;
    }
  }
  explicit operator bool() const { return seen_; }
  double value() const { return seen_ ? value_ : 0; }
  const std::string& where() const { return where_; }

private:
  bool seen_ = false;
  double value_ = 0;
  std::string where_;
};
using Largest = Extreme<Keep::most>;
using Smallest = Extreme<Keep::least>;

// At most a bound: measured = the largest, margin = bound / measured.
void conclude_at_most(Judgement& j, const Largest& largest, double bound);

// The kinds judged in claims_relation.cpp, over `grid`.
Judgement judge(const Scene& scene, const RelationClaim& claim, const ClaimGrid& grid,
                std::vector<MeasuredOrder>& orders, const Workers& workers);
Judgement judge(const Scene& scene, const AsymptoticClaim& claim, const ClaimGrid& grid,
                std::vector<MeasuredOrder>& orders, const Workers& workers);

} // namespace pldamp::harness::claim_parts
