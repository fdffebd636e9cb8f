// The parts of a run shared among MPI ranks that need no MPI (distribution.hpp).
#include "pldamp/harness/distribution.hpp"

#include "common/input.hpp"
#include "common/parallel.hpp"
#include "scene/scene.hpp"
#include "truth/point_bytes.hpp"

#include <algorithm>
#include <exception>
#include <limits>
#include <stdexcept>

namespace pldamp::harness {

NotReady not_ready_message(int rank, const std::vector<std::string>& failures) {
  if (rank != 0) {
    return {};
  }
  if (!failures.at(0).empty()) {
    return {failures[0], true};
  }
  const auto failed = [](const std::string& f) { return !f.empty(); };
  const auto first = std::find_if(failures.begin(), failures.end(), failed);
  if (first == failures.end()) {
    return {};
  }
  const auto more = std::count_if(first + 1, failures.end(), failed);
  return {"rank " + std::to_string(first - failures.begin()) + ": " + *first +
              (more == 0 ? ""
                         : " (and " + std::to_string(more) + " more rank" + (more == 1 ? "" : "s") +
                               " could not start)"),
          false};
}

std::vector<Point> points_on_ranks(Distribution& distribution, std::size_t count,
                                   const std::function<Point(std::size_t)>& point_at, int jobs) {
  const auto rank = static_cast<std::size_t>(distribution.rank());
  const auto ranks = static_cast<std::size_t>(distribution.size());
  // What a failed point threw, as the command line tells them apart (cli.cpp).
  enum : std::uint8_t { none, scene_error, input_error, internal_error };
  std::vector<Point> mine((count + ranks - 1 - std::min(rank, count)) / ranks);
  std::vector<std::exception_ptr> thrown(mine.size());
  for_each_index(mine.size(), jobs, [&](std::size_t i) {
    try {
      mine[i] = point_at(rank + i * ranks);
    } catch (...) {
      thrown[i] = std::current_exception();
    }
  });
  std::uint8_t failed = none;
  std::uint64_t failed_at = 0;
  std::string why;
  if (const auto first =
          std::find_if(thrown.begin(), thrown.end(),
                       [](const std::exception_ptr& e) { return static_cast<bool>(e); });
      first != thrown.end()) {
    failed_at = rank + static_cast<std::size_t>(first - thrown.begin()) * ranks;
    try {
      std::rethrow_exception(*first);
    } catch (const SceneError& e) {
      failed = scene_error;
      why = e.what();
    } catch (const std::invalid_argument& e) {
      failed = input_error;
      why = e.what();
    } catch (const std::exception& e) {
      failed = internal_error;
      why = e.what();
    } catch (...) {
      failed = internal_error;
      why = "an unknown exception";
    }
  }
  std::string bytes;
  ByteWriter out(bytes);
  out.put(failed);
  out.put(failed_at);
  out.put(why);
  append_points(bytes, failed == none ? std::span<const Point>(mine) : std::span<const Point>());
  const std::vector<std::string> shares = distribution.all_gather(bytes);
  std::vector<Point> points(count);
  std::uint64_t first_failure = std::numeric_limits<std::uint64_t>::max();
  std::uint8_t first_kind = none;
  std::string first_why;
  for (std::size_t r = 0; r < shares.size(); ++r) {
    const std::string source = "rank " + std::to_string(r) + "'s points";
    ByteReader in(shares[r], source);
    const auto kind = in.get<std::uint8_t>();
    const auto at = in.get<std::uint64_t>();
    std::string said = in.string();
    if (kind != none && at < first_failure) {
      first_failure = at;
      first_kind = kind;
      first_why = std::move(said);
    }
    std::vector<Point> share = read_points(in.rest(), source);
    for (std::size_t i = 0; i < share.size(); ++i) {
      points.at(r + i * ranks) = std::move(share[i]);
    }
  }
  switch (first_kind) {
  case scene_error:
    throw SceneError(first_why);
  case input_error:
    throw InputError(first_why);
  case internal_error:
    throw InternalError(first_why);
  default:
    return points;
  }
}

} // namespace pldamp::harness
