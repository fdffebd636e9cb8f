#include "pldamp/harness/cli.hpp"

#ifdef PLDAMP_WITH_MPI
#include "mpi/mpi_main.hpp"
#endif

#include <iostream>

int main(int argc, char** argv) {
#ifdef PLDAMP_WITH_MPI
  if (pldamp::harness::launched_by_mpi()) {
    return pldamp::harness::run_under_mpi(argc, argv);
  }
#endif
  return pldamp::harness::run_cli(argc, argv, std::cout, std::cerr);
}
