// The cheapest adapter the external-solver protocol allows (docs/external.md "Your code in the
// loop"): it answers the handshake, then every problem at once with a fixed result. harness_bench
// runs a plan through it to measure what the protocol itself costs per record.
#include <cstdio>
#include <iostream>
#include <string>

int main() {
  std::string line;
  if (!std::getline(std::cin, line)) {
    return 1;
  }
  std::cout << R"({"protocol":"pldamp-solver","version":1,"solver":"answers at once"})" << '\n'
            << std::flush;
  while (std::getline(std::cin, line)) {
    // The id is the first key pldamp writes: {"id":N,...
    const std::size_t start = line.find(':') + 1, end = line.find(',');
    std::cout << R"({"id":)" << line.substr(start, end - start)
              << R"(,"outcome":"exited","e":0.5,"delta_max":1,"t_peak":1.5,"tau":3,"steps":1})"
              << '\n'
              << std::flush;
  }
  return 0;
}
