// Who computes a map of independent pieces (common/parallel.hpp): `jobs` threads of this process
// and, under MPI, the run's ranks. A map shared among the ranks (map_shared) gives rank r the
// pieces r, r + N, r + 2N, ... (each on its threads), and the ranks exchange the results as bytes
// (Encoding), bit for bit: every rank then holds every piece's result and goes on in step with the
// others, to the next shared map. That is how a run's claims on grids of their own, its searches
// and its time-step study are shared (judge/), each piece computed once in the run.
//
// Every rank calls the same shared maps in the same order: what decides whether a map is made,
// and over how many pieces, must be the same on every rank (the scene, the plan, results of
// earlier shared maps), never a rank's own records, timings or signals. A map inside a piece of a
// shared map is not shared (it is given a thread count only): the pieces run on one rank each.
#pragma once

#include "common/bytes.hpp"
#include "common/parallel.hpp"
#include "pldamp/harness/distribution.hpp"

#include <cstddef>
#include <exception>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct Workers {
  int jobs = 1;
  Distribution* ranks = nullptr; // none, or one rank: this process alone

  Workers(int threads) : jobs(threads) {} // NOLINT(google-explicit-constructor): threads alone
  Workers(int threads, Distribution* shared_with) : jobs(threads), ranks(shared_with) {}
  bool shared() const { return ranks != nullptr && ranks->size() > 1; }
};

// How a map's result travels between ranks, exact: by the functions `put_piece(ByteWriter&, const
// T&)` and `get_piece(ByteReader&, T&)` found beside T (argument-dependent lookup), or by a
// specialisation for types that have no namespace of ours (bool, std::optional<std::string>).
template <class T>
struct Encoding {
  static void put(ByteWriter& out, const T& value) { put_piece(out, value); }
  static T get(ByteReader& in) {
    T value{};
    get_piece(in, value);
    return value;
  }
};

// The exchange behind map_shared: every rank's `results` (the bytes of its pieces, in its order),
// once each rank said which of its pieces failed first (`failed_at`, `failure`). A failure on any
// rank is thrown on every rank alike, the lowest failing index's, as the serial map would throw it
// (SceneError, InputError, InternalError: what the command line tells apart). A stop request on
// any rank becomes every rank's (stop_requested, run/run.hpp).
std::vector<std::string> exchange_pieces(Distribution& ranks, const std::string& results,
                                         std::size_t failed_at, std::exception_ptr failure);

// f(i) for every i in [0, count), in index order, as map_indices, shared among the ranks when
// `workers` are.
template <class T, class F>
std::vector<T> map_shared(std::size_t count, const Workers& workers, F&& f) {
  if (!workers.shared()) {
    return map_indices<T>(count, workers.jobs, f);
  }
  const auto rank = static_cast<std::size_t>(workers.ranks->rank());
  const auto ranks = static_cast<std::size_t>(workers.ranks->size());
  std::vector<T> mine(count > rank ? (count - rank + ranks - 1) / ranks : 0);
  std::vector<std::exception_ptr> thrown(mine.size());
  for_each_index(mine.size(), workers.jobs, [&](std::size_t i) {
    try {
      mine[i] = f(rank + i * ranks);
    } catch (...) {
      thrown[i] = std::current_exception();
    }
  });
  std::string bytes;
  std::size_t failed_at = count; // this rank's first failing piece, if one failed
  std::exception_ptr failure;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    if (thrown[i]) {
      failure = thrown[i];
      failed_at = rank + i * ranks;
      break;
    }
  }
  if (!failure) {
    ByteWriter out(bytes);
    for (const T& result : mine) {
      Encoding<T>::put(out, result);
    }
  }
  const std::vector<std::string> shares =
      exchange_pieces(*workers.ranks, bytes, failed_at, failure);
  std::vector<T> all(count);
  for (std::size_t r = 0; r < shares.size(); ++r) {
    const std::string source = "rank " + std::to_string(r) + "'s results";
    ByteReader in(shares[r], source);
    for (std::size_t i = r; i < count; i += ranks) {
      all[i] = Encoding<T>::get(in);
    }
    if (!in.at_end()) {
      in.corrupt();
    }
  }
  return all;
}

template <>
struct Encoding<bool> {
  static void put(ByteWriter& out, bool value) { out.put<std::uint8_t>(value ? 1 : 0); }
  static bool get(ByteReader& in) {
    const auto flag = in.get<std::uint8_t>();
    if (flag > 1) {
      in.corrupt();
    }
    return flag == 1;
  }
};

template <>
struct Encoding<std::optional<std::string>> {
  static void put(ByteWriter& out, const std::optional<std::string>& text) {
    Encoding<bool>::put(out, text.has_value());
    if (text) {
      out.put(*text);
    }
  }
  static std::optional<std::string> get(ByteReader& in) {
    return Encoding<bool>::get(in) ? std::optional<std::string>(in.string()) : std::nullopt;
  }
};

} // namespace pldamp::harness
