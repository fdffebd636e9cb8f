// docs/scenes.md against the scene reader: every table of keys the reader takes
// (scene/keys.hpp) is documented under its heading, key for key, no heading documents a key the
// reader refuses, and the reader's refusals list exactly those tables.
#include "fixtures.hpp"
#include "scene/keys.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <sstream>

namespace pldamp::harness {
namespace {

using testing::valid_scene;
using testing::write_file;

std::string scenes_doc() {
  std::ifstream in(std::filesystem::path(PLDAMP_DATA_DIR) / ".." / "docs" / "scenes.md");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// The keys documented under each heading (lower case, without the #s): the `names` in the first
// cell of the rows of its tables whose header row begins "| key |".
std::map<std::string, std::set<std::string>> documented_keys(const std::string& text) {
  std::map<std::string, std::set<std::string>> out;
  std::istringstream lines(text);
  std::string heading;
  bool key_table = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind('#', 0) == 0) {
      heading = lower(line.substr(line.find_first_not_of('#') + 1));
      key_table = false;
    } else if (line.rfind("| key |", 0) == 0) {
      key_table = true;
      out[heading];
    } else if (line.rfind('|', 0) != 0) {
      key_table = false;
    } else if (key_table) {
      const std::string first = line.substr(1, line.find('|', 1) - 1);
      for (std::size_t at = first.find('`'); at != std::string::npos;) {
        const std::size_t end = first.find('`', at + 1);
        out[heading].insert(first.substr(at + 1, end - at - 1));
        at = first.find('`', end + 1);
      }
    }
  }
  return out;
}

TEST(SceneDocs, EveryTableOfTheReaderIsDocumentedKeyForKey) {
  const std::map<std::string, std::set<std::string>> documented = documented_keys(scenes_doc());
  std::set<std::string> headings;
  for (const scene_keys::KeyTable& table : scene_keys::tables) {
    const std::string heading(table.heading);
    headings.insert(heading);
    const auto found = documented.find(heading);
    ASSERT_NE(found, documented.end()) << "docs/scenes.md has no key table under " << heading;
    const std::set<std::string> keys(table.keys.begin(), table.keys.end());
    EXPECT_EQ(keys.size(), table.keys.size()) << heading << " lists a key twice";
    for (const std::string& key : keys) {
      EXPECT_EQ(found->second.count(key), 1u)
          << "the reader takes " << key << " in " << heading << "; docs/scenes.md does not say";
    }
    for (const std::string& key : found->second) {
      EXPECT_EQ(keys.count(key), 1u)
          << "docs/scenes.md documents " << key << " in " << heading << "; the reader refuses it";
    }
  }
  for (const auto& [heading, keys] : documented) {
    EXPECT_EQ(headings.count(heading), 1u)
        << "docs/scenes.md documents keys under " << heading << ", which is no table of the reader";
  }
}

std::string joined(std::initializer_list<scene_keys::Keys> parts) {
  std::string out;
  for (const scene_keys::Keys keys : parts) {
    for (const std::string_view key : keys) {
      out += out.empty() ? "" : "|";
      out += key;
    }
  }
  return out;
}

// The tables are the reader's: an unknown key is refused with exactly their list.
TEST(SceneDocs, TheReaderRefusesAnUnknownKeyListingItsTable) {
  const std::string grid = "[grid]\np = 1.5\ne = 0.5\nv0 = 1.0\n";
  const std::string claim = "[[claim]]\nname = \"c\"\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"zzz = 1\n" + valid_scene, "the scene, expected " + joined({scene_keys::top_level})},
      {"[grid]\nzzz = 1\np = 1.5\ne = 0.5\nv0 = 1.0\n",
       "[grid], expected " + joined({scene_keys::grid})},
      {valid_scene + "[[solver]]\nname = \"taylor\"\nzzz = 1\n",
       "[[solver]], expected " + joined({scene_keys::solver})},
      {valid_scene + "[[solver]]\ncommand = [\"prog\"]\nzzz = 1\n",
       "[[solver]] with a command, expected " + joined({scene_keys::external_solver})},
      {valid_scene + claim + "observable = \"e\"\nbound = 1\nzzz = 1\n",
       "[[claim]], expected " + joined({scene_keys::claim, scene_keys::bound_claim})},
      {valid_scene + claim + "observable = \"e\"\nbound = 1\nconvention = \"yade\"\nzzz = 1\n",
       "[[claim]], expected " + joined({scene_keys::claim, scene_keys::convention_claim})},
      {grid + claim +
           "kind = \"relation\"\nof = \"truth\"\nquantity = \"e\"\nformula = \"seed_restitution\"\n"
           "relation = \"equal_within\"\ntolerance = 1\nzzz = 1\n",
       "[[claim]] of kind relation, expected " +
           joined({scene_keys::claim, scene_keys::relation_claim})},
      {grid + claim +
           "kind = \"asymptotic\"\nof = \"truth\"\nquantity = \"e\"\nformula = "
           "\"seed_restitution\"\norder = 1\nzzz = 1\n",
       "[[claim]] of kind asymptotic, expected " +
           joined({scene_keys::claim, scene_keys::asymptotic_claim})},
      {grid + claim + "kind = \"recovered_parameter\"\nsolver = \"taylor\"\nbound = 1\nzzz = 1\n",
       "[[claim]] of kind recovered_parameter, expected " +
           joined({scene_keys::claim, scene_keys::recovered_parameter_claim})},
      {grid + claim +
           "kind = \"stability\"\nsolver = \"dem-verlet\"\nformula = \"seed_dt_crit\"\nzzz = 1\n",
       "[[claim]] of kind stability, expected " +
           joined({scene_keys::claim, scene_keys::stability_claim})},
      {valid_scene + "[[search]]\nzzz = 1\n",
       "[[search]], expected " + joined({scene_keys::search})},
      {valid_scene + "[[figure]]\nzzz = 1\n",
       "[[figure]], expected " + joined({scene_keys::figure})},
      {valid_scene + "[[figure]]\nkind = \"restitution_approximations\"\nsolver = \"taylor\"\n",
       "[[figure]] restitution_approximations, expected " +
           joined({scene_keys::restitution_figure})},
      {grid + "[[trajectory]]\nzzz = 1\n",
       "[[trajectory]], expected " + joined({scene_keys::trajectory})},
      {valid_scene + "[report]\nzzz = 1\n", "[report], expected " + joined({scene_keys::report})},
      {valid_scene + "[timing]\nzzz = 1\n", "[timing], expected " + joined({scene_keys::timing})},
      {valid_scene + "[limits]\nzzz = 1\n", "[limits], expected " + joined({scene_keys::limits})},
      {valid_scene + "[diff]\nzzz = 1\n", "[diff], expected " + joined({scene_keys::diff})},
  };
  for (const auto& [text, refusal] : cases) {
    try {
      parse_scene(text, "keys.toml");
      ADD_FAILURE() << "no error for " << text;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(": unknown key in " + refusal + " (got "),
                std::string::npos)
          << e.what();
    }
  }
}

} // namespace
} // namespace pldamp::harness
