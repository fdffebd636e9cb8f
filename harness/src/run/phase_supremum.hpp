// The worst over every onset phase φ ∈ [0, 1) of a fixed-step scheme's errors, not over a sample
// of phases (docs/MATH.md §5.2). For a fixed step the scheme's results are piecewise smooth in φ:
// the pieces change where the step position leaving the contact changes (there e and τ jump) or
// the one holding a peak does (there δ_max and the peak force have a kink). So, from values at
// sampled phases (k/n, and the largest double below 1):
//   1. every change of the piece between two neighbouring phases is bisected to the double's
//      resolution in φ (2^-52), both sides evaluated: the supremum at a jump is approached from
//      one side and reached there to that resolution, a kink's at it (a phase at which another
//      piece begins in between is bisected on both sides);
//   2. every sampled local maximum of a score inside a piece is sought by Brent's method between
//      its neighbours;
//   3. a piece found in between by step 2 sends the search back to step 1.
// Every point evaluated is a real phase: the worst found is reached at a phase the caller reports,
// and a user reproduces it with `solve --onset-phase`. A score is what to maximize (a relative
// error); −inf where there is none, +inf where the run failed (nothing more is sought then).
#pragma once

#include <boost/math/tools/minima.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace pldamp::harness {

struct PhasePoint {
  double phase = 0;
  long piece = 0;             // which smooth piece it lies on (piece_of)
  std::vector<double> scores; // one per quantity maximized
};

// Which smooth piece a fixed-step run at `phase` lies on: its steps to the exit, and the step
// positions holding the overlap's and the force's peaks (a kink where either changes, located by
// bisection like a jump). A peak time on the step grid (the DEM loops report the position) is
// that position; between positions (verlet-predicted interpolates) the interval's start.
template <class Result>
long piece_of(const Result& result, double phase) {
  long piece = result.steps;
  for (const auto& time : {result.t_peak, result.t_normal_force_max}) {
    long index = -1;
    if (time && result.fixed_step) {
      const double steps = static_cast<double>(*time / *result.fixed_step) - phase;
      const double nearest = std::round(steps);
      index = static_cast<long>(std::abs(steps - nearest) < 1e-6 ? nearest : std::floor(steps));
    }
    piece = piece * 1000003 + index;
  }
  return piece;
}

// The phases a search begins with: k/n and the largest double below 1 (φ → 1 is not φ = 0: at
// φ = 0 a step position falls on the moment of contact).
inline std::vector<double> sampled_phases(int n) {
  std::vector<double> phases;
  for (int k = 0; k < n; ++k) {
    phases.push_back(double(k) / double(n));
  }
  phases.push_back(std::nextafter(1.0, 0.0));
  return phases;
}

// Refines `points` (at least the sampled phases, any order) with evaluate(φ) -> PhasePoint until
// the supremum of every score is found, or a score exceeds `enough` (a search's bound: the value
// fails whatever the supremum), or `budget` evaluations are spent (returns false then: the worst
// found is a lower bound).
template <class Evaluate>
bool refine_to_supremum(std::vector<PhasePoint>& points, Evaluate&& evaluate, int budget = 4000,
                        double enough = std::numeric_limits<double>::infinity()) {
  constexpr double resolution = 0x1p-52;
  constexpr double inf = std::numeric_limits<double>::infinity();
  int spent = 0;
  bool beyond = false; // a score above `enough`, +inf or NaN: nothing more to seek
  auto note = [&](const PhasePoint& point) {
    for (const double score : point.scores) {
      beyond = beyond || !(score < inf && score <= enough);
    }
  };
  std::for_each(points.begin(), points.end(), note);
  auto at = [&](double phase) -> const PhasePoint& {
    ++spent;
    points.push_back(evaluate(phase));
    note(points.back());
    return points.back();
  };
  auto by_phase = [&] {
    std::sort(points.begin(), points.end(),
              [](const PhasePoint& a, const PhasePoint& b) { return a.phase < b.phase; });
  };
  // Step 1 between two phases of different pieces.
  auto bisect = [&](auto&& self, double a, long piece_a, double b, long piece_b) -> void {
    while (b - a > resolution && spent < budget && !beyond) {
      const double mid = a + (b - a) / 2;
      if (mid <= a || mid >= b) {
        return;
      }
      const long piece = at(mid).piece;
      if (piece == piece_a) {
        a = mid;
      } else if (piece == piece_b) {
        b = mid;
      } else {
        self(self, a, piece_a, mid, piece);
        a = mid;
        piece_a = piece;
      }
    }
  };
  std::vector<std::pair<double, double>> bisected, sought;
  for (int round = 0; round < 4 && !beyond; ++round) {
    by_phase();
    std::vector<PhasePoint> ends; // copies: bisect appends to points
    for (std::size_t i = 1; i < points.size(); ++i) {
      const PhasePoint &a = points[i - 1], &b = points[i];
      if (a.piece != b.piece && b.phase - a.phase > resolution &&
          std::find(bisected.begin(), bisected.end(), std::pair(a.phase, b.phase)) ==
              bisected.end()) {
        ends.push_back(a);
        ends.push_back(b);
      }
    }
    for (std::size_t j = 0; j < ends.size(); j += 2) {
      bisected.emplace_back(ends[j].phase, ends[j + 1].phase);
      bisect(bisect, ends[j].phase, ends[j].piece, ends[j + 1].phase, ends[j + 1].piece);
    }
    // Step 2: each score's local maxima inside a piece, between their neighbours.
    by_phase();
    const std::size_t before = points.size();
    struct Bracket {
      double a, b;
      std::size_t score;
    };
    std::vector<Bracket> brackets;
    const std::size_t scores = points.front().scores.size();
    for (std::size_t s = 0; s < scores; ++s) {
      for (std::size_t i = 1; i + 1 < points.size(); ++i) {
        const PhasePoint &left = points[i - 1], &mid = points[i], &right = points[i + 1];
        if (left.piece == mid.piece && right.piece == mid.piece && mid.scores[s] > -inf &&
            mid.scores[s] >= left.scores[s] && mid.scores[s] >= right.scores[s] &&
            (mid.scores[s] > left.scores[s] || mid.scores[s] > right.scores[s]) &&
            std::find(sought.begin(), sought.end(), std::pair(left.phase, right.phase)) ==
                sought.end()) {
          brackets.push_back({left.phase, right.phase, s});
        }
      }
    }
    for (const Bracket& bracket : brackets) {
      if (spent >= budget || beyond) {
        break;
      }
      sought.emplace_back(bracket.a, bracket.b);
      std::uintmax_t iterations = 30;
      boost::math::tools::brent_find_minima(
          [&](double phase) {
            if (beyond) {
              return 0.0; // nothing more is sought
            }
            const PhasePoint& point = at(phase);
            const double score = point.scores[bracket.score];
            return score > -inf ? -score : inf;
          },
          bracket.a, bracket.b, 20, iterations);
    }
    if (points.size() == before || spent >= budget || beyond) {
      break;
    }
    // Another round only finds something where step 2 met a piece between two of the same.
    by_phase();
    bool unbisected = false;
    for (std::size_t i = 1; i < points.size() && !unbisected; ++i) {
      unbisected = points[i - 1].piece != points[i].piece &&
                   points[i].phase - points[i - 1].phase > resolution &&
                   std::find(bisected.begin(), bisected.end(),
                             std::pair(points[i - 1].phase, points[i].phase)) == bisected.end();
    }
    if (!unbisected) {
      break;
    }
  }
  return spent < budget || beyond;
}

} // namespace pldamp::harness
