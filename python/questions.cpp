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

// repr(value) of a finite double, as Python writes it (its shortest round-trip digits; fixed
// notation for decimal exponents −4 to 15, with ".0" when whole; otherwise d.ddde±XX), without a
// Python string made and read back: the keywords' floats are a tenth of what a call adds to its
// C++.
std::string python_repr(double value) {
  std::array<char, 32> buffer{};
  const char* const end = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                        std::chars_format::scientific)
                              .ptr;
  const std::string_view written(buffer.data(), static_cast<std::size_t>(end - buffer.data()));
  const std::size_t e = written.find('e');
  int exponent = 0;
  std::from_chars(written.data() + e + (written[e + 1] == '+' ? 2 : 1), end, exponent);
  if (exponent < -4 || exponent >= 16) {
    return std::string(written); // d.ddde±XX already
  }
  std::string digits, out;
  for (const char c : written.substr(0, e)) {
    if (c >= '0' && c <= '9') {
      digits += c;
    } else if (c == '-') {
      out += '-';
    }
  }
  if (exponent < 0) {
    return out + "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
  }
  const std::size_t whole = static_cast<std::size_t>(exponent) + 1;
  if (digits.size() <= whole) {
    return out + digits + std::string(whole - digits.size(), '0') + ".0";
  }
  return out + digits.substr(0, whole) + "." + digits.substr(whole);
}

// A cell's value as its option reads it: a whole number as an integer ("100000", which an integer
// option takes: "1e+05" was refused), else its shortest round-trip digits in double, or every
// digit of its binary value for a wider precision (a double is exactly representable there, and
// "0.3" would be float128's 0.3, not the double the caller gave).
std::string cell_text(double value, bool exact) {
  if (std::trunc(value) == value && std::fabs(value) < 9.0e18) {
    return std::to_string(static_cast<long long>(value));
  }
  if (!exact || !std::isfinite(value)) {
    return to_string_full(value); // shortest round-trip digits, as the command line prints it
  }
  std::array<char, 800> buffer{}; // a double's exact expansion: at most 767 significant digits
  char* end = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                            std::chars_format::scientific, 767)
                  .ptr;
  std::string digits(buffer.data(), end);
  const std::size_t exponent = digits.find('e');
  std::size_t last = digits.find_last_not_of('0', exponent - 1);
  if (digits[last] == '.') { // "5.000e-01" is "5e-01", not "5.e-01"
    --last;
  }
  digits.erase(last + 1, exponent - last - 1); // the trailing zeros of the mantissa
  return digits;
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
    // A whole number's shortest digits may have no point ("1", but "1e+06"); any other's have one.
    // Below 10^5 they never have (as many digits as "1e+05" has characters, and to_chars writes
    // the fixed form on a tie), so those skip the digits.
    if (std::trunc(number) == number && std::fabs(number) < 1e5) {
      return py::reinterpret_steal<py::object>(PyLong_FromDouble(number));
    }
    if (std::trunc(number) == number) {
      if (const std::string digits = to_string_full(number); integral(digits)) {
        return py::reinterpret_steal<py::object>(PyLong_FromString(digits.c_str(), nullptr, 10));
      }
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

// One key's values over the cells, as the array it becomes. A JSON null that is not an infinity
// (an e_to_enter out of reach) is a cell without a value; a double's infinity stays one.
class Column {
public:
  void add(std::size_t cell, const Answer& value) {
    if (value.is_null()) {
      return;
    }
    if (kind_ == Kind::none) {
      kind_ = value.is_number_float()     ? Kind::number
              : value.is_number_integer() ? Kind::integer
                                          : Kind::other;
    } else if ((kind_ == Kind::number && !value.is_number_float()) ||
               (kind_ == Kind::integer && !value.is_number_integer())) {
      to_other(); // a key of two kinds (none seen): kept as the answers have them
    }
    grow(cell);
    present_[cell] = true;
    if (kind_ == Kind::number) {
      numbers_[cell] = value.get<double>();
    } else if (kind_ == Kind::integer) {
      integers_[cell] = value.get<std::int64_t>();
    } else {
      values_[cell] = distinct(value);
    }
  }

  py::object array(std::size_t cells, bool exact) {
    grow(cells - 1);
    const bool everywhere = std::find(present_.begin(), present_.begin() + std::ptrdiff_t(cells),
                                      false) == present_.begin() + std::ptrdiff_t(cells);
    if (kind_ == Kind::none || kind_ == Kind::number || (kind_ == Kind::integer && !everywhere)) {
      py::array_t<double> out(static_cast<py::ssize_t>(cells));
      double* into = out.mutable_data();
      for (std::size_t i = 0; i < cells; ++i) {
        into[i] = !present_[i]             ? std::numeric_limits<double>::quiet_NaN()
                  : kind_ == Kind::integer ? static_cast<double>(integers_[i])
                                           : numbers_[i];
      }
      return out;
    }
    if (kind_ == Kind::integer) {
      py::array_t<std::int64_t> out(static_cast<py::ssize_t>(cells));
      std::copy(integers_.begin(), integers_.begin() + std::ptrdiff_t(cells), out.mutable_data());
      return out;
    }
    // A text or list every cell shares (the precision, the outcome of every cell, the observables
    // judged) is one value; a number stays an array, wide or not.
    if (everywhere && distinct_.size() == 1 && !harness::exact_digits(distinct_.front())) {
      return python_value(distinct_.front(), exact);
    }
    if (const std::optional<std::size_t> width = number_pairs(cells)) { // timestep's range
      py::array_t<double> out({static_cast<py::ssize_t>(cells), static_cast<py::ssize_t>(*width)});
      double* into = out.mutable_data();
      for (std::size_t i = 0; i < cells; ++i) {
        for (std::size_t j = 0; j < *width; ++j) {
          into[i * *width + j] = present_[i] ? distinct_[values_[i]][j].get<double>()
                                             : std::numeric_limits<double>::quiet_NaN();
        }
      }
      return out;
    }
    std::vector<py::object> shown; // each distinct value made once
    for (const Answer& value : distinct_) {
      const std::optional<std::string> digits = harness::exact_digits(value);
      shown.push_back(digits && (*digits == "inf" || *digits == "-inf")
                          ? decimal_type()(*digits == "inf" ? "Infinity" : "-Infinity")
                          : python_value(value, exact));
    }
    py::array out(py::dtype("O"), std::vector<py::ssize_t>{static_cast<py::ssize_t>(cells)});
    auto* slots = static_cast<PyObject**>(out.mutable_data());
    for (std::size_t i = 0; i < cells; ++i) {
      py::object value = present_[i] ? shown[values_[i]] : py::none();
      Py_XDECREF(slots[i]);
      slots[i] = value.release().ptr();
    }
    return out;
  }

private:
  enum class Kind { none, number, integer, other };

  void grow(std::size_t cell) {
    if (present_.size() <= cell) {
      present_.resize(cell + 1, false);
      if (kind_ == Kind::number) {
        numbers_.resize(cell + 1, 0.0);
      } else if (kind_ == Kind::integer) {
        integers_.resize(cell + 1, 0);
      } else if (kind_ == Kind::other) {
        values_.resize(cell + 1, 0);
      }
    }
  }

  void to_other() {
    values_.assign(present_.size(), 0);
    for (std::size_t i = 0; i < present_.size(); ++i) {
      if (present_[i]) {
        values_[i] =
            kind_ == Kind::number ? distinct(Answer(numbers_[i])) : distinct(Answer(integers_[i]));
      }
    }
    numbers_.clear();
    integers_.clear();
    kind_ = Kind::other;
  }

  // The index of `value` among the distinct values held: a column of texts holds a few (the
  // memory of 10^6 cells was 1.3 KB a cell with a copy each).
  std::uint32_t distinct(const Answer& value) {
    for (std::size_t i = distinct_.size(); i-- > 0 && distinct_.size() - i <= 16;) {
      if (distinct_[i] == value) {
        return static_cast<std::uint32_t>(i);
      }
    }
    distinct_.push_back(value);
    return static_cast<std::uint32_t>(distinct_.size() - 1);
  }

  // The width when every cell's value is a list of that many doubles.
  std::optional<std::size_t> number_pairs(std::size_t cells) const {
    std::optional<std::size_t> width;
    for (std::size_t i = 0; i < cells; ++i) {
      if (!present_[i]) {
        continue;
      }
      const Answer& value = distinct_[values_[i]];
      if (!value.is_array() || value.empty() ||
          !std::all_of(value.begin(), value.end(),
                       [](const Answer& v) { return v.is_number_float(); }) ||
          (width && *width != value.size())) {
        return std::nullopt;
      }
      width = value.size();
    }
    return width;
  }

  Kind kind_ = Kind::none;
  std::vector<bool> present_;
  std::vector<double> numbers_;
  std::vector<std::int64_t> integers_;
  std::vector<std::uint32_t> values_; // indexes into distinct_
  std::vector<Answer> distinct_;
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
      refuse(question, name); // raises TypeError
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
      if (PyFloat_CheckExact(value.ptr()) && !exact) { // wider: its exact digits, by typed_one
        const double number = PyFloat_AS_DOUBLE(value.ptr());
        text = std::isfinite(number) ? python_repr(number) : py::repr(value).cast<std::string>();
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
      const py::object made = typed_one(name, value, exact);
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
          options[i].emplace_back(varying[j].first, cell_text(values[j][first + i], exact));
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
