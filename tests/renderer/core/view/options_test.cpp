// The option table (renderer/core/options.hpp) is the one declaration of every render option:
// its defaults are RenderSettings{}'s, each option is on terrain-render's command line and,
// when per frame, a frames CSV column, and set_option checks what the CLI and the CSV accept.
#include <gtest/gtest.h>

#include <algorithm>

#include <fmt/format.h>

#include "renderer/core/frames.hpp"
#include "renderer/core/options.hpp"
#include "terrain/error.hpp"
#include "test_support.hpp"

namespace renderer {
namespace {

TEST(RenderOptions, EachDefaultIsTheLibrarysDefault) {
  const RenderSettings library;
  for (const OptionSpec& o : render_options()) {
    RenderSettings s;
    set_option(s, o, o.default_text);
    EXPECT_EQ(o.get(s), o.get(library)) << "--" << o.name << " " << o.default_text;
  }
  EXPECT_EQ(changed_options(library), "");
}

TEST(RenderOptions, NamesAreUniqueAndEveryOneIsOnTheCommandLineAndInTheCsv) {
  const auto r = terrain::test::run(terrain::test::tool("terrain-render") + " frame --help");
  ASSERT_EQ(r.exit_code, 0);
  std::vector<std::string> names;
  for (const OptionSpec& o : render_options()) {
    names.push_back(o.name);
    EXPECT_NE(r.out.find("--" + o.name + " "), std::string::npos)
        << o.name << " is not in terrain-render frame --help";
    EXPECT_NE(r.out.find(o.group + ":"), std::string::npos) << o.group;
    const auto& cols = frame_columns();
    EXPECT_EQ(std::find(cols.begin(), cols.end(), csv_column(o)) != cols.end(), o.per_frame)
        << o.name;
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
}

// Every bounded number: its ends are accepted, just outside them is refused, on the
// command line (exit 2) as in a frames CSV (per-frame options) as by set_option.
TEST(RenderOptions, RangesAreCheckedAlikeEverywhere) {
  int checked = 0;
  for (const OptionSpec& o : render_options()) {
    if ((o.type != OptionType::Number && o.type != OptionType::Integer) || o.max >= 1e9) continue;
    const double step = o.type == OptionType::Integer ? 1.0 : 0.5;
    for (const double v : {o.min, o.max}) {
      RenderSettings s;
      EXPECT_NO_THROW(set_option(s, o, fmt::format("{}", v))) << o.name << " " << v;
    }
    for (const double v : {o.min - step, o.max + step}) {
      RenderSettings s;
      EXPECT_THROW(set_option(s, o, fmt::format("{}", v)), terrain::Error) << o.name << " " << v;
      if (o.per_frame) {
        const std::string csv = csv_column(o) + "\n" + fmt::format("{}", v) + "\n";
        EXPECT_THROW(parse_frames_csv(csv, {}, "f.csv"), terrain::Error) << o.name << " " << v;
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 20);
  // The command line: one option of each kind, below its range.
  for (const char* bad :
       {"--view-alt 91", "--silhouette-width 0", "--crease-lift -5", "--flow-scale cubic",
        "--background nocolour", "--layers shaded,contours", "--size 8x8"}) {
    const auto r =
        terrain::test::run(terrain::test::tool("terrain-render") + " frame m.ply -o x.png " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
  }
}

TEST(RenderOptions, ChangedOptionsReadBack) {
  RenderSettings s;
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, std::string>>{{"view-alt", "12.5"},
                                                        {"layers", "shaded,creases"},
                                                        {"aliased", "true"},
                                                        {"crease-colour", "red"},
                                                        {"eye", "1 2 3"},
                                                        {"flow-scale", "linear"},
                                                        {"size", "640x480"}})
    set_option(s, *find_option(name), value);
  const std::string line = changed_options(s);
  EXPECT_NE(line.find("--view-alt '12.5'"), std::string::npos) << line;
  EXPECT_NE(line.find("--aliased"), std::string::npos) << line;
  EXPECT_NE(line.find("--eye 1 2 3"), std::string::npos) << line;
  EXPECT_NE(line.find("--size '640x480'"), std::string::npos) << line;
}

}  // namespace
}  // namespace renderer
