#include "questions.hpp"

#include "common/input.hpp"
#include "common/parallel.hpp"

#include <pybind11/stl.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>

namespace pldamp::python {
namespace {

using harness::Answer;

// decimal.Decimal, held to the end of the process as the module is.
const py::object& decimal_type() {
  static const auto* const decimal = new py::object(py::module_::import("decimal").attr("Decimal"));
  return *decimal;
}

// Digits without a point or an exponent, as json.loads reads them: an int.
bool integral(std::string_view digits) {
  return digits.find_first_of(".eE") == std::string_view::npos;
}

// A double's shortest round-trip digits ("0.5", "1e-05", "inf"): as the command line prints it.
std::string shortest(double value) {
  std::array<char, 32> buffer{};
  return std::string(buffer.data(),
                     std::to_chars(buffer.data(), buffer.data() + buffer.size(), value).ptr);
}

// An answer's key as a Python str, made and hashed once per process: the keys are a few dozen
// words, and a str made for each key of each answer was a third of what a call adds to its C++.
PyObject* key_of(const std::string& key) {
  static auto* const made = new std::unordered_map<std::string, PyObject*>();
  const auto [found, added] = made->try_emplace(key, nullptr);
  if (added) {
    found->second = PyUnicode_InternFromString(key.c_str()); // held to the end of the process
  }
  return found->second;
}

py::object python_value(const Answer& value, bool exact) {
  if (value.is_number_float()) { // a double (common/answer.hpp): read as its digits would be
    const double number = value.get<double>();
    if (std::isinf(number)) {
      return py::none();
    }
    // A whole number's shortest digits may have no point ("1", but "1e+16"); any other's have one.
    if (std::trunc(number) == number && integral(shortest(number))) {
      return py::reinterpret_steal<py::object>(
          PyLong_FromString(shortest(number).c_str(), nullptr, 10));
    }
    return py::float_(number);
  }
  if (const std::optional<std::string> digits = harness::exact_digits(value)) {
    if (*digits == "inf" || *digits == "-inf") {
      return py::none();
    }
    if (integral(*digits)) {
      return py::reinterpret_steal<py::object>(PyLong_FromString(digits->c_str(), nullptr, 10));
    }
    return exact ? decimal_type()(*digits) : py::float_(std::stod(*digits));
  }
  switch (value.type()) {
  case Answer::value_t::object: {
    py::dict items;
    for (const auto& [key, item] : value.items()) {
      PyObject* name = key_of(key);
      if (name == nullptr ||
          PyDict_SetItem(items.ptr(), name, python_value(item, exact).ptr()) != 0) {
        throw py::error_already_set();
      }
    }
    return items;
  }
  case Answer::value_t::array: {
    py::list items;
    for (const Answer& item : value) {
      items.append(python_value(item, exact));
    }
    return items;
  }
  case Answer::value_t::string:
    return py::str(value.get_ref<const std::string&>());
  case Answer::value_t::boolean:
    return py::bool_(value.get<bool>());
  case Answer::value_t::number_integer:
    return py::int_(value.get<std::int64_t>());
  case Answer::value_t::number_unsigned:
    return py::int_(value.get<std::uint64_t>());
  default:
    return py::none();
  }
}

// What went wrong answering, as the Python exception to raise once the GIL is held again.
struct Failure {
  bool internal = false;
  std::string message;
};

template <class Body>
std::optional<Failure> failure_of(Body&& body) {
  try {
    body();
  } catch (const harness::InternalError& e) {
    return Failure{true, harness::one_line(e.what())};
  } catch (const std::invalid_argument& e) { // InputError and the library's validation
    return Failure{false, harness::one_line(e.what())};
  } catch (const std::exception& e) {
    return Failure{true, harness::one_line(e.what())};
  }
  return std::nullopt;
}

[[noreturn]] void raise(const Failure& failure) {
  if (failure.internal) {
    throw std::runtime_error("internal: " + failure.message);
  }
  throw py::value_error(failure.message);
}

// One key's values over the cells, as the array it becomes.
struct Column {
  enum class Kind { number, integer, other } kind = Kind::number;
  std::vector<double> numbers;             // Kind::number (NaN: no value)
  std::vector<std::int64_t> integers;      // Kind::integer
  std::vector<std::optional<Answer>> rest; // Kind::other: text, exact digits, lists
  std::vector<bool> present;

  void add(std::size_t cell, const Answer& value) {
    if (present.size() < cell) { // cells before without this key
      present.resize(cell, false);
      numbers.resize(cell, std::numeric_limits<double>::quiet_NaN());
      integers.resize(cell, 0);
      rest.resize(cell);
    }
    if (present.empty()) {
      kind = value.is_number_float()     ? Kind::number
             : value.is_number_integer() ? Kind::integer
                                         : Kind::other;
    }
    present.push_back(true);
    numbers.push_back(value.is_number() ? value.get<double>()
                                        : std::numeric_limits<double>::quiet_NaN());
    integers.push_back(value.is_number_integer() ? value.get<std::int64_t>() : 0);
    rest.push_back(kind == Kind::other ? std::optional<Answer>(value) : std::nullopt);
    if ((kind == Kind::number && !value.is_number_float()) ||
        (kind == Kind::integer && !value.is_number_integer())) {
      kind = Kind::other; // a key of two kinds (never seen): kept as the answers have it
      for (std::size_t i = 0; i + 1 < rest.size(); ++i) {
        rest[i] = present[i] ? std::optional<Answer>(numbers[i]) : std::nullopt;
      }
      rest.back() = value;
    }
  }

  py::object array(std::size_t cells, bool exact) {
    present.resize(cells, false);
    numbers.resize(cells, std::numeric_limits<double>::quiet_NaN());
    integers.resize(cells, 0);
    rest.resize(cells);
    const bool everywhere = std::find(present.begin(), present.end(), false) == present.end();
    if (kind == Kind::number || (kind == Kind::integer && !everywhere)) {
      py::array_t<double> out(static_cast<py::ssize_t>(cells));
      std::copy(numbers.begin(), numbers.end(), out.mutable_data());
      return out;
    }
    if (kind == Kind::integer) {
      py::array_t<std::int64_t> out(static_cast<py::ssize_t>(cells));
      std::copy(integers.begin(), integers.end(), out.mutable_data());
      return out;
    }
    // A value every cell shares (the precision, the solver, the outcome of every cell, the list
    // of observables judged) is one value.
    if (everywhere &&
        std::all_of(rest.begin(), rest.end(), [&](const auto& v) { return *v == *rest.front(); })) {
      return python_value(*rest.front(), exact);
    }
    py::array out(py::dtype("O"), std::vector<py::ssize_t>{static_cast<py::ssize_t>(cells)});
    auto* slots = static_cast<PyObject**>(out.mutable_data());
    for (std::size_t i = 0; i < cells; ++i) {
      py::object value = rest[i] ? python_value(*rest[i], exact) : py::none();
      Py_XDECREF(slots[i]);
      slots[i] = value.release().ptr();
    }
    return out;
  }
};

} // namespace

py::dict ask(const std::string& question, const harness::TypedOptions& options, bool exact) {
  Answer answer;
  std::optional<Failure> failed;
  {
    py::gil_scoped_release unlocked; // a timestep search or a slow solve runs for seconds
    failed = failure_of([&] { answer = harness::ask(harness::question_named(question), options); });
  }
  if (failed) {
    raise(*failed);
  }
  return python_value(answer, exact);
}

py::object ask_keywords(const std::string& question, const py::dict& options, const py::dict& flags,
                        const py::frozenset& switches, const py::frozenset& cells,
                        const py::object& typed_one, const py::object& refuse, bool exact) {
  harness::TypedOptions typed;
  for (const auto& [name, value] : options) {
    PyObject* const flag = PyDict_GetItemWithError(flags.ptr(), name.ptr());
    if (flag == nullptr) {
      if (PyErr_Occurred() != nullptr) {
        throw py::error_already_set();
      }
      refuse(name);
      throw std::logic_error("refuse() returned for an unknown keyword");
    }
    if (value.is_none()) {
      continue;
    }
    if (cells.contains(name) && (PyList_Check(value.ptr()) || PyTuple_Check(value.ptr()) ||
                                 py::isinstance<py::array>(value))) {
      return py::none();
    }
    std::optional<std::string> text;
    if (!switches.contains(name)) {
      if (PyFloat_CheckExact(value.ptr())) {
        text = py::repr(value).cast<std::string>();
      } else if (PyLong_CheckExact(value.ptr())) {
        text = py::str(value).cast<std::string>();
      } else if (PyUnicode_CheckExact(value.ptr())) {
        Py_ssize_t size = 0;
        const char* bytes = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
        if (bytes == nullptr) {
          PyErr_Clear(); // not UTF-8-encodable: typed_one says so
        } else if (std::memchr(bytes, '\0', static_cast<std::size_t>(size)) == nullptr) {
          text.emplace(bytes, static_cast<std::size_t>(size));
        }
      }
    }
    if (!text) {
      const py::object made = typed_one(name, value);
      if (made.is_none()) {
        continue;
      }
      text = made.cast<std::string>();
    }
    typed.emplace_back(py::reinterpret_borrow<py::str>(flag).cast<std::string>(), std::move(*text));
  }
  return ask(question, typed, exact);
}

py::dict ask_many(const std::string& question, const harness::TypedOptions& fixed,
                  const std::vector<std::pair<std::string, Doubles>>& varying, bool exact,
                  int jobs) {
  const std::size_t cells =
      varying.empty() ? 0 : static_cast<std::size_t>(varying[0].second.size());
  std::vector<const double*> values;
  for (const auto& [flag, array] : varying) {
    if (static_cast<std::size_t>(array.size()) != cells) {
      throw std::invalid_argument("the arrays must have one length (broadcast them first)");
    }
    values.push_back(array.data());
  }
  if (cells == 0) {
    throw std::invalid_argument("the arrays hold no cell (got arrays of size 0)");
  }
  if (jobs <= 0) {
    jobs = harness::all_cores();
  }
  const harness::Question asked = harness::question_named(question);
  std::vector<std::pair<std::string, Column>> columns;
  std::map<std::string, std::size_t, std::less<>> column_of;
  std::optional<std::pair<std::size_t, Failure>> refused;
  {
    py::gil_scoped_release unlocked;
    // In blocks, so that the answers held at once stay few (10^6 cells of 30 keys would not fit).
    constexpr std::size_t block = 4096;
    std::vector<harness::TypedOptions> options;
    std::vector<Answer> answers;
    std::vector<std::exception_ptr> failures;
    for (std::size_t first = 0; first < cells && !refused; first += block) {
      const std::size_t count = std::min(block, cells - first);
      options.assign(count, fixed);
      for (std::size_t i = 0; i < count; ++i) {
        for (std::size_t j = 0; j < varying.size(); ++j) {
          options[i].emplace_back(varying[j].first, shortest(values[j][first + i]));
        }
      }
      harness::ask_cells(asked, options, jobs, answers, failures);
      for (std::size_t i = 0; i < count; ++i) {
        if (failures[i]) {
          refused.emplace(first + i, *failure_of([&] { std::rethrow_exception(failures[i]); }));
          break;
        }
        // The cells' answers have their keys in one order, mostly: the column at the key's
        // place is tried first (a map lookup per key per cell was a third of the time).
        std::size_t place = 0;
        for (const auto& [key, value] : answers[i].items()) {
          std::size_t column = place;
          if (column >= columns.size() || columns[column].first != key) {
            auto found = column_of.find(key);
            if (found == column_of.end()) {
              found = column_of.emplace(key, columns.size()).first;
              columns.emplace_back(key, Column());
            }
            column = found->second;
          }
          columns[column].second.add(first + i, value);
          place = column + 1;
        }
      }
    }
  }
  if (refused) {
    raise({refused->second.internal,
           refused->second.message + " at element " + std::to_string(refused->first)});
  }
  py::dict out;
  for (auto& [key, column] : columns) {
    out[py::str(key)] = column.array(cells, exact);
  }
  return out;
}

} // namespace pldamp::python
