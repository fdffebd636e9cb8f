// The parts of a run shared among MPI ranks that need no MPI (distribution.hpp).
#include "pldamp/harness/distribution.hpp"

#include <algorithm>

namespace pldamp::harness {

NotReady not_ready_message(int rank, const std::vector<bool>& ready, const std::string& failure) {
  const auto first_failed = std::find(ready.begin(), ready.end(), false);
  if (!ready.at(0)) {
    return {rank == 0 ? failure : "", rank == 0};
  }
  if (rank == 0) {
    return {"rank " + std::to_string(first_failed - ready.begin()) +
                " could not start the run (that rank prints why)",
            false};
  }
  return failure.empty() ? NotReady{}
                         : NotReady{"rank " + std::to_string(rank) + ": " + failure, true};
}

} // namespace pldamp::harness
