// The `pldamp` program under MPI (PLDAMP_MPI): mpi_main.cpp.
#pragma once

namespace pldamp::harness {

// Whether an MPI launcher started this process: launched_by_mpi (pldamp/harness/distribution.hpp).
// Only then is MPI initialised, so that without one the program behaves as a build without MPI.
// run_cli on every rank of MPI_COMM_WORLD, `pldamp run` sharing the cells (distribution.hpp);
// returns the exit code.
int run_under_mpi(int argc, char** argv);

} // namespace pldamp::harness
