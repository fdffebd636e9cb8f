// The questions about one contact (harness/src/ask/ask.hpp) asked from Python: one cell, or many
// cells on the library's threads, the answers handed over as Python objects and numpy arrays.
#pragma once

#include "ask/ask.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <utility>
#include <vector>

namespace pldamp::python {

namespace py = pybind11;

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// `pldamp QUESTION OPTIONS... --json` without the text: the options by their command-line names
// ("--alpha-eff") and values as typed, the answer as a dict read as json.loads reads the
// command's line (floats as float, or decimal.Decimal when `exact`). Bad input is ValueError with
// the command's one line; what the command calls internal, RuntimeError.
py::dict ask(const std::string& question, const harness::TypedOptions& options, bool exact);

// ask() from the keywords of a Python call, read here for speed (a loop in Python was a fifth
// of a call): `flags` maps each keyword the question takes to its flag; in double a float goes in
// as its repr (the very double), an int and a str (without NUL, UTF-8-encodable) as written, None
// not at all; every other value (a float in a wider precision: its exact digits), and every
// keyword in `switches`, as `typed_one(name, value, exact)` makes it
// (pldamp._typed_one: a str, or None to leave it out), so that one definition decides those. An
// unknown keyword calls `refuse(question, name)`, which raises. Returns None, asking nothing, when
// a keyword of `cells` holds a list, tuple or array: the caller asks at every cell.
py::object ask_keywords(const std::string& question, const py::dict& options, const py::dict& flags,
                        const py::frozenset& switches, const py::frozenset& cells,
                        const py::object& typed_one, const py::object& refuse, bool exact);

// The question at each of n cells: `fixed` options for all, and per cell the value of each
// `varying` option (its flag and a float64 array of n). Each cell is answered as ask() answers it
// (a double goes in as digits that read back as the very double in the precision asked), on
// `jobs` threads (0: every core this process may use) with the GIL released. Returns {key: array of
// n} in the answers' key order: float64 (NaN where a cell has no such value: τ of a contact that
// never returns is inf there and null in JSON), int64, or object (text, exact digits as
// decimal.Decimal); a text every cell shares is one str. A refused cell is ValueError naming its
// index.
py::dict ask_many(const std::string& question, const harness::TypedOptions& fixed,
                  const std::vector<std::pair<std::string, Doubles>>& varying, bool exact,
                  int jobs);

} // namespace pldamp::python
