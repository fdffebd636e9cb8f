// report.html as a person sees it (ctest label browser): the quick scene's report rendered by
// headless Chromium, each plot found on the page and its pixels counted in a screenshot. A plot
// that collapses (an SVG without a size inside an inline-block figure), stays blank or is too
// small to read fails; so does a `nan` anywhere on the page.
//
// The page is measured on an instrumented copy (a script appended that writes each figure's box
// into the DOM, read back by --dump-dom); the screenshot is of the report itself.
#include "cli_run.hpp"
#include "common/process.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Box {
  int x, y, width, height;
};

// Chromium, headless, with its own empty profile and nothing reaching the network.
ProgramRun chromium(const fs::path& profile, std::vector<std::string> arguments) {
  std::vector<std::string> argv{PLDAMP_CHROMIUM,
                                "--headless",
                                "--no-sandbox",
                                "--disable-gpu",
                                "--disable-quic",
                                "--no-first-run",
                                "--disable-background-networking",
                                "--disable-component-update",
                                "--disable-sync",
                                "--hide-scrollbars",
                                "--user-data-dir=" + profile.string()};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return run_program(argv, "", std::chrono::seconds(120));
}

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const {
    return &rgb[3 * (std::size_t(y) * std::size_t(width) + std::size_t(x))];
  }
  bool background(int x, int y) const { // white, or nearly
    const unsigned char* px = at(x, y);
    return px[0] > 245 && px[1] > 245 && px[2] > 245;
  }
  bool coloured(int x, int y) const { // not white, grey or black: a series' colour
    const unsigned char* px = at(x, y);
    return std::max({px[0], px[1], px[2]}) - std::min({px[0], px[1], px[2]}) > 60;
  }
};

Image read_png(const fs::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Image out;
  if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
    return out;
  }
  image.format = PNG_FORMAT_RGB;
  out.rgb.resize(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) == 0) {
    return {};
  }
  out.width = int(image.width);
  out.height = int(image.height);
  return out;
}

TEST(ReportInChromium, EveryPlotIsVisibleAtItsNaturalSize) {
  const fs::path dir = fs::temp_directory_path() / "pldamp-browser-test";
  fs::remove_all(dir);
  fs::create_directories(dir / "profile");
  const testing::CliRun run =
      testing::run({"run", std::string(PLDAMP_DATA_DIR) + "/scenes/quick.toml", "--out",
                    (dir / "out").string()});
  ASSERT_EQ(run.code, 0) << run.err;
  const std::string html = read(dir / "out" / "report.html");
  EXPECT_EQ(html.find("nan"), std::string::npos) << "a NaN reached the page";
  EXPECT_EQ(html.find("gnuplot was not found"), std::string::npos);

  // Measure: each shown <figure>'s box in page pixels, and the page's height.
  const std::string measure = R"(<script>
const shown = [...document.querySelectorAll('figure')].filter(
  f => f.closest('details:not([open])') === null);
const boxes = shown.map(f => {
  const r = f.querySelector('svg').getBoundingClientRect();
  return [Math.round(r.left + scrollX), Math.round(r.top + scrollY), Math.round(r.width),
          Math.round(r.height)].join(' ');
});
const out = document.createElement('pre');
out.id = 'measured';
out.textContent = document.documentElement.scrollHeight + ';' + boxes.join(';');
document.body.appendChild(out);
</script>)";
  std::string instrumented = html;
  instrumented.insert(instrumented.rfind("</body>"), measure);
  std::ofstream(dir / "measure.html") << instrumented;
  const ProgramRun dom = chromium(dir / "profile", {"--window-size=1400,1000", "--dump-dom",
                                                    "file://" + (dir / "measure.html").string()});
  ASSERT_TRUE(dom.succeeded()) << "chromium --dump-dom failed (exit " << dom.exit_code << ")";
  const std::string open = "<pre id=\"measured\">";
  const std::size_t start = dom.out.find(open);
  ASSERT_NE(start, std::string::npos) << dom.out.substr(0, 500);
  const std::size_t end = dom.out.find("</pre>", start);
  ASSERT_NE(end, std::string::npos);
  std::stringstream fields(dom.out.substr(start + open.size(), end - start - open.size()));
  std::string item;
  std::getline(fields, item, ';');
  const int page_height = std::stoi(item);
  std::vector<Box> boxes;
  while (std::getline(fields, item, ';')) {
    std::stringstream numbers(item);
    Box box{};
    numbers >> box.x >> box.y >> box.width >> box.height;
    boxes.push_back(box);
  }
  // quick.toml: 2 work-precision series (e and the worst of all) × 3 p × (time, rhs, extended
  // time), 3 p × the time-step study's e, δ_max and τ, and the map of each solver line's last
  // configuration (7; the other configurations' maps are folded, a click away). A work-precision
  // plot whose every error is 0 (taylor in extended precision at p = 1 may give e exactly) is a
  // line saying so instead.
  std::size_t nothing_to_draw = 0;
  for (std::size_t at = html.find("a point to draw"); at != std::string::npos;
       at = html.find("a point to draw", at + 1)) {
    ++nothing_to_draw;
  }
  EXPECT_LE(nothing_to_draw, 2u);
  EXPECT_EQ(boxes.size() + nothing_to_draw, 2u * 3u * 3u + 3u * 3u + 7u);

  // Look: a screenshot of the whole page, every plot's box inspected.
  const fs::path shot = dir / "shot.png";
  const ProgramRun screenshot =
      chromium(dir / "profile", {"--window-size=1400," + std::to_string(page_height),
                                 "--screenshot=" + shot.string(),
                                 "file://" + (dir / "out" / "report.html").string()});
  ASSERT_TRUE(screenshot.succeeded()) << "chromium --screenshot failed";
  const Image image = read_png(shot);
  ASSERT_EQ(image.width, 1400);
  ASSERT_GE(image.height, page_height - 1);
  for (const Box& box : boxes) {
    // At its natural size (gnuplot's fixed 600-odd by 400 pixels), and inside the page.
    EXPECT_GE(box.width, 600) << box.x << "," << box.y;
    EXPECT_GE(box.height, 380) << box.x << "," << box.y;
    ASSERT_LE(box.x + box.width, image.width);
    ASSERT_LE(box.y + box.height, image.height);
    long ink = 0, colour = 0;
    for (int y = box.y; y < box.y + box.height; ++y) {
      for (int x = box.x; x < box.x + box.width; ++x) {
        ink += image.background(x, y) ? 0 : 1;
        colour += image.coloured(x, y) ? 1 : 0;
      }
    }
    const double share = double(ink) / (double(box.width) * double(box.height));
    // Measured on quick.toml: ink 5 % on work-precision plots, 2.8 % on a panel with a single
    // point, 57 % on error maps; coloured pixels (the data: lines, markers, map cells) about
    // 2000, 150 and 137 000. An empty frame with its axes, grid and a legend entry has 2.7 % ink
    // but only 40 coloured pixels; a collapsed or blank plot has neither.
    EXPECT_GT(share, 0.01) << "plot at " << box.x << "," << box.y << " is blank";
    EXPECT_GE(colour, 100) << "plot at " << box.x << "," << box.y << " shows no data";
    RecordProperty("ink_at_" + std::to_string(box.x) + "_" + std::to_string(box.y),
                   std::to_string(share) + " " + std::to_string(colour));
  }
}

} // namespace
} // namespace pldamp::harness
