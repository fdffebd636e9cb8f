#include "pldamp/harness/cli.hpp"

#include <iostream>

int main(int argc, char** argv) {
  return pldamp::harness::run_cli(argc, argv, std::cout, std::cerr);
}
