#include "pldamp/harness/cli.hpp"
#include "pldamp/harness/distribution.hpp"

#ifdef PLDAMP_WITH_MPI
#include "mpi/mpi_main.hpp"
#endif

#include <csignal>
#include <iostream>

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) makes a write fail with EFBIG, which is reported in one line with
  // the files left as they were, instead of killing the process mid-report with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
#ifdef PLDAMP_WITH_MPI
  if (pldamp::harness::launched_by_mpi()) {
    return pldamp::harness::run_under_mpi(argc, argv);
  }
#endif
  return pldamp::harness::run_cli(argc, argv, std::cout, std::cerr);
}
