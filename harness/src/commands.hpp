// The analytic subcommands (calibrate, observables, showcase), behind a precision dispatch.
#pragma once

#include <optional>
#include <ostream>
#include <string>

namespace pldamp::harness {

// Options as typed by the user; numbers are parsed later, in the precision asked for.
struct ContactArgs {
  std::string p;
  std::optional<std::string> e, alpha, alpha_eff;
  std::string v0 = "1", m = "1", k = "1";
  std::string precision = "double";
  std::string end = "overlap";
  bool json = false;
};

void run_calibrate(const ContactArgs& args, std::ostream& out);
void run_observables(const ContactArgs& args, std::ostream& out);
void run_showcase(const std::string& precision, std::ostream& out);

} // namespace pldamp::harness
