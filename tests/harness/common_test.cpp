// What every harness stage shares: the observable table (each row reads the field its key names,
// in the solver result and in the closed forms at either contact end), the want words, the
// answers' JSON (escaped strings, exact numbers in their own precision), enumeration names, and
// files written whole or not at all.
#include "common/answer.hpp"
#include "common/files.hpp"
#include "common/input.hpp"
#include "common/names.hpp"
#include "common/observables.hpp"
#include "fixtures.hpp"

#include <fmt/format.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

TEST(ObservableTable, KeysInReportOrderEachReadingItsOwnField) {
  std::vector<std::string> keys;
  for (const Observable& observable : observable_table()) {
    keys.emplace_back(observable.key);
  }
  EXPECT_EQ(keys,
            (std::vector<std::string>{"e", "delta_max", "t_peak", "tau", "energy_load",
                                      "energy_unload", "normal_force_max", "t_normal_force_max"}));
  // A result and a closed-form bundle whose every field holds a different value.
  solvers::Result<long double> result;
  result.e = 1, result.delta_max = 2, result.t_peak = 3, result.tau = 4, result.energy_load = 5,
  result.energy_unload = 6, result.normal_force_max = 7, result.t_normal_force_max = 8;
  analytic::Observables<long double> closed;
  closed.e = 11, closed.delta_max = 12, closed.t_peak = 13, closed.tau = 14,
  closed.energy_load = 15, closed.energy_unload = 16, closed.normal_force_max = 17,
  closed.t_normal_force_max = 18, closed.e_cap = 21, closed.t_cut = 24;
  const std::map<std::string, std::pair<long double, long double>> field{
      {"e", {1, 11}},
      {"delta_max", {2, 12}},
      {"t_peak", {3, 13}},
      {"tau", {4, 14}},
      {"energy_load", {5, 15}},
      {"energy_unload", {6, 16}},
      {"normal_force_max", {7, 17}},
      {"t_normal_force_max", {8, 18}}};
  for (const Observable& observable : observable_table()) {
    const std::string key(observable.key);
    EXPECT_EQ(*observable.measured(result), field.at(key).first) << key;
    EXPECT_EQ(*observable.exact(closed, solvers::End::overlap), field.at(key).second) << key;
    EXPECT_NE(observable.solver_want & solvers::want_all, 0u) << key;
    EXPECT_EQ(find_observable(key), &observable);
  }
  // At the force end e and τ are the cut's (MATH.md §4); the energy split has no closed form.
  EXPECT_EQ(*find_observable("e")->exact(closed, solvers::End::force), 21);
  EXPECT_EQ(*find_observable("tau")->exact(closed, solvers::End::force), 24);
  EXPECT_EQ(*find_observable("delta_max")->exact(closed, solvers::End::force), 12);
  EXPECT_FALSE(find_observable("energy_unload")->exact(closed, solvers::End::force));
  EXPECT_EQ(find_observable("e")->key_at(solvers::End::force), "e_cap");
  EXPECT_EQ(find_observable("tau")->key_at(solvers::End::force), "t_cut");
  EXPECT_EQ(*find_observable("normal_force_max")->exact(closed, solvers::End::force), 17);
  // The spring's k δ_max^p is not compared (it follows from δ_max); the old name means nothing.
  EXPECT_EQ(find_observable("force_max"), nullptr);
  EXPECT_EQ(find_observable("spring_force_max"), nullptr);
}

TEST(ObservableTable, WantWordsSelectObservablesAndTheirClosedForms) {
  EXPECT_EQ(want_words(false), "e|delta_max|t_peak|tau|energy|normal_force");
  EXPECT_EQ(want_words(true), "e|delta_max|t_peak|tau|energy|normal_force|all");
  EXPECT_EQ(parse_want({"energy", "e"}, "want", false), solvers::want_energy | solvers::want_e);
  EXPECT_EQ(parse_want({"all"}, "--want", true), unsigned(solvers::want_all));
  EXPECT_EQ(parse_want({}, "want", false), 0u);
  try {
    parse_want({"all"}, "want", false);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown observable in want, expected "
                           "e|delta_max|t_peak|tau|energy|normal_force (got all)");
  }
  std::vector<std::string> energies;
  for (const Observable* observable : observables_of(solvers::want_energy)) {
    energies.emplace_back(observable->key);
  }
  EXPECT_EQ(energies, (std::vector<std::string>{"energy_load", "energy_unload"}));
  // Only what is wanted is asked of the closed forms: no quadrature for δ_max alone.
  EXPECT_EQ(analytic_want_of(solvers::want_delta_max, solvers::End::overlap),
            unsigned(analytic::want_delta_max));
  EXPECT_EQ(analytic_want_of(solvers::want_e | solvers::want_tau, solvers::End::force),
            unsigned(analytic::want_capped));
  EXPECT_EQ(analytic_want_of(solvers::want_e | solvers::want_tau, solvers::End::overlap),
            unsigned(analytic::want_e | analytic::want_tau));
}

TEST(Answer, StringsAreEscapedAndNumbersKeepTheirPrecision) {
  Answer answer;
  answer["name"] = "a \"quoted\"\nline\\";
  answer["third"] = exact_number(1.0 / 3);
  answer["tau"] = exact_number(std::numeric_limits<double>::infinity());
  answer["steps"] = 12;
  answer["samples"] = Answer::array({Answer::array({exact_number(0.5), exact_number(2.0)})});
  EXPECT_EQ(answer_json(answer), R"({"name": "a \"quoted\"\nline\\", "third": 0.3333333333333333, )"
                                 R"("tau": null, "steps": 12, "samples": [[0.5, 2]]})");
  EXPECT_EQ(answer_text(answer), "name            a \"quoted\"\nline\\\n"
                                 "third           0.3333333333333333\n"
                                 "tau             inf\n"
                                 "steps           12\n"
                                 "samples         [[0.5, 2]]\n");
  EXPECT_EQ(nlohmann::json::parse(answer_json(answer))["name"], "a \"quoted\"\nline\\");
  // 50 digits: every digit that round-trips (max_digits10), read back exactly.
  const std::string third_50 = answer_json(Answer{{"x", exact_number(bin50(1) / 3)}});
  ASSERT_EQ(third_50.rfind("{\"x\": 0." + std::string(50, '3'), 0), 0u) << third_50;
  const std::string digits = third_50.substr(6, third_50.size() - 7);
  EXPECT_EQ(bin50(digits), bin50(1) / 3) << digits;
  EXPECT_THROW(exact_number(std::numeric_limits<double>::quiet_NaN()), InternalError);
}

// A text shown in one line: control characters and bytes that are not UTF-8 escaped (a UTF-16
// file's cells printed raw bytes; a NUL cut an error line), well-formed UTF-8 kept as it is; cut
// to a limit, never inside a character.
TEST(Text, OneLineEscapesWhatIsNotPrintableUtf8) {
  using namespace std::string_literals;
  EXPECT_EQ(one_line("a\tb\nc\x7f"), "a\\tb\\nc\\x7f");
  EXPECT_EQ(one_line("t\0,\0d"s), "t\\x00,\\x00d");
  EXPECT_EQ(one_line("\xff\xfet\0"s), "\\xff\\xfet\\x00"); // UTF-16's byte order mark
  EXPECT_EQ(one_line("\u00e9\u20ac\U0001f600"), "\u00e9\u20ac\U0001f600");
  // What turns a line around or hides itself: bidirectional overrides, isolates, marks and C1.
  EXPECT_EQ(one_line("fake\u202ecode\u2066|\u200f|\u0085"),
            "fake\\u202ecode\\u2066|\\u200f|\\u0085");
  // Overlong, surrogate, beyond U+10FFFF, a lead byte cut short.
  EXPECT_EQ(one_line("\xc0\xaf|\xed\xa0\x80|\xf4\x90\x80\x80|\xe2\x82"),
            "\\xc0\\xaf|\\xed\\xa0\\x80|\\xf4\\x90\\x80\\x80|\\xe2\\x82");
  EXPECT_EQ(one_line("short", 10), "short");
  EXPECT_EQ(one_line("0123456789abc", 10), "0123456...");
  EXPECT_EQ(one_line("012345\u00e9\u00e9x", 10), "012345...");      // é is bytes 6-7: cut before
  EXPECT_EQ(one_line("01234\u00e9\u00e9xy", 10), "01234\u00e9..."); // a whole é fits
  EXPECT_EQ(one_line(std::string(1000000, '\n'), 10).size(), 10u);  // a long text read in part
}

TEST(Names, OneTableGivesNamesValuesAndTheList) {
  enum class Colour { red, green };
  constexpr NameTable<Colour, 2> colours{{{Colour::red, "red"}, {Colour::green, "green"}}};
  static_assert(name_of(colours, Colour::green) == "green");
  EXPECT_EQ(value_named(colours, "red"), Colour::red);
  EXPECT_FALSE(value_named(colours, "blue"));
  EXPECT_EQ(names_of(colours), "red|green");
}

namespace fs = std::filesystem;

std::string contents(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The folder's entries other than `keep`: a temporary left behind would show here.
std::vector<std::string> others(const fs::path& folder, const std::string& keep) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().filename() != keep) {
      names.push_back(entry.path().filename().string());
    }
  }
  return names;
}

TEST(Files, AFileIsReplacedWholeAndNoTemporaryStays) {
  const fs::path folder = testing::scratch() / "atomic";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const fs::path file = folder / "report.md";
  write_file_atomically(file, "old\n");
  write_file_atomically(file, "new, and longer\n");
  EXPECT_EQ(contents(file), "new, and longer\n");
  EXPECT_EQ(others(folder, "report.md"), std::vector<std::string>{});
  // A target that cannot be replaced (a directory): refused, the temporary removed.
  fs::create_directories(folder / "report.html");
  try {
    write_file_atomically(folder / "report.html", "x");
    ADD_FAILURE() << "a directory was replaced";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot write " + (folder / "report.html").string(), 0),
              0u)
        << e.what();
  }
  EXPECT_EQ(others(folder, "report.md"), std::vector<std::string>{"report.html"});
}

// A content made in pieces: small ones gathered past the writer's 1 MiB buffer, one larger than
// it written through; a producer that throws halfway leaves the old file whole and no temporary.
TEST(Files, AContentMadeInPiecesIsWrittenWholeOrNotAtAll) {
  const fs::path folder = testing::scratch() / "pieces";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const fs::path file = folder / "report.json";
  std::string expected;
  std::vector<std::string> seen_while_writing;
  const auto produce = [&](const TextSink& put) {
    seen_while_writing = others(folder, "report.json");
    expected.clear();
    for (int i = 0; i < 30000; ++i) { // 30000 × 53 bytes: 1.5 MiB
      const std::string piece = fmt::format("{:052d}\n", i);
      expected += piece;
      put(piece);
    }
    const std::string large(3 << 20, 'x');
    expected += large;
    put(large);
    put("end\n");
    expected += "end\n";
  };
  write_file_atomically(file, produce);
  EXPECT_EQ(contents(file), expected);
  // Unnamed while written (O_TMPFILE, which this filesystem has): a process killed then leaves no
  // temporary behind.
  EXPECT_EQ(seen_while_writing, std::vector<std::string>{});
  EXPECT_EQ(gather_text(produce), expected);
  EXPECT_THROW(write_file_atomically(file,
                                     [](const TextSink& put) {
                                       put(std::string(2 << 20, 'y'));
                                       throw std::runtime_error("the producer failed");
                                     }),
               std::runtime_error);
  EXPECT_EQ(contents(file), expected);
  EXPECT_EQ(others(folder, "report.json"), std::vector<std::string>{});
}

TEST(Files, AFolderThatCannotHoldAFileIsRefusedBeforeTheWork) {
  const fs::path file = testing::scratch() / "a-file";
  write_file_atomically(file, "x");
  EXPECT_THROW(require_writable_folder(file / "sub"), InputError);
  EXPECT_THROW(require_writable_folder("/proc/pldamp"), InputError);
  require_writable_folder(testing::scratch() / "fresh" / "folder"); // created
  EXPECT_TRUE(fs::is_directory(testing::scratch() / "fresh" / "folder"));
}

} // namespace
} // namespace pldamp::harness
