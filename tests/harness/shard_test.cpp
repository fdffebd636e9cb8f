// A run in shards (`pldamp run SCENE --shard K/N`, `pldamp merge`): records read back bit for bit,
// the merged report the serial one but for times, and every shard set that is not one run's
// refused with one line.
#include "fixtures.hpp"

#include "common/files.hpp"
#include "pldamp/harness/distribution.hpp"
#include "report/report.hpp"
#include "run/record_check.hpp"
#include "run/record_store.hpp"
#include "run/shard.hpp"
#include "truth/point_bytes.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <barrier>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <thread>

namespace pldamp::harness {
namespace {

using namespace testing;

// Bit for bit: −0 is not +0, and a NaN keeps its payload.
bool same_bits(const std::optional<double>& a, const std::optional<double>& b) {
  return a.has_value() == b.has_value() &&
         (!a || std::bit_cast<std::uint64_t>(*a) == std::bit_cast<std::uint64_t>(*b));
}
bool same_bits(const std::vector<std::optional<double>>& a,
               const std::vector<std::optional<double>>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                            [](auto& x, auto& y) { return same_bits(x, y); });
}

void expect_identical(const Record& a, const Record& b) {
  static_assert(sizeof(Record) == 448, "a Record field was added: compare it here");
  EXPECT_EQ(a.cell, b.cell);
  EXPECT_EQ(a.config, b.config);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.failure, b.failure);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.rhs_evals, b.rhs_evals);
  EXPECT_TRUE(same_bits(a.wall_seconds, b.wall_seconds));
  EXPECT_TRUE(same_bits(a.wall_seconds_slowest, b.wall_seconds_slowest));
  EXPECT_TRUE(same_bits(a.cpu_seconds, b.cpu_seconds));
  EXPECT_TRUE(same_bits(a.cpu_seconds_slowest, b.cpu_seconds_slowest));
  EXPECT_TRUE(same_bits(a.alpha, b.alpha));
  EXPECT_EQ(a.alpha_digits, b.alpha_digits);
  EXPECT_EQ(a.phases, b.phases);
  EXPECT_EQ(a.runs, b.runs);
  EXPECT_TRUE(same_bits(a.dt, b.dt));
  for (const auto member :
       {&Record::value, &Record::reference, &Record::error, &Record::abs_error, &Record::rel_error,
        &Record::spread, &Record::worst_phase, &Record::replica_difference}) {
    EXPECT_TRUE(same_bits(a.*member, b.*member));
  }
  EXPECT_EQ(a.skip_reason, b.skip_reason);
  EXPECT_EQ(a.note, b.note);
}

// Records with every kind of field: values that JSON could not carry (±∞, NaN, −0, subnormals),
// empty and multi-line messages, absent optionals, each outcome and none.
std::vector<Record> awkward_records() {
  std::vector<Record> records;
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::optional<double>> values{0.0,
                                                  -0.0,
                                                  inf,
                                                  -inf,
                                                  std::numeric_limits<double>::quiet_NaN(),
                                                  std::numeric_limits<double>::denorm_min(),
                                                  std::nullopt,
                                                  0.1,
                                                  -1e308};
  for (int outcome = -1; outcome <= static_cast<int>(solvers::Outcome::unstable); ++outcome) {
    Record r;
    r.cell = static_cast<std::size_t>(outcome + 7) * 1000003;
    r.config = static_cast<std::size_t>(outcome + 1);
    if (outcome >= 0) {
      r.outcome = static_cast<solvers::Outcome>(outcome);
    }
    r.failure = outcome == -1 ? "the solver threw:\nline two, ünïcödé" : "";
    r.steps = -1 - outcome;
    r.rhs_evals = std::numeric_limits<long>::max() - 1 - outcome; // no overflow at -1
    r.wall_seconds = 1e-7 * outcome;
    r.wall_seconds_slowest = inf;
    r.cpu_seconds = outcome % 2 == 0 ? std::optional<double>(3e-9) : std::nullopt;
    r.alpha = 0.1 + outcome;
    r.alpha_digits = outcome == 2 ? "0.12345678901234567890123456789012345" : "";
    r.phases = outcome + 2;
    r.runs = 3 * outcome;
    r.dt = outcome == 1 ? std::optional<double>(-0.0) : std::nullopt;
    r.value = r.reference = r.error = r.abs_error = values;
    r.rel_error = {std::nullopt};
    r.worst_phase = {0.5, std::nullopt};
    r.skip_reason = outcome == 3 ? "skipped: its code has no force end" : "";
    r.note = std::string(300, 'n');
    r.replica_difference = outcome == 4 ? values : std::vector<std::optional<double>>{};
    records.push_back(r);
  }
  return records;
}

TEST(Shards, RecordsReadBackBitForBit) {
  const std::vector<Record> records = awkward_records();
  std::string bytes;
  append_records(bytes, records);
  const std::vector<Record> back = read_records(bytes, "test");
  ASSERT_EQ(back.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    expect_identical(records[i], back[i]);
  }
  // A real run's records too (every configuration kind of a scene, times included).
  const Scene scene = parse_scene(R"(want = ["e", "delta_max", "tau"]
[grid]
p = [1.5, 3.0]
e = [0.5]
alpha_eff = [2.0]
v0 = [1.0]
[[solver]]
name = "cvode-bdf"
rtol = 1e-8
[[solver]]
name = "taylor"
precision = "quad"
[[solver]]
name = "dem-verlet"
steps_per_contact = 40
onset_phases = 3
)",
                                  "shards.toml");
  const Plan plan = make_plan(scene);
  RunTotals totals;
  const std::vector<Record> solved = run_plan(plan, 2, totals);
  std::string solved_bytes;
  append_records(solved_bytes, solved);
  const std::vector<Record> solved_back = read_records(solved_bytes, "test");
  ASSERT_EQ(solved_back.size(), solved.size());
  for (std::size_t i = 0; i < solved.size(); ++i) {
    expect_identical(solved[i], solved_back[i]);
  }
}

// The records where one process gathers them (rank 0, merge): stored in any order, past the
// writer's buffer, read back in plan order bit for bit; each stored once, read once sealed; the
// file is gone from the folder from the start.
TEST(Shards, AStoreGivesBackItsRecordsInPlanOrderAndLeavesNoFile) {
  const std::vector<Record> awkward = awkward_records();
  std::vector<Record> records;
  for (std::size_t i = 0; i < 6000; ++i) { // about 4 MB: four times the store's buffer
    records.push_back(awkward[i % awkward.size()]);
    records.back().cell = i;
  }
  const fs::path folder = scratch() / "store";
  fs::remove_all(folder);
  fs::create_directories(folder);
  RecordStore store(records.size(), folder);
  EXPECT_TRUE(fs::is_empty(folder));
  for (std::size_t i = 0; i < records.size(); ++i) {
    const std::size_t at = (i * 7919) % records.size(); // a permutation: 7919 is prime
    if (i % 2 == 0) {
      store.put(at, records[at]);
    } else {
      std::string bytes;
      append_record(bytes, records[at]);
      store.put_bytes(at, bytes);
    }
  }
  EXPECT_EQ(store.stored(), records.size());
  EXPECT_THROW(store.put(5, records[5]), std::logic_error);
  EXPECT_THROW(store.at(0), std::logic_error); // not sealed yet
  store.seal();
  std::size_t i = 0;
  for (const Record& record : RecordRange(store)) {
    expect_identical(record, records[i++]);
  }
  EXPECT_EQ(i, records.size());
  EXPECT_THROW(store.put(0, records[0]), std::logic_error); // sealed
  EXPECT_TRUE(fs::is_empty(folder));
  EXPECT_THROW(RecordStore(1, scratch() / "no" / "such" / "folder"), InputError);
}

// Every truncation, and bytes that were never records, give one InputError, never a crash or a
// wrong record.
TEST(Shards, TruncatedOrForeignBytesAreRefused) {
  std::string bytes;
  append_records(bytes, awkward_records());
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    EXPECT_THROW(read_records(std::string_view(bytes).substr(0, length), "test"), InputError)
        << length;
  }
  EXPECT_THROW(read_records(bytes + "x", "test"), InputError);
  // A count of 2^62 records in 8 bytes: refused before anything is allocated.
  std::string huge(8, '\0');
  huge[7] = 0x40;
  EXPECT_THROW(read_records(huge, "test"), InputError);
}

TEST(Shards, CellsAreSplitOnceEachInEveryShareOfTheGrid) {
  for (const std::size_t cells : {1u, 7u, 45u, 100u}) {
    for (const std::size_t count : {1u, 2u, 3u, 8u, 200u}) {
      std::vector<int> seen(cells, 0);
      for (std::size_t k = 1; k <= count; ++k) {
        const std::vector<std::size_t> mine = shard_cells(cells, k, count);
        EXPECT_LE(mine.size(), cells / count + 1);
        EXPECT_GE(mine.size(), cells / count);
        for (const std::size_t cell : mine) {
          ++seen.at(cell);
        }
      }
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(cells));
    }
  }
}

// report.json without what timing decides: times, the runs the repeats made, and what made it
// (`run`: the date and the command line differ; its build is checked apart).
nlohmann::json without_times(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : j.items()) {
      if (key.find("second") == std::string::npos && key != "runs" && key != "solver_runs" &&
          key != "x_analytic" && key != "generated" && key != "run") {
        out[key] = without_times(value);
      }
    }
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const nlohmann::json& item : j) {
      out.push_back(without_times(item));
    }
    return out;
  }
  return j;
}

nlohmann::json report_at(const fs::path& folder) {
  std::ifstream in(folder / "report.json");
  return nlohmann::json::parse(in);
}

// A scene with a claim, every kind of configuration (adaptive, quad, batched fixed-step with
// onset phases) and overdamped cells, in two shards and in five (more shards than a p's cells).
const std::string sharded_scene = R"(name = "sharded"
want = ["e", "delta_max", "tau"]
[grid]
p = [1.0, 1.5, 2.5]
e = [0.9, 0.3]
alpha_eff = [2.0]
v0 = [0.5, 2.0]
[[solver]]
name = "cvode-bdf"
rtol = [1e-6, 1e-10]
[[solver]]
name = "taylor"
precision = "quad"
[[solver]]
name = "verlet-predicted"
steps_per_contact = [50, 200]
onset_phases = 3
[[claim]]
name = "dp5 e"
observable = "e"
solver = "cvode-bdf"
rtol = 1e-10
bound = 1e-5
[report]
formats = ["json", "csv"]
)";

// A record's bytes without what timing decides (its times, the runs its repeats made).
std::string bytes_without_times(Record record) {
  record.wall_seconds = record.wall_seconds_slowest = 0;
  record.cpu_seconds = record.cpu_seconds_slowest = std::nullopt;
  record.runs = 0;
  std::string bytes;
  append_record(bytes, record);
  return bytes;
}

// The records a run solves into a store, a batch of cells at a time (a shard's, a serial run's),
// are run_plan's in plan order whatever the batches, times aside; progress counts every record.
TEST(Shards, RecordsSolvedIntoAStoreInBatchesAreThePlansRecords) {
  const Plan plan = make_plan(parse_scene(sharded_scene, "batches.toml"), 2);
  RunTotals totals;
  const std::vector<Record> expected = run_plan(plan, 2, totals);
  std::vector<std::size_t> cells(plan.cells.size());
  std::iota(cells.begin(), cells.end(), std::size_t{0});
  ASSERT_GT(cells.size(), 16u); // more than one batch of 16 cells
  const fs::path folder = scratch() / "batches";
  fs::create_directories(folder);
  PlanRunner runner(plan, 1);
  for (const std::size_t batch_records : {std::size_t{1}, std::size_t{1} << 20}) {
    RecordStore store(expected.size(), folder);
    std::size_t last = 0;
    solve_into(
        plan, runner, cells, store, 1,
        [&](std::size_t done, std::size_t total) {
          EXPECT_EQ(total, expected.size());
          EXPECT_EQ(done, last + 1);
          last = done;
        },
        batch_records);
    EXPECT_EQ(last, expected.size());
    store.seal();
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(bytes_without_times(store.at(i)), bytes_without_times(expected[i]))
          << "record " << i << ", batches of " << batch_records << " records";
    }
  }
}

TEST(Shards, MergedShardsGiveTheSerialReport) {
  const std::string scene = write_file("sharded.toml", sharded_scene);
  const fs::path base = scratch() / "sharded";
  fs::remove_all(base);
  const CliRun serial = run({"run", scene, "--out", (base / "serial").string(), "--jobs", "2"});
  ASSERT_EQ(serial.code, 0) << serial.err;
  const nlohmann::json expected = without_times(report_at(base / "serial"));
  for (const int count : {2, 5}) {
    std::vector<std::string> merge{"merge"};
    for (int k = count; k >= 1; --k) { // any order
      const std::string folder = (base / fmt::format("{}-of-{}", k, count)).string();
      const CliRun shard = run({"run", scene, "--shard", fmt::format("{}/{}", k, count), "--out",
                                folder, "--jobs", "1"});
      ASSERT_EQ(shard.code, 0) << shard.err;
      EXPECT_NE(shard.out.find(fmt::format("shard {}/{}", k, count)), std::string::npos);
      EXPECT_FALSE(fs::exists(fs::path(folder) / "report.json")); // the merge writes the report
      merge.push_back(folder);
    }
    const fs::path merged = base / fmt::format("merged-{}", count);
    merge.insert(merge.end(), {"--out", merged.string(), "--jobs", "2"});
    const CliRun merging = run(merge);
    ASSERT_EQ(merging.code, 0) << merging.err;
    EXPECT_NE(merging.out.find("claim dp5 e: holds"), std::string::npos) << merging.out;
    EXPECT_EQ(without_times(report_at(merged)), expected) << count << " shards";
    // The merged report names the build that ran the shards, and the merge that made it.
    const nlohmann::json made = report_at(merged)["run"];
    EXPECT_EQ(made["build"], report_at(base / "serial")["run"]["build"]);
    EXPECT_EQ(made["command"][1], "merge");
    EXPECT_EQ(made["scene_checksum"], report_at(base / "serial")["run"]["scene_checksum"]);
    const CliRun diff = run(
        {"diff", (base / "serial" / "report.json").string(), (merged / "report.json").string()});
    EXPECT_EQ(diff.code, 0) << diff.out;
    EXPECT_NE(diff.out.find("0 regressions, 0 changes"), std::string::npos) << diff.out;
  }
}

TEST(Shards, ASetThatIsNotOneRunsShardsIsRefusedWithOneLine) {
  const std::string scene = write_file("refused.toml", sharded_scene);
  const std::string other = write_file("other.toml", valid_scene);
  const fs::path base = scratch() / "refused";
  fs::remove_all(base);
  const auto shard = [&](const std::string& file, const std::string& which,
                         const std::string& name) {
    const std::string folder = (base / name).string();
    const CliRun ran = run({"run", file, "--shard", which, "--out", folder, "--jobs", "1"});
    EXPECT_EQ(ran.code, 0) << ran.err;
    return folder;
  };
  const std::string one = shard(scene, "1/3", "one"), two = shard(scene, "2/3", "two"),
                    three = shard(scene, "3/3", "three"), half = shard(scene, "1/2", "half"),
                    foreign = shard(other, "3/3", "foreign"), limited = (base / "limited").string();
  ASSERT_EQ(run({"run", scene, "--shard", "3/3", "--max-steps", "50", "--out", limited}).code, 0);
  const std::string out = (base / "merged").string();
  const auto refused = [&](std::vector<std::string> args, const std::string& says) {
    args.insert(args.begin(), "merge");
    args.insert(args.end(), {"--out", out});
    const CliRun ran = run(args);
    EXPECT_EQ(ran.code, 2) << says;
    EXPECT_NE(ran.err.find(says), std::string::npos) << ran.err;
    EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1) << ran.err;
    EXPECT_FALSE(fs::exists(fs::path(out) / "report.json"));
  };
  refused({one, two}, "incomplete: 2 of 3 given, missing shard 3");
  refused({one, two, two, three}, "shard 2/3 is given twice");
  refused({one, two, half}, "share their N");
  refused({one, two, foreign}, "different runs");
  refused({one, two, limited}, "different runs");
  refused({one, two, (base / "nowhere").string()}, "not a shard");
  // Another build's shard, and a torn one.
  Shard changed = read_shard(three);
  changed.header.build = "0.0.1+0123456789ab";
  fs::create_directories(base / "old");
  write_shard(base / "old", changed);
  refused({one, two, (base / "old").string()}, "was written by pldamp 0.0.1+0123456789ab");
  fs::create_directories(base / "torn");
  {
    std::ifstream in(fs::path(three) / shard_file_name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(base / "torn" / shard_file_name, std::ios::binary)
        << bytes.substr(0, bytes.size() / 2);
  }
  refused({one, two, (base / "torn").string()}, "truncated or corrupt");
  // One bit flipped in a record's value: the checksum refuses it (it would be merged otherwise).
  fs::create_directories(base / "flipped");
  {
    std::ifstream in(fs::path(three) / shard_file_name, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    bytes[bytes.size() / 2] ^= 0x10;
    std::ofstream(base / "flipped" / shard_file_name, std::ios::binary) << bytes;
  }
  refused({one, two, (base / "flipped").string()}, "checksum does not match");
  // The report into a shard's folder.
  {
    const CliRun ran = run({"merge", one, two, three, "--out", two});
    EXPECT_EQ(ran.code, 2);
    EXPECT_NE(ran.err.find("--out must not be one of the shards' folders"), std::string::npos)
        << ran.err;
    EXPECT_FALSE(fs::exists(fs::path(two) / "report.json"));
  }
  // And the command line's own errors.
  for (const char* bad : {"0/3", "4/3", "3", "1/0", "a/b", "1/1000001"}) {
    const CliRun ran = run({"run", scene, "--shard", bad, "--out", out});
    EXPECT_EQ(ran.code, 2) << bad;
    EXPECT_NE(ran.err.find("--shard must be K/N"), std::string::npos) << ran.err;
  }
  // The complete set still merges; so does a shard run again with the scene's path typed
  // another way (a failed task rerun by hand), which is the same scene.
  EXPECT_EQ(run({"merge", three, one, two, "--out", out}).code, 0);
  const std::string again = (base / "again").string();
  const fs::path relative = fs::relative(scene, fs::current_path());
  ASSERT_EQ(run({"run", "./" + relative.string(), "--shard", "3/3", "--out", again}).code, 0);
  EXPECT_EQ(run({"merge", one, two, again, "--out", out}).code, 0);
}

// A hand-made shard (its checksum is easy to recompute) is held to what a run of this build
// writes: its header's counts against its bytes before anything is allocated or planned (a
// header of a 10^7-cell grid with max_runs = 1e12 was planned in full, 51 s and 1.27 GB; an
// inflated count of the externals' texts turned a 4 MB file into 145 MB), and each record
// checked as an external answer is (a NaN value became null beside its error and failed =
// false; delta_max = 1e308 was reported beside an error of -6e-8).
TEST(Shards, AHandMadeShardIsHeldToWhatItsRunCouldWrite) {
  const std::string scene = write_file("hand-made.toml", sharded_scene);
  const fs::path base = scratch() / "hand-made";
  fs::remove_all(base);
  std::vector<std::string> folders;
  for (int k = 1; k <= 2; ++k) {
    folders.push_back((base / fmt::format("{}", k)).string());
    ASSERT_EQ(run({"run", scene, "--shard", fmt::format("{}/2", k), "--out", folders.back(),
                   "--jobs", "1"})
                  .code,
              0);
  }
  const std::string out = (base / "merged").string();
  const auto merged = [&](const std::function<void(Shard&)>& edit) {
    Shard shard = read_shard(folders[1]);
    edit(shard);
    const fs::path folder = base / "edited";
    fs::remove_all(folder);
    fs::create_directories(folder);
    write_shard(folder, shard);
    return run({"merge", folders[0], folder.string(), "--out", out});
  };
  const auto refused = [&](const std::function<void(Shard&)>& edit, const std::string& says) {
    const CliRun ran = merged(edit);
    EXPECT_EQ(ran.code, 2) << says;
    EXPECT_NE(ran.err.find(says), std::string::npos) << ran.err;
    EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1) << ran.err;
  };
  ASSERT_EQ(merged([](Shard&) {}).code, 0) << "the shards as written merge";
  const Plan plan = make_plan(parse_scene(sharded_scene, scene));
  const auto observable = [&](std::string_view key) {
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      if (plan.observables[o]->key == key) {
        return o;
      }
    }
    throw std::logic_error("no such observable");
  };
  const std::size_t e = observable("e"), delta_max = observable("delta_max");
  // The first record with a value of each.
  const auto with_values = [&](Shard& shard) -> Record& {
    for (Record& record : shard.records) {
      if (record.value.size() > delta_max && record.value[e] && record.value[delta_max] &&
          record.error[e] && record.value[e] != 0) {
        return record;
      }
    }
    throw std::logic_error("no record with values");
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  refused([&](Shard& s) { with_values(s).value[e] = nan; }, "e's value is NaN");
  refused([&](Shard& s) { with_values(s).error[e] = std::numeric_limits<double>::infinity(); },
          "e's error is inf");
  refused([&](Shard& s) { with_values(s).value[delta_max] = 1e308; },
          "delta_max's error " /* is not its value 1e+308 minus its reference */);
  refused([&](Shard& s) { *with_values(s).reference[e] *= 1 + 1e-15; },
          "e's reference " /* is not the plan's */);
  refused(
      [&](Shard& s) {
        Record& r = with_values(s);
        r.value[e] = 1.5; // its error as compare() makes it: an e that gains energy, consistent
        r.error[e] = 1.5 - *r.reference[e];
        r.abs_error[e] = std::abs(*r.error[e]);
        r.rel_error[e] = *r.abs_error[e] / *r.reference[e];
      },
      "e = 1.5 gains energy");
  refused([&](Shard& s) { with_values(s).abs_error[e] = 0.0; }, "e's abs_error 0 is not |error|");
  // |error| stands for the relative error against a reference 0 or infinite and for e on a late
  // return, not for any observable of any record (common/record_consistency.hpp): merged before.
  refused(
      [&](Shard& s) {
        Record& r = with_values(s);
        r.rel_error[delta_max] = r.abs_error[delta_max];
      },
      "delta_max's rel_error " /* is not |error| / |reference| */);
  refused([&](Shard& s) { with_values(s).phases = 7; }, "onset phases, its configuration runs");
  refused([&](Shard& s) { with_values(s).wall_seconds = -1; }, "a time of -1 s, not in [0, 61]");
  // Found by the second hostile pass: each merged with exit 0, or crashed the merge (all lists
  // empty), or ended it with an internal error (text that is not UTF-8 reached report.json).
  refused(
      [&](Shard& s) {
        Record& r = with_values(s);
        r.value = r.reference = r.error = r.abs_error = r.rel_error = r.spread = r.worst_phase = {};
      },
      "it holds 0 values of an observable, the plan has 3 observables");
  refused([&](Shard& s) { with_values(s).note = "x"; },
          "a skip or a note on a configuration of pldamp's own solver");
  refused([&](Shard& s) { with_values(s).skip_reason = "x"; },
          "a skip or a note on a configuration of pldamp's own solver");
  refused([&](Shard& s) { with_values(s).outcome = solvers::Outcome::peak; },
          "e, tau or energy_unload beside outcome peak");
  refused([&](Shard& s) { with_values(s).outcome = solvers::Outcome::unstable; },
          "values beside outcome unstable");
  refused([&](Shard& s) { with_values(s).alpha = 123; }, "alpha = 123, its cell's is ");
  refused([&](Shard& s) { with_values(s).wall_seconds = 1e300; }, "a time of 1e+300 s");
  refused([&](Shard& s) { with_values(s).rhs_evals = std::numeric_limits<long>::max(); },
          "work out of its run's limits");
  refused(
      [&](Shard& s) {
        for (Record& r : s.records) {
          if (!plan.configs[r.config].steps_per_contact) {
            r.dt = 0.1; // a step on an error-controlled configuration
            return;
          }
        }
      },
      "a step dt = 0.1 for a configuration without one");
  refused([&](Shard& s) { with_values(s).failure = "\xff"; }, "is truncated or corrupt");
  refused([&](Shard& s) { with_values(s).failure = std::string(20000, 'x'); },
          "is truncated or corrupt");
  // More bytes than its records could take: refused before the checksum reads them (a 4 GiB file
  // was hashed whole, 24 s, before).
  {
    std::ifstream in(fs::path(folders[1]) / shard_file_name, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    bytes.insert(bytes.size() - 8, std::string(std::size_t{8} << 20, '\0'));
    fs::create_directories(base / "padded");
    std::ofstream(base / "padded" / shard_file_name, std::ios::binary) << bytes;
    const CliRun ran = run({"merge", folders[0], (base / "padded").string(), "--out", out});
    EXPECT_EQ(ran.code, 2);
    EXPECT_NE(ran.err.find("records its header names could take"), std::string::npos) << ran.err;
  }
  // The header: a scene of 10^7 cells with limits lifted, planned only after its bytes are
  // counted; one whose cells disagree with its scene.
  std::vector<int> values(1000); // 9·10^6 cells in 9 kB: 3 p × 3 dampings × 10^3 v0 × 10^3 m
  std::iota(values.begin(), values.end(), 1);
  std::string huge = sharded_scene;
  huge.replace(huge.find("v0 = [0.5, 2.0]"), 15,
               fmt::format("v0 = [{0}]\nm = [{0}]", fmt::join(values, ", ")));
  refused(
      [&](Shard& s) {
        s.header.scene_text = huge;
        s.header.cells = 3 * 3 * 1000000;
        s.header.max_runs = 1000000000000L;
      },
      "are shards of different runs");
  const auto both = [&](const std::function<void(Shard&)>& edit) {
    // The same header in both shards: the set is one run's but for what the header says.
    for (const std::string& folder : folders) {
      Shard shard = read_shard(folder);
      edit(shard);
      fs::remove_all(base / "both" / fs::path(folder).filename());
      fs::create_directories(base / "both" / fs::path(folder).filename());
      write_shard(base / "both" / fs::path(folder).filename(), shard);
    }
    return run(
        {"merge", (base / "both" / "1").string(), (base / "both" / "2").string(), "--out", out});
  };
  const CliRun planned = both([&](Shard& s) {
    s.header.scene_text = huge;
    s.header.cells = 3 * 3 * 1000000;
    s.header.max_runs = 1000000000000L;
  });
  EXPECT_EQ(planned.code, 2);
  EXPECT_NE(planned.err.find("the shards' header says 9000000 cells x "), std::string::npos)
      << planned.err;
  const CliRun disagreeing = both([&](Shard& s) { s.header.cells += 1; });
  EXPECT_NE(disagreeing.err.find("the shards' scene has 18 cells, their header says 19"),
            std::string::npos)
      << disagreeing.err;
  for (const auto& [edit, why] : std::vector<std::pair<std::function<void(Shard&)>, std::string>>{
           {[](Shard& s) { s.header.max_runs = 0; }, "max_runs 0"},
           {[nan](Shard& s) { s.header.max_seconds = nan; }, "max_seconds NaN"},
           {[](Shard& s) { s.header.totals.external.push_back("x"); }, "a text too many"}}) {
    const CliRun ran = both(edit);
    EXPECT_EQ(ran.code, 2) << why;
    EXPECT_NE(ran.err.find("is truncated or corrupt: it is not a file pldamp wrote"),
              std::string::npos)
        << why << ": " << ran.err;
  }
  // A count of texts inflated to the bytes left: refused before 8 bytes a text are allocated.
  {
    std::ifstream in(fs::path(folders[1]) / shard_file_name, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const Shard shard = read_shard(folders[1]);
    // The count sits right after the totals' wall seconds: found by the two values.
    const auto count = static_cast<std::uint64_t>(shard.header.totals.external.size());
    std::string pattern(reinterpret_cast<const char*>(&count), sizeof count);
    double wall = shard.header.totals.wall_seconds;
    pattern.insert(0, std::string(reinterpret_cast<const char*>(&wall), sizeof wall));
    const std::size_t at = bytes.find(pattern);
    ASSERT_NE(at, std::string::npos);
    const std::uint64_t inflated = bytes.size();
    std::memcpy(bytes.data() + at + sizeof wall, &inflated, sizeof inflated);
    const std::string body = bytes.substr(0, bytes.size() - 8);
    const std::uint64_t sum = fnv1a(body);
    bytes = body + std::string(reinterpret_cast<const char*>(&sum), sizeof sum);
    fs::create_directories(base / "inflated");
    std::ofstream(base / "inflated" / shard_file_name, std::ios::binary) << bytes;
    const CliRun ran = run({"merge", folders[0], (base / "inflated").string(), "--out", out});
    EXPECT_EQ(ran.code, 2);
    EXPECT_NE(ran.err.find("is truncated or corrupt"), std::string::npos) << ran.err;
  }
}

// What a run of pldamp's own solvers writes is what merge takes: a coarse fixed step's dashpot
// work can come out negative, and its solver does not refuse it (only an external program's
// answers are held to the energy's sign, run/answers.hpp); a merge of the shipped viscoelastic
// scene refused exactly that record before.
TEST(Shards, ARecordAsItsOwnSolverWroteItIsMerged) {
  const Plan plan = make_plan(parse_scene(R"(name = "coarse"
want = ["e", "energy"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "dem-symplectic-euler"
steps_per_contact = [10]
)",
                                          "coarse.toml"));
  Record record;
  record.cell = 0;
  record.config = 0;
  record.outcome = solvers::Outcome::exited;
  record.alpha = alpha_as_received<double>(plan.cells[0].alpha);
  record.value.assign(plan.observables.size(), std::nullopt);
  record.reference = record.error = record.abs_error = record.rel_error = record.spread =
      record.worst_phase = record.value;
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    if (plan.observables[o]->key == "energy_load") {
      record.value[o] = -6.0; // six times m v0^2/2: beyond any allowance an external answer gets
    }
  }
  EXPECT_EQ(impossible_record(plan, record), "");
  for (std::size_t o = 0; o < plan.observables.size(); ++o) {
    if (plan.observables[o]->key == "e") {
      record.value[o] = 1.3; // beyond the step's allowance, min((ωΔt)²/8, 1/4)
    }
  }
  EXPECT_EQ(impossible_record(plan, record).rfind("e = 1.3 gains energy", 0), 0u);
}

// A record of several onset phases keeps the first phase's outcome and each observable's worst
// phase: no_exit in one phase beside another phase's e is what a run writes, and merges (it was
// refused as "e = 0.3 beside outcome no_exit"); with one phase it is a contradiction.
TEST(Shards, APhasedRecordsOutcomeAndValuesMayComeFromDifferentPhases) {
  for (const int phases : {1, 4}) {
    const Plan plan = make_plan(parse_scene(R"(name = "phased"
want = ["e"]
[grid]
p = [1.5]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "dem-verlet"
steps_per_contact = [10]
onset_phases = )" + std::to_string(phases) + "\n",
                                            "phased.toml"));
    Record record;
    record.cell = 0;
    record.config = 0;
    record.phases = phases;
    record.outcome = solvers::Outcome::no_exit;
    record.alpha = alpha_as_received<double>(plan.cells[0].alpha);
    record.value.assign(plan.observables.size(), std::nullopt);
    record.reference = record.error = record.abs_error = record.rel_error = record.spread =
        record.worst_phase = record.value;
    record.value[0] = 0.3;
    record.worst_phase[0] = 0.25;
    if (phases == 1) {
      record.worst_phase[0] = 0.0;
      EXPECT_EQ(impossible_record(plan, record), "e = 0.3 beside outcome no_exit");
    } else {
      EXPECT_EQ(impossible_record(plan, record), "");
    }
  }
}

// An external program's record is merged only as its answer was judged when it ran
// (run/answers.hpp, impossible_answer): delta_max = 1e308 beside a consistent error was merged
// before. With one onset phase the values are one answer's; with more, each observable's is its
// worst phase's, so only each value alone is held.
TEST(Shards, AnExternalRecordIsMergedOnlyAsItsAnswerWasJudged) {
  const auto plan_of = [](int phases) {
    return make_plan(parse_scene(fmt::format(R"(name = "external"
want = ["e", "delta_max", "t_peak", "tau"]
[grid]
p = [1.0]
e = [0.5]
v0 = [1.0]
[[solver]]
command = ["./adapter"]
label = "fake"
steps_per_contact = [20]
onset_phases = {}
)",
                                             phases),
                                 "external.toml"));
  };
  const auto record_of = [](const Plan& plan, double delta_max, double t_peak, double tau) {
    Record record;
    record.cell = 0;
    record.config = 0;
    record.outcome = solvers::Outcome::exited;
    record.phases = plan.configs[0].onset_phases;
    record.alpha = alpha_as_received<double>(plan.cells[0].alpha);
    record.value.assign(plan.observables.size(), std::nullopt);
    record.reference = record.error = record.abs_error = record.rel_error = record.spread =
        record.worst_phase = record.value;
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const std::string_view key = plan.observables[o]->key;
      record.value[o] = key == "e"           ? 0.5
                        : key == "delta_max" ? delta_max
                        : key == "t_peak"    ? t_peak
                                             : tau;
    }
    return record;
  };
  // p = 1, m = k = v0 = 1: δ_u = 1, the undamped contact lasts π.
  const Plan one = plan_of(1);
  EXPECT_EQ(impossible_record(one, record_of(one, 0.8, 1.4, 3.5)), "");
  EXPECT_EQ(impossible_record(one, record_of(one, 1e308, 1.4, 3.5))
                .rfind("impossible answer: energy gained: delta_max = 1e+308 above the undamped "
                       "peak delta_u = 1",
                       0),
            0u);
  EXPECT_EQ(impossible_record(one, record_of(one, 0.8, 0.0, 3.5)),
            "impossible answer: t_peak = 0: not positive (the contact begins at v0 > 0)");
  EXPECT_EQ(impossible_record(one, record_of(one, 0.8, 3.5, 1.4)),
            "impossible answer: tau = 1.4 not after t_peak = 3.5: a contact ends after its peak");
  // Two phases: t_peak and τ may be different phases' (each its worst), a value alone may not.
  const Plan two = plan_of(2);
  EXPECT_EQ(impossible_record(two, record_of(two, 0.8, 3.5, 1.4)), "");
  EXPECT_EQ(impossible_record(two, record_of(two, 1e308, 1.4, 3.5))
                .rfind("impossible answer: energy gained: delta_max = 1e+308", 0),
            0u);
  EXPECT_EQ(impossible_record(two, record_of(two, 0.8, 1.4, 5e-324)), ""); // alone, positive
}

// When a rank cannot start (MPI's all_ready): rank 0 says why, once, for every rank; what fails
// on rank 0 as it is, what fails on other ranks only as the first such rank's, with how many more.
TEST(Distribution, WhoSaysWhyARunCannotStart) {
  const std::string failure = "cannot read scene.toml";
  const std::vector<std::string> everywhere(3, failure);
  EXPECT_EQ(not_ready_message(0, everywhere).why, failure);
  EXPECT_TRUE(not_ready_message(0, everywhere).speaks);
  EXPECT_EQ(not_ready_message(2, everywhere).why, ""); // said by rank 0
  EXPECT_FALSE(not_ready_message(2, everywhere).speaks);
  // Ranks 2 and 3 lack a file: rank 0 says rank 2's failure, and that one more failed.
  const std::vector<std::string> two{"", "", failure, "another copy of the scene"};
  EXPECT_EQ(not_ready_message(0, two).why,
            "rank 2: cannot read scene.toml (and 1 more rank could not start)");
  EXPECT_FALSE(not_ready_message(0, two).speaks);
  EXPECT_EQ(not_ready_message(3, two).why, "");
  EXPECT_EQ(not_ready_message(0, {"", failure}).why, "rank 1: cannot read scene.toml");
  EXPECT_EQ(not_ready_message(0, {"", "", ""}).why, ""); // every rank ready
}

// Exact values as bytes: bit for bit in every precision, ±0, ±∞, NaN of either sign (a report
// prints "-nan" where a formula gave one: under MPI it printed "nan"), the extremes of each type's
// range and values with every significand bit in use.
template <class Real>
void expect_reals_read_back() {
  using std::ldexp;
  using L = std::numeric_limits<Real>;
  std::vector<Real> values{Real(0),           -Real(0),          L::infinity(),    -L::infinity(),
                           L::quiet_NaN(),    -L::quiet_NaN(),   L::max(),         -L::max(),
                           L::min(),          L::denorm_min(),   -L::denorm_min(), L::epsilon(),
                           Real(1) / Real(3), -Real(2) / Real(7)};
  for (int e : {-1000, -60, -1, 0, 1, 53, 113, 900}) {
    values.push_back(ldexp(Real(1) - L::epsilon() / 2, e)); // every significand bit set
    values.push_back(-ldexp(Real(5) / Real(11), e));
  }
  std::string bytes;
  ByteWriter out(bytes);
  for (const Real& x : values) {
    put_real(out, x);
  }
  ByteReader in(bytes, "test");
  for (const Real& x : values) {
    const Real back = get_real<Real>(in);
    using std::isnan;
    if (isnan(x)) {
      EXPECT_TRUE(isnan(back) && boost::math::signbit(back) == boost::math::signbit(x));
    } else {
      EXPECT_TRUE(back == x && boost::math::signbit(back) == boost::math::signbit(x))
          << x << " read back as " << back;
    }
  }
  EXPECT_TRUE(in.at_end());
}

TEST(Points, ExactValuesReadBackBitForBitInEveryPrecision) {
  expect_reals_read_back<double>();
  expect_reals_read_back<long double>();
  expect_reals_read_back<Exact>();
  expect_reals_read_back<boost::multiprecision::cpp_bin_float_50>(); // Exact without float128
}

bool same_exact(const Exact& a, const Exact& b) {
  using std::isnan;
  return boost::math::signbit(a) == boost::math::signbit(b) && ((isnan(a) && isnan(b)) || a == b);
}

// A plan's points as the ranks exchange them: seed points (one overdamped) and a point beyond the
// seed (its truth a reference solve), every field as it was.
TEST(Points, APlansPointsReadBackBitForBit) {
  Scene scene = parse_scene(sharded_scene, "points.toml");
  Plan plan = make_plan(scene);
  scene.damping_exponent = {0.5};
  scene.p = {1.5};
  scene.damping.resize(1);
  const Plan beyond = make_plan(scene);
  ASSERT_TRUE(beyond.points.at(0).solved);
  plan.points.push_back(beyond.points[0]);
  std::string bytes;
  append_points(bytes, plan.points);
  const std::vector<Point> back = read_points(bytes, "test");
  ASSERT_EQ(back.size(), plan.points.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    const Point &a = plan.points[i], &b = back[i];
    EXPECT_TRUE(same_bits(a.p, b.p));
    EXPECT_EQ(a.damping.kind, b.damping.kind);
    EXPECT_TRUE(same_bits(a.damping.value, b.damping.value));
    EXPECT_TRUE(same_bits(a.alpha_eff, b.alpha_eff));
    EXPECT_TRUE(same_exact(a.alpha, b.alpha));
    EXPECT_EQ(a.overdamped, b.overdamped);
    EXPECT_TRUE(same_exact(a.log_duration, b.log_duration));
    ASSERT_EQ(a.reference.size(), b.reference.size());
    for (const auto& [at, values] : a.reference) {
      const auto& other = b.reference.at(at);
      ASSERT_EQ(values.size(), other.size());
      for (std::size_t o = 0; o < values.size(); ++o) {
        EXPECT_EQ(values[o].has_value(), other[o].has_value());
        EXPECT_TRUE(!values[o] || same_exact(*values[o], *other[o])) << i << " " << o;
      }
    }
    ASSERT_EQ(a.analytic.size(), b.analytic.size());
    for (std::size_t o = 0; o < a.analytic.size(); ++o) {
      EXPECT_TRUE(same_bits(a.analytic[o].value, b.analytic[o].value));
      EXPECT_TRUE(same_bits(a.analytic[o].error, b.analytic[o].error));
      EXPECT_EQ(a.analytic[o].representable, b.analytic[o].representable);
      EXPECT_TRUE(same_bits(a.analytic[o].log_error, b.analytic[o].log_error));
    }
    EXPECT_TRUE(same_bits(a.analytic_seconds, b.analytic_seconds));
    EXPECT_TRUE(same_bits(a.beta, b.beta));
    EXPECT_EQ(a.solved, b.solved);
    EXPECT_TRUE(same_bits(a.truth_error, b.truth_error));
    EXPECT_EQ(a.no_truth, b.no_truth);
    EXPECT_TRUE(same_exact(a.group, b.group));
  }
  for (std::size_t length = 0; length < bytes.size(); length += 7) {
    EXPECT_THROW(read_points(std::string_view(bytes).substr(0, length), "test"), InputError);
  }
  EXPECT_THROW(read_points(bytes + "x", "test"), InputError);
}

// Ranks as threads of one process, exchanging through memory as MPI ranks do through messages.
struct ThreadRanks {
  explicit ThreadRanks(int ranks)
      : size(ranks), sync(ranks), slots(static_cast<std::size_t>(ranks)) {}
  int size;
  std::barrier<> sync;
  std::vector<std::string> slots;
};

class ThreadRank final : public Distribution {
public:
  ThreadRank(ThreadRanks& ranks, int rank) : ranks_(ranks), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return ranks_.size; }
  int ranks_on_node() const override { return ranks_.size; }
  bool all_ready(const std::string& failure, std::string&) override { return failure.empty(); }
  std::vector<std::string> all_gather(const std::string& mine) override {
    ranks_.slots[static_cast<std::size_t>(rank_)] = mine;
    ranks_.sync.arrive_and_wait();
    std::vector<std::string> all = ranks_.slots;
    ranks_.sync.arrive_and_wait();
    return all;
  }
  void run(const Plan&, PlanRunner&, RecordStore*,
           const std::function<void(std::size_t, std::size_t)>&, bool&) override {}

private:
  ThreadRanks& ranks_;
  int rank_;
};

// body(rank) on `size` ranks, each a thread.
template <class Body>
void on_thread_ranks(int size, Body&& body) {
  ThreadRanks ranks(size);
  std::vector<std::thread> threads;
  for (int r = 0; r < size; ++r) {
    threads.emplace_back([&, r] {
      ThreadRank rank(ranks, r);
      body(rank);
    });
  }
  for (std::thread& thread : threads) {
    thread.join();
  }
}

// The bytes of a plan's points, their times (the closed forms' cost, measured) set aside.
std::string points_without_times(std::vector<Point> points) {
  for (Point& point : points) {
    point.analytic_seconds = 0;
  }
  std::string bytes;
  append_points(bytes, points);
  return bytes;
}

// Under MPI each point's truth is computed once in the run, by one rank, and every rank then holds
// the serial plan's points; a point that fails fails every rank's plan with the serial error.
TEST(Distribution, EachPointIsComputedOnceAndEveryRankHoldsTheSerialPlan) {
  Scene scene = parse_scene(sharded_scene, "points.toml");
  const Plan serial = make_plan(scene, 2);
  constexpr int size = 3;
  std::vector<std::atomic<int>> computed(serial.points.size());
  std::vector<Plan> plans(size);
  on_thread_ranks(size, [&](ThreadRank& rank) {
    plans[static_cast<std::size_t>(rank.rank())] = make_plan(
        scene, 1, [&](std::size_t count, const std::function<Point(std::size_t)>& point_at) {
          return points_on_ranks(
              rank, count,
              [&](std::size_t i) {
                ++computed.at(i);
                return point_at(i);
              },
              2);
        });
  });
  for (std::size_t i = 0; i < computed.size(); ++i) {
    EXPECT_EQ(computed[i], 1) << "point " << i;
  }
  std::string first;
  append_points(first, plans[0].points);
  for (const Plan& plan : plans) {
    std::string bytes;
    append_points(bytes, plan.points);
    EXPECT_EQ(bytes, first); // times included: one rank measured each
    EXPECT_EQ(points_without_times(plan.points), points_without_times(serial.points));
    EXPECT_EQ(plan.cells.size(), serial.cells.size());
  }

  // Points 4 and 5 fail on ranks 1 and 2: every rank throws point 4's error, as a serial plan.
  std::vector<std::string> errors(size);
  on_thread_ranks(size, [&](ThreadRank& rank) {
    try {
      points_on_ranks(
          rank, 9,
          [](std::size_t i) -> Point {
            if (i == 4) {
              throw InputError("point 4 has no truth");
            }
            if (i == 5) {
              throw std::runtime_error("point 5 failed inside");
            }
            return Point{};
          },
          1);
    } catch (const InputError& e) {
      errors[static_cast<std::size_t>(rank.rank())] = e.what();
    }
  });
  EXPECT_EQ(errors, std::vector<std::string>(size, "point 4 has no truth"));
}

// A map shared among ranks computes each piece once in the run, and every rank holds every
// result in index order, as the serial map's: for fewer pieces than ranks, none, and a count the
// ranks do not divide. A piece that fails throws the lowest failing index's error, of its kind,
// on every rank alike (an internal one as InternalError: the command line's exit code 3).
TEST(Distribution, ASharedMapComputesEachPieceOnceAndEveryRankHoldsEveryResult) {
  constexpr int size = 3;
  const auto piece = [](std::size_t i) {
    return i % 4 == 3 ? std::nullopt : std::optional<std::string>(std::string(i, 'x'));
  };
  for (const std::size_t count : {0, 2, 10}) {
    std::vector<std::atomic<int>> computed(count);
    std::vector<std::vector<std::optional<std::string>>> held(size);
    on_thread_ranks(size, [&](ThreadRank& rank) {
      held[static_cast<std::size_t>(rank.rank())] =
          map_shared<std::optional<std::string>>(count, Workers(2, &rank), [&](std::size_t i) {
            ++computed.at(i);
            return piece(i);
          });
    });
    const std::vector<std::optional<std::string>> serial =
        map_shared<std::optional<std::string>>(count, 2, piece);
    ASSERT_EQ(serial.size(), count);
    for (std::size_t i = 0; i < count; ++i) {
      EXPECT_EQ(computed[i], 1) << "piece " << i << " of " << count;
    }
    for (const auto& results : held) {
      EXPECT_EQ(results, serial) << count << " pieces";
    }
  }
  const std::vector<std::pair<std::size_t, std::string>> failures{
      {7, "piece 7: bad input"}, {5, "piece 5 failed inside"}, {9, "piece 9 failed"}};
  std::vector<std::string> said(size);
  on_thread_ranks(size, [&](ThreadRank& rank) {
    try {
      map_shared<bool>(10, Workers(1, &rank), [&](std::size_t i) {
        if (i == 7) {
          throw InputError(failures[0].second);
        }
        if (i == 5 || i == 9) {
          throw std::runtime_error(i == 5 ? failures[1].second : failures[2].second);
        }
        return true;
      });
    } catch (const InternalError& e) {
      said[static_cast<std::size_t>(rank.rank())] = e.what();
    }
  });
  EXPECT_EQ(said, std::vector<std::string>(size, "piece 5 failed inside"));
}

// Claims of every kind judged on grids of their own (a bound's with a denser grid), a search with
// a group per p (as many as the test's ranks) and one with a group of all cells, and a time-step
// study.
const std::string shared_judging_scene = R"(name = "judged"
want = ["e", "tau"]
[grid]
p = [1.0, 1.5, 2.0]
e = [0.5]
v0 = [1.0]
[[solver]]
name = "verlet-predicted"
steps_per_contact = [50, 200]
[[claim]]
name = "bound on a grid of its own"
observable = "e"
solver = "cvode-bdf"
rtol = 1e-8
bound = 1e-4
p = [1.0, 3.0]
e = [0.3, 0.9]
v0 = 1.0
denser = true
[[claim]]
name = "relation"
kind = "relation"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
relation = "lower_bound"
p = [1.0, 2.0]
alpha_eff = [0.1, 0.5]
v0 = 1.0
denser = true
[[claim]]
name = "asymptotic"
kind = "asymptotic"
expect = "fails"
of = "truth"
quantity = "tau_ratio"
formula = "seed_tau_ratio_curve"
order = 3
range = [1e-4, 1e-2]
points = 4
p = [1.0, 2.0]
v0 = 1.0
[[claim]]
name = "recovered"
kind = "recovered_parameter"
solver = "arkode-dp5"
rtol = 1e-8
bound = 1e-3
p = [1.5]
e = [0.5, 0.9]
v0 = 1.0
[[claim]]
name = "stability"
kind = "stability"
expect = "fails"
solver = "dem-verlet"
formula = "seed_dt_crit"
p = [1.0, 2.0]
e = [0.5]
v0 = [1.0]
[[search]]
name = "by p"
solver = "verlet-predicted"
parameter = "steps_per_contact"
range = [10, 1000]
observable = "e"
bound = 1e-3
group_by = "p"
[[search]]
name = "all cells"
solver = "arkode-dp5"
parameter = "rtol"
range = [1e-10, 1e-3]
observable = "e"
bound = 1e-6
group_by = "all"
[report]
formats = ["json"]
)";

// Under MPI the ranks judge the claims of every kind on grids of their own, the searches (more
// groups than ranks, and one group whose trials they share) and the time-step study together,
// only rank 0 with the records: rank 0's budgets are the serial ones.
TEST(Distribution, TheRanksJudgeTheClaimsSearchesAndStepStudyAsOneProcess) {
  const Scene scene = parse_scene(shared_judging_scene, "judged.toml");
  const Plan plan = make_plan(scene, 2);
  RunTotals totals;
  const std::vector<Record> records = run_plan(plan, 2, totals);
  const auto report_of = [&](const Budgets& budgets) {
    const std::vector<Figure> figures;
    return without_times(report_json(RunReport{plan, records, budgets, totals, figures}));
  };
  const nlohmann::json serial = report_of(make_budgets(plan, records, 2));
  ASSERT_EQ(serial["claims"].size(), 5u);
  ASSERT_EQ(serial["searches"].size(), 2u);
  constexpr int size = 3;
  std::vector<std::optional<Budgets>> budgets(size);
  on_thread_ranks(size, [&](ThreadRank& rank) {
    const std::vector<Record> none;
    budgets[static_cast<std::size_t>(rank.rank())] =
        make_budgets(plan, rank.rank() == 0 ? records : none, Workers(1, &rank));
  });
  const nlohmann::json of_rank_0 = report_of(*budgets[0]);
  for (const auto& [section, part] : serial.items()) {
    EXPECT_EQ(of_rank_0[section], part) << section;
  }
  for (const std::optional<Budgets>& of_rank : budgets) { // what every rank decided alike
    EXPECT_EQ(of_rank->searches.size(), 2u);
    EXPECT_EQ(of_rank->steps.sweeps.size(), 1u);
  }
}

// Under mpirun the ranks share the cells: --shard is refused there, even on one rank.
TEST(Shards, AShardIsRefusedUnderMpi) {
  struct OneRank final : Distribution {
    int rank() const override { return 0; }
    int size() const override { return 1; }
    int ranks_on_node() const override { return 1; }
    bool all_ready(const std::string&, std::string&) override { return true; }
    std::vector<std::string> all_gather(const std::string& mine) override { return {mine}; }
    void run(const Plan&, PlanRunner&, RecordStore*,
             const std::function<void(std::size_t, std::size_t)>&, bool&) override {}
  } one_rank;
  const std::string scene = write_file("mpi-shard.toml", sharded_scene);
  const std::vector<std::string> args{
      "pldamp", "run", scene, "--shard", "1/2", "--out", (scratch() / "mpi-shard").string()};
  std::vector<const char*> argv;
  for (const std::string& a : args) {
    argv.push_back(a.c_str());
  }
  std::ostringstream out, err;
  EXPECT_EQ(run_cli(static_cast<int>(argv.size()), argv.data(), out, err, &one_rank), 2);
  EXPECT_NE(err.str().find("--shard is for job arrays without MPI"), std::string::npos)
      << err.str();
}

// The plan guard counts what one process runs: a grid too large for one is accepted in shards,
// each a share of it.
TEST(Shards, ThePlanGuardCountsOneShardsRuns) {
  // Without the claim and the fixed-step scheme: the claim's solves (on a denser grid of its
  // own) and the time-step study's one process makes.
  const std::string grid = sharded_scene.substr(0, sharded_scene.find("[[solver]]"));
  const std::string scene = write_file(
      "guarded.toml", grid + "[[solver]]\nname = \"cvode-bdf\"\nrtol = [1e-6, 1e-8, 1e-10]\n");
  const std::string out = (scratch() / "guarded").string();
  const CliRun whole = run({"run", scene, "--max-runs", "40", "--out", out}); // 54 runs
  EXPECT_EQ(whole.code, 2);
  EXPECT_NE(whole.err.find("or share it with --shard or mpirun"), std::string::npos) << whole.err;
  const CliRun share = run({"run", scene, "--max-runs", "40", "--shard", "1/2", "--out", out});
  EXPECT_EQ(share.code, 0) << share.err;
}

} // namespace
} // namespace pldamp::harness

namespace pldamp::harness {
namespace {

// Sets an environment variable for a scope.
class ScopedVariable {
public:
  ScopedVariable(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~ScopedVariable() { ::unsetenv(name_); }
  ScopedVariable(const ScopedVariable&) = delete;
  ScopedVariable& operator=(const ScopedVariable&) = delete;

private:
  const char* name_;
};

// `srun -n 4 pldamp run ...` without --mpi=pmix started 4 serial runs of the whole scene into one
// folder, all exiting 0 (issue 49): a task of several that is not an MPI rank is refused, unless
// it runs its own --shard.
TEST(Shards, SrunTasksThatAreNotRanksAreRefusedUnlessSharded) {
  const std::string scene = write_file("srun.toml", sharded_scene);
  const fs::path out = scratch() / "srun";
  fs::remove_all(out);
  const ScopedVariable task("SLURM_PROCID", "1");
  const ScopedVariable tasks("SLURM_STEP_NUM_TASKS", "4");
  const CliRun plain = run({"run", scene, "--out", out.string()});
  EXPECT_EQ(plain.code, 2);
  EXPECT_EQ(plain.err,
            "error: started by srun as task 1 of 4 but not as an MPI rank: each task would run "
            "the whole scene into one folder; add --mpi=pmix to srun for MPI ranks, or give each "
            "task its own --shard K/N and --out (got SLURM_PROCID=1 SLURM_STEP_NUM_TASKS=4)\n");
  EXPECT_FALSE(fs::exists(out / "report.json"));
  {
    const ScopedVariable pmix("PMIX_RANK", "1"); // a PMIx launch this build cannot join
    const CliRun without_mpi = run({"run", scene, "--out", out.string()});
    EXPECT_EQ(without_mpi.code, 2);
    EXPECT_NE(without_mpi.err.find("this pldamp was built without MPI"), std::string::npos)
        << without_mpi.err;
  }
  const CliRun merge = run({"merge", out.string()});
  EXPECT_EQ(merge.code, 2);
  EXPECT_NE(merge.err.find("merge is one process's work"), std::string::npos) << merge.err;
  const CliRun sharded = run({"run", scene, "--shard", "2/4", "--out", out.string()});
  EXPECT_EQ(sharded.code, 0) << sharded.err;
  const ScopedVariable one("SLURM_STEP_NUM_TASKS", "1"); // one task: an ordinary run
  EXPECT_EQ(run({"run", scene, "--out", (scratch() / "srun-one").string()}).code, 0);
}

// merge refuses only what changes records: shards run under different --max-runs (a guard on
// the plan's size) merge; other step budgets are refused, the line naming both (issue 49: both
// read "shards of different runs (another scene, another scene text or other limits)").
TEST(Shards, ShardsDifferingOnlyInTheirGuardMergeAndABudgetThatChangesRecordsIsNamed) {
  const std::string scene = write_file("guards.toml", sharded_scene);
  const fs::path base = scratch() / "guards";
  fs::remove_all(base);
  const auto shard = [&](const std::string& k, const std::string& name,
                         std::vector<std::string> extra) {
    std::vector<std::string> args{"run", scene, "--shard", k, "--out", (base / name).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return (base / name).string();
  };
  const std::string one = shard("1/2", "1", {"--max-runs", "100000"});
  const std::string two = shard("2/2", "2", {"--max-runs", "200000"});
  const CliRun merged = run({"merge", one, two, "--out", (base / "merged").string()});
  EXPECT_EQ(merged.code, 0) << merged.err;
  const std::string budget = shard("2/2", "2-steps", {"--max-steps", "50000"});
  const CliRun refused = run({"merge", one, budget, "--out", (base / "refused").string()});
  EXPECT_EQ(refused.code, 2);
  EXPECT_EQ(refused.err, "error: " + one + " and " + budget +
                             " are shards of different runs: each solve's step budget "
                             "(--max-steps, [limits] max_steps) is 1000000 and 50000 (got " +
                             budget + ")\n");
}

// A shard's --out is its folder, not a report's (issue 49: the error said "report folder").
TEST(Shards, AShardsFolderThatCannotBeMadeIsNamedAsSuch) {
  const std::string scene = write_file("folder.toml", sharded_scene);
  const std::string file = write_file("a-file", "not a folder");
  const CliRun r = run({"run", scene, "--shard", "1/2", "--out", file + "/shard"});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err.rfind("error: cannot create the shard's folder, ", 0), 0u) << r.err;
}

} // namespace
} // namespace pldamp::harness
