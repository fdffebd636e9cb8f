// _pldamp, the compiled half of the Python module `pldamp` (docs/python.md; python/pldamp holds the
// other half), a front end beside the command line (docs/design.md §2). Three doors in: the
// questions about one contact (ask/ask.hpp: calibrate, observables, solve, timestep), asked as
// the command line asks them, by the options' names, and answered in Python objects straight
// from the answer tree (its answers, precisions and refusals are the command line's, word for
// word, without its text); the command line itself, run in-process (run, merge, diff, check);
// and the closed forms in double over numpy arrays, evaluated element by element in C++ with the
// GIL released.
#include "common/parallel.hpp"
#include "questions.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/harness/cli.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

using pldamp::analytic::Contact;
using pldamp::analytic::ContactEnd;

// Text written to Python's sys.stderr as it comes, a line at a time (the GIL taken for each): a
// run's progress shown where a notebook or a script shows its own.
class PythonStderr : public std::streambuf {
protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) {
      line_ += traits_type::to_char_type(c);
      if (c == '\n' || c == '\r') {
        flush_line();
      }
    }
    return c;
  }
  int sync() override {
    flush_line();
    return 0;
  }

private:
  void flush_line() {
    if (line_.empty()) {
      return;
    }
    const py::gil_scoped_acquire locked;
    try {
      py::module_::import("sys").attr("stderr").attr("write")(line_);
      py::module_::import("sys").attr("stderr").attr("flush")();
    } catch (const py::error_already_set&) { // a closed stderr: the progress is lost, not the run
    }
    line_.clear();
  }
  std::string line_;
};

// `pldamp ARGS...` in-process: (exit code, standard output, standard error). `progress`: a run's
// progress lines on sys.stderr as it goes; none by default (the command's stderr is returned, not
// shown, and a notebook has no terminal to redraw a bar on).
py::tuple cli(const std::vector<std::string>& args, bool progress) {
  std::vector<const char*> argv{"pldamp"};
  for (const std::string& arg : args) {
    if (arg.find('\0') != std::string::npos) { // C would read it as cut at the NUL
      throw std::invalid_argument("an argument holds a NUL character");
    }
    argv.push_back(arg.c_str());
  }
  std::ostringstream out, err;
  PythonStderr to_python;
  std::ostream shown(progress ? &to_python : nullptr); // no buffer: discards
  int code = 0;
  {
    py::gil_scoped_release unlocked; // a scene's run may take minutes on its own threads
    code = pldamp::harness::run_cli(static_cast<int>(argv.size()), argv.data(), out, err, nullptr,
                                    &shown);
    shown.flush();
  }
  return py::make_tuple(code, out.str(), err.str());
}

// The observables a vectorised call computes, by name, and what each needs.
struct Column {
  const char* key;
  unsigned want;
  std::optional<double> pldamp::analytic::Observables<double>::*member;
};
const Column columns[] = {
    {"e", pldamp::analytic::want_e, &pldamp::analytic::Observables<double>::e},
    {"delta_max", pldamp::analytic::want_delta_max,
     &pldamp::analytic::Observables<double>::delta_max},
    {"t_peak", pldamp::analytic::want_t_peak, &pldamp::analytic::Observables<double>::t_peak},
    {"tau", pldamp::analytic::want_tau, &pldamp::analytic::Observables<double>::tau},
    {"tau0", pldamp::analytic::want_tau, &pldamp::analytic::Observables<double>::tau0},
    {"energy_load", pldamp::analytic::want_energy,
     &pldamp::analytic::Observables<double>::energy_load},
    {"energy_unload", pldamp::analytic::want_energy,
     &pldamp::analytic::Observables<double>::energy_unload},
    {"spring_force_max", pldamp::analytic::want_spring_force_max,
     &pldamp::analytic::Observables<double>::spring_force_max},
    {"normal_force_max", pldamp::analytic::want_normal_force,
     &pldamp::analytic::Observables<double>::normal_force_max},
    {"t_normal_force_max", pldamp::analytic::want_normal_force,
     &pldamp::analytic::Observables<double>::t_normal_force_max},
    {"dt_crit", pldamp::analytic::want_dt_crit, &pldamp::analytic::Observables<double>::dt_crit},
    {"dt_tangent", pldamp::analytic::want_dt_crit,
     &pldamp::analytic::Observables<double>::dt_tangent},
    {"e_cap", pldamp::analytic::want_capped, &pldamp::analytic::Observables<double>::e_cap},
    {"t_cut", pldamp::analytic::want_capped, &pldamp::analytic::Observables<double>::t_cut},
};

const Column& column(const std::string& key) {
  for (const Column& c : columns) {
    if (key == c.key) {
      return c;
    }
  }
  std::ostringstream message;
  message << "unknown observable in want, expected a list of ";
  for (std::size_t i = 0; i < std::size(columns); ++i) {
    message << (i == 0 ? "" : ",") << columns[i].key;
  }
  message << " (got " << key << ")";
  throw std::invalid_argument(message.str());
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// How a contact's damping is given, read once per call (not per element).
enum class DampingKind { e, alpha, alpha_eff };

DampingKind damping_kind_of(const std::string& kind) {
  if (kind == "e" || kind == "alpha" || kind == "alpha_eff") {
    return kind == "e"       ? DampingKind::e
           : kind == "alpha" ? DampingKind::alpha
                             : DampingKind::alpha_eff;
  }
  throw std::invalid_argument("the damping is e, alpha or alpha_eff (got " + kind + ')');
}

ContactEnd end_of(const std::string& end) {
  if (end != "overlap" && end != "force") {
    throw std::invalid_argument("unknown contact end, expected overlap|force (got " + end + ')');
  }
  return end == "force" ? ContactEnd::force : ContactEnd::overlap;
}

// The contact of one element, as the command line builds it from --e, --alpha or --alpha-eff.
Contact<double> contact_from(DampingKind kind, ContactEnd end, double p, double damping, double v0,
                             double m, double k) {
  switch (kind) {
  case DampingKind::e:
    return Contact<double>::from_e(p, damping, v0, m, k, end);
  case DampingKind::alpha:
    return Contact<double>::from_alpha(p, damping, v0, m, k);
  case DampingKind::alpha_eff:
    break;
  }
  return Contact<double>::from_alpha_eff(p, damping, v0, m, k);
}

// The closed forms over flat arrays of one length (python/pldamp broadcasts them): `damping_kind`
// is e, alpha or alpha_eff; `end` overlap or force (a target e met where the force ends). Returns
// alpha, alpha_eff and each wanted observable: inf for τ of a contact that never returns, NaN
// where an observable does not exist. A value outside the domain raises ValueError naming the
// element. On `jobs` threads (0: every core this process may use).
py::dict observables_double(const Array& p, const std::string& damping_kind, const Array& damping,
                            const Array& v0, const Array& m, const Array& k, const std::string& end,
                            const std::vector<std::string>& want, int jobs) {
  const auto n = static_cast<std::size_t>(p.size());
  for (const Array* a : {&damping, &v0, &m, &k}) {
    if (static_cast<std::size_t>(a->size()) != n) {
      throw std::invalid_argument("the arrays must have one length (broadcast them first)");
    }
  }
  const DampingKind kind = damping_kind_of(damping_kind);
  const ContactEnd contact_end = end_of(end);
  std::vector<const Column*> wanted;
  unsigned bits = 0;
  for (const std::string& key : want) {
    wanted.push_back(&column(key));
    bits |= wanted.back()->want;
  }
  std::vector<Array> out; // alpha, alpha_eff, then the wanted: each its own buffer
  std::vector<double*> into;
  for (std::size_t j = 0; j < wanted.size() + 2; ++j) {
    out.emplace_back(static_cast<py::ssize_t>(n));
    into.push_back(out.back().mutable_data());
  }
  const double *ps = p.data(), *ds = damping.data(), *vs = v0.data(), *ms = m.data(),
               *ks = k.data();
  // In chunks on `jobs` threads, each element in its own slot; a chunk stops at its first refused
  // element, and the first of those by index is the one reported, as a serial loop would.
  constexpr std::size_t chunk = 4096;
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::optional<std::pair<std::size_t, std::string>>> failures(chunks);
  {
    py::gil_scoped_release unlocked;
    pldamp::harness::for_each_index(
        chunks, jobs <= 0 ? pldamp::harness::all_cores() : jobs, [&](std::size_t c) {
          for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
            try {
              const Contact<double> contact =
                  contact_from(kind, contact_end, ps[i], ds[i], vs[i], ms[i], ks[i]);
              const pldamp::analytic::Observables<double> o =
                  pldamp::analytic::observables(contact, bits);
              into[0][i] = contact.alpha();
              into[1][i] = contact.alpha_eff();
              for (std::size_t j = 0; j < wanted.size(); ++j) {
                into[j + 2][i] =
                    (o.*(wanted[j]->member)).value_or(std::numeric_limits<double>::quiet_NaN());
              }
            } catch (const std::exception& e) {
              failures[c].emplace(i, e.what());
              return;
            }
          }
        });
  }
  for (const auto& failure : failures) {
    if (failure) {
      throw std::invalid_argument(failure->second + " at element " +
                                  std::to_string(failure->first));
    }
  }
  py::dict result;
  result["alpha"] = out[0];
  result["alpha_eff"] = out[1];
  for (std::size_t j = 0; j < wanted.size(); ++j) {
    result[wanted[j]->key] = out[j + 2];
  }
  return result;
}

// δ(t) and v(t) of one contact from the closed form (MATH.md §3 "Time-domain solution"), in
// double, at each of `t`: before the contact (t < 0) the free flight at v0; after its end, the free
// flight at the exit speed from where the contact ended. At the overlap end that is δ = 0 at τ and
// −e v0 (τ = ∞ when it never returns); at the force end (MATH.md §4) δ(t_cut) at t_cut, where the
// total force reaches 0 with δ still > 0, and −e_cap v0.
py::tuple trajectory_double(double p, const std::string& damping_kind, double damping, double v0,
                            double m, double k, const std::string& end, const Array& t) {
  const ContactEnd contact_end = end_of(end);
  const Contact<double> c =
      contact_from(damping_kind_of(damping_kind), contact_end, p, damping, v0, m, k);
  const auto n = static_cast<std::size_t>(t.size());
  Array delta(static_cast<py::ssize_t>(n)), v(static_cast<py::ssize_t>(n));
  double *ds = delta.mutable_data(), *vs = v.mutable_data();
  const double* ts = t.data();
  {
    py::gil_scoped_release unlocked;
    const pldamp::analytic::Trajectory<double> exact(c);
    double t_end = 0, delta_end = 0, v_end = 0; // where and how the bodies part
    if (contact_end == ContactEnd::force) {
      t_end = pldamp::analytic::cut_time(c);
      delta_end = exact.at_time(t_end).delta;
      v_end = -pldamp::analytic::capped_restitution(c) * v0;
    } else {
      t_end = pldamp::analytic::contact_duration(c); // ∞ for a contact that never returns
      v_end = -pldamp::analytic::restitution(c) * v0;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (ts[i] <= 0) { // free flight towards the contact
        vs[i] = v0;
        ds[i] = v0 * ts[i];
      } else if (ts[i] >= t_end && std::isfinite(t_end)) { // free flight away from it
        vs[i] = v_end;
        ds[i] = delta_end + v_end * (ts[i] - t_end);
      } else if (std::isinf(ts[i])) { // a contact that never returns, at rest at δ = 0 at last
        vs[i] = -0.0;
        ds[i] = 0;
      } else {
        const auto at = exact.at_time(ts[i]);
        ds[i] = at.delta;
        vs[i] = at.v;
      }
    }
  }
  return py::make_tuple(delta, v);
}

} // namespace

PYBIND11_MODULE(_pldamp, m) {
  m.doc() = "pldamp's compiled half: the command line in-process, and the closed forms over "
            "arrays (use the package `pldamp`)";
  m.def("cli", &cli, py::arg("args"), py::arg("progress") = false);
  m.def("ask", &pldamp::python::ask, py::arg("question"), py::arg("options"), py::arg("exact"));
  m.def("ask_keywords", &pldamp::python::ask_keywords, py::arg("question"), py::arg("options"),
        py::arg("flags"), py::arg("switches"), py::arg("cells"), py::arg("typed_one"),
        py::arg("refuse"), py::arg("exact"));
  m.def("ask_many", &pldamp::python::ask_many, py::arg("question"), py::arg("fixed"),
        py::arg("varying"), py::arg("exact"), py::arg("jobs"));
  m.def("observables_double", &observables_double, py::arg("p"), py::arg("damping_kind"),
        py::arg("damping"), py::arg("v0"), py::arg("m"), py::arg("k"), py::arg("end"),
        py::arg("want"), py::arg("jobs") = 0);
  m.def("trajectory_double", &trajectory_double, py::arg("p"), py::arg("damping_kind"),
        py::arg("damping"), py::arg("v0"), py::arg("m"), py::arg("k"), py::arg("end"),
        py::arg("t"));
}
