// The arrows of docs/design.md §§2–3, read from the includes: solvers/ never includes the closed
// forms (its value as a check is its independence), core/ includes no other layer, and in harness/
// a stage includes only itself and the stages before it (common, scene, truth, run, judge, report,
// cli).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

namespace fs = std::filesystem;

const fs::path root = fs::path(PLDAMP_DATA_DIR).parent_path();

// The quoted includes of every source file below `folder`, as (file, included path).
std::vector<std::pair<fs::path, std::string>> includes_below(const fs::path& folder) {
  std::vector<std::pair<fs::path, std::string>> out;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string extension = entry.path().extension().string();
    if (!entry.is_regular_file() || (extension != ".cpp" && extension != ".hpp")) {
      continue;
    }
    std::ifstream in(entry.path());
    for (std::string line; std::getline(in, line);) {
      const std::string opening = "#include \"";
      if (line.rfind(opening, 0) == 0) {
        const std::size_t end = line.find('"', opening.size());
        out.emplace_back(entry.path(), line.substr(opening.size(), end - opening.size()));
      }
    }
  }
  return out;
}

TEST(Layers, SolversNeverIncludeTheClosedFormsAndCoreNoOtherLayer) {
  std::size_t seen = 0;
  for (const auto& [file, included] : includes_below(root / "solvers")) {
    ++seen;
    EXPECT_EQ(included.find("analytic"), std::string::npos) << file << " includes " << included;
    EXPECT_EQ(included.find("harness"), std::string::npos) << file << " includes " << included;
  }
  EXPECT_GT(seen, 20u);
  for (const auto& [file, included] : includes_below(root / "core")) {
    EXPECT_EQ(included.rfind("pldamp/core/", 0), 0u) << file << " includes " << included;
  }
}

TEST(Layers, AHarnessStageIncludesOnlyItselfAndTheStagesBeforeIt) {
  const std::array<std::string, 7> stages{"common", "scene",  "truth", "run",
                                          "judge",  "report", "cli"};
  const auto rank = [&](const std::string& stage) {
    return std::find(stages.begin(), stages.end(), stage) - stages.begin();
  };
  std::size_t seen = 0;
  for (const std::string& stage : stages) {
    for (const auto& [file, included] : includes_below(root / "harness" / "src" / stage)) {
      const std::string folder = included.substr(0, included.find('/'));
      if (included.find('/') == std::string::npos || rank(folder) == long(stages.size())) {
        continue; // not a stage: pldamp/..., a third-party header
      }
      ++seen;
      EXPECT_LE(rank(folder), rank(stage)) << file << " (" << stage << ") includes " << included;
    }
  }
  EXPECT_GT(seen, 100u);
}

} // namespace
} // namespace pldamp::harness
