// The questions' options by name (ask/ask.hpp): settle() for every front end, set_option() for
// the ones without an argv. The command line reads the same options with CLI11 (cli/cli.cpp);
// python/tests/test_direct.py holds the two readings to one answer and one refusal.
#include "ask/contact.hpp"
#include "ask/materials.hpp"
#include "common/parallel.hpp"

#include <algorithm>
#include <array>
#include <ostream>

namespace pldamp::harness {
namespace {

// The option as the user gave it ("--m 2"), if given.
const std::string* given_option(const ContactArgs& args, std::string_view name) {
  for (const std::string& typed : args.given) {
    if (typed.size() > name.size() && typed.compare(0, name.size(), name) == 0 &&
        typed[name.size()] == ' ') {
      return &typed;
    }
  }
  return nullptr;
}

void settle_contact(ContactArgs& a) {
  // A value per body: two equal bodies may repeat one.
  a.radius = list_items("--radius", a.radius, false);
  a.young = list_items("--young", a.young, false);
  a.poisson = list_items("--poisson", a.poisson, false);
  a.density = list_items("--density", a.density, false);
  std::vector<std::string> mass_options_given;
  for (const char* option : {"--m", "--k"}) {
    if (const std::string* typed = given_option(a, option)) {
      mass_options_given.push_back(*typed);
    }
  }
  settle_materials(a, mass_options_given);
}

// The contact options each question takes (as cli/cli.cpp's add_contact_options gives them).
bool takes_contact_option(Question question, std::string_view name) {
  using namespace std::string_view_literals; // sized names: no strlen per comparison
  constexpr std::array every{"--p"sv,       "--e"sv,     "--end"sv, "--geometry"sv,
                             "--radius"sv,  "--young"sv, "--v0"sv,  "--poisson"sv,
                             "--density"sv, "--m"sv,     "--k"sv};
  if (std::find(every.begin(), every.end(), name) != every.end()) {
    return true;
  }
  const bool with_precision = question != Question::timestep && question != Question::check;
  switch (question) {
  case Question::calibrate:
    return name == "--precision" || name == "--code" || name == "--limit-damping" ||
           name == "--speeds" || name == "--reff";
  case Question::timestep:
    if (name == "--code") {
      return true;
    }
    [[fallthrough]];
  default:
    return name == "--alpha" || name == "--alpha-eff" ||
           (with_precision && (name == "--precision" || name == "--damping-exponent"));
  }
}

// Sets the field `name` names among `fields`, if it names one.
template <class Field, std::size_t N>
bool set_named(const std::pair<std::string_view, Field*> (&fields)[N], const std::string& name,
               const std::string& value) {
  for (const auto& [option, field] : fields) {
    if (name == option) {
      *field = value;
      return true;
    }
  }
  return false;
}

} // namespace

void settle(Question question, ContactArgs& args) {
  settle_contact(args);
  if (question == Question::calibrate) {
    args.speed_options_given.clear();
    for (const char* option : {"--geometry", "--v0", "--m", "--k", "--speeds", "--reff"}) {
      if (const std::string* typed = given_option(args, option)) {
        args.speed_options_given.push_back(*typed);
      }
    }
    args.speeds = list_items("--speeds", args.speeds, true);
  }
}

void settle(SolveArgs& args) {
  settle(Question::solve, args.contact);
  args.sample_times = list_items("--sample-times", args.sample_times, true);
}

void settle(TimestepArgs& args) {
  settle(Question::timestep, args.contact);
  // With materials Δt is in seconds and depends on the speed: no default of 1 m/s.
  if (args.contact.geometry && given_option(args.contact, "--v0") == nullptr) {
    throw InputError("--v0, the relative normal speed in m/s, is required with --geometry "
                     "(got nothing)");
  }
  if (args.contact.code && given_option(args.contact, "--end") != nullptr) {
    throw InputError("--code sets the contact end (a capped code's is force) (got --end " +
                     args.contact.end + ")");
  }
}

namespace {

void set_option(ContactArgs& a, Question question, const std::string& name,
                const std::string& value) {
  if (!takes_contact_option(question, name)) {
    throw InputError("unknown option " + name + " (got " + name + " " + value + ")");
  }
  a.given.push_back(name + " " + value);
  if (name == "--limit-damping") {
    a.limit_damping = true;
    return;
  }
  const std::pair<std::string_view, std::vector<std::string>*> lists[] = {{"--radius", &a.radius},
                                                                          {"--young", &a.young},
                                                                          {"--poisson", &a.poisson},
                                                                          {"--density", &a.density},
                                                                          {"--speeds", &a.speeds}};
  for (const auto& [list_name, list] : lists) {
    if (name == list_name) {
      list->push_back(value);
      return;
    }
  }
  const std::pair<std::string_view, std::string*> texts[] = {{"--p", &a.p},
                                                             {"--v0", &a.v0},
                                                             {"--m", &a.m},
                                                             {"--k", &a.k},
                                                             {"--precision", &a.precision},
                                                             {"--end", &a.end},
                                                             {"--reff", &a.reff}};
  const std::pair<std::string_view, std::optional<std::string>*> optional_texts[] = {
      {"--e", &a.e},
      {"--alpha", &a.alpha},
      {"--alpha-eff", &a.alpha_eff},
      {"--geometry", &a.geometry},
      {"--damping-exponent", &a.damping_exponent},
      {"--code", &a.code}};
  if (!set_named(texts, name, value) && !set_named(optional_texts, name, value)) {
    throw InternalError("takes_contact_option admits " + name + ", which sets nothing");
  }
}

void set_option(SolveArgs& a, const std::string& name, const std::string& value) {
  if (name == "--sample-times") {
    a.sample_times.push_back(value);
    return;
  }
  const std::pair<std::string_view, std::optional<std::string>*> optional_texts[] = {
      {"--rtol", &a.rtol},
      {"--atol", &a.atol},
      {"--dt", &a.dt},
      {"--horizon", &a.horizon},
      {"--tau-as", &a.tau_as},
      {"--steps-per-contact", &a.steps_per_contact},
      {"--onset-phase", &a.onset_phase}};
  const std::pair<std::string_view, std::string*> texts[] = {{"--solver", &a.solver},
                                                             {"--want", &a.want},
                                                             {"--max-steps", &a.max_steps},
                                                             {"--max-seconds", &a.max_seconds},
                                                             {"--repeats", &a.repeats}};
  if (!set_named(optional_texts, name, value) && !set_named(texts, name, value)) {
    set_option(a.contact, Question::solve, name, value);
  }
}

void set_option(TimestepArgs& a, const std::string& name, const std::string& value) {
  const std::pair<std::string_view, std::string*> texts[] = {{"--scheme", &a.scheme},
                                                             {"--tolerance", &a.tolerance},
                                                             {"--observables", &a.observables},
                                                             {"--tau-as", &a.tau_as}};
  if (!set_named(texts, name, value)) {
    set_option(a.contact, Question::timestep, name, value);
  }
}

// What CLI11 requires of the command line, in its words and its order (the contact's options are
// defined before the question's).
void require_given(bool given, const char* option) {
  if (!given) {
    throw InputError(std::string(option) + " is required (got nothing)");
  }
}

bool typed(const TypedOptions& options, std::string_view name) {
  return std::any_of(options.begin(), options.end(),
                     [&](const auto& option) { return option.first == name; });
}

template <class Args>
Args read_options(Question question, const TypedOptions& options) {
  Args args;
  for (const auto& [name, value] : options) {
    if constexpr (std::is_same_v<Args, ContactArgs>) {
      set_option(args, question, name, value);
    } else {
      set_option(args, name, value);
    }
  }
  return args;
}

} // namespace

Question question_named(std::string_view name) {
  constexpr std::pair<std::string_view, Question> questions[] = {
      {"calibrate", Question::calibrate},
      {"observables", Question::observables},
      {"solve", Question::solve},
      {"timestep", Question::timestep}};
  for (const auto& [question_name, question] : questions) {
    if (name == question_name) {
      return question;
    }
  }
  throw InputError("unknown question, expected calibrate|observables|solve|timestep (got " +
                   std::string(name) + ")");
}

namespace {

SolveArgs solve_args(const TypedOptions& options) {
  SolveArgs args = read_options<SolveArgs>(Question::solve, options);
  require_given(typed(options, "--v0"), "--v0");
  require_given(typed(options, "--solver"), "--solver");
  settle(args);
  return args;
}

} // namespace

void ask_cells(Question question, std::span<const TypedOptions> cells, int jobs,
               std::vector<Answer>& answers, std::vector<std::exception_ptr>& failures) {
  if (question != Question::solve) {
    answers.assign(cells.size(), Answer());
    failures.assign(cells.size(), nullptr);
    for_each_index(cells.size(), jobs, [&](std::size_t i) {
      try {
        answers[i] = ask(question, cells[i]);
      } catch (...) {
        failures[i] = std::current_exception();
      }
    });
    return;
  }
  // A chunk of cells per thread, read, prepared, solved and answered there (memory made on one
  // thread and freed on another cost more than the solves of short contacts); a batched solver's
  // lanes within the chunk.
  answers.assign(cells.size(), Answer());
  failures.assign(cells.size(), nullptr);
  constexpr std::size_t chunk = 256;
  for_each_index((cells.size() + chunk - 1) / chunk, jobs, [&](std::size_t c) {
    const std::size_t first = c * chunk, count = std::min(chunk, cells.size() - first);
    std::vector<SolveArgs> read;
    std::vector<std::size_t> index;
    for (std::size_t i = first; i < first + count; ++i) {
      try {
        read.push_back(solve_args(cells[i]));
        index.push_back(i);
      } catch (...) {
        failures[i] = std::current_exception();
      }
    }
    std::vector<Answer> solved;
    std::vector<std::exception_ptr> refused;
    solve_answers(read, solved, refused);
    for (std::size_t j = 0; j < index.size(); ++j) {
      answers[index[j]] = std::move(solved[j]);
      failures[index[j]] = refused[j];
    }
  });
}

Answer ask(Question question, const TypedOptions& options) {
  switch (question) {
  case Question::calibrate: {
    ContactArgs args = read_options<ContactArgs>(question, options);
    settle(question, args);
    return calibrate_answer(args);
  }
  case Question::observables: {
    ContactArgs args = read_options<ContactArgs>(question, options);
    require_given(typed(options, "--v0"), "--v0");
    settle(question, args);
    return observables_answer(args);
  }
  case Question::solve:
    return solve_answer(solve_args(options));
  case Question::timestep: {
    TimestepArgs args = read_options<TimestepArgs>(question, options);
    require_given(typed(options, "--scheme"), "--scheme");
    settle(args);
    return timestep_answer(args);
  }
  case Question::check:
    break;
  }
  throw InputError("check reads a file: ask it through the command line (got check)");
}

void emit(Answer answer, bool json, std::ostream& out) {
  answer = with_units(std::move(answer));
  out << (json ? answer_json(answer) + "\n" : answer_text(answer));
}

} // namespace pldamp::harness
