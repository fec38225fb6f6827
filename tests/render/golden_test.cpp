// Golden images (docs/design.md §9): the views a person looks at, drawn by `dwatch render` and compared
// with tests/golden/*.png. A pixel differs when a channel is off by more than kTolerance; an image
// fails when more than kMaxShare of its pixels differ. A failing test writes the actual image and
// a diff (differing pixels red) under DWATCH_GOLDEN_OUT and names them.
//
// Re-bless after an intended change of the picture (and look at every image before committing):
//   scripts/bless-goldens.sh
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <string>

#include "render/image.h"

namespace dw::render {
namespace {

namespace fs = std::filesystem;

constexpr int kTolerance = 16;
constexpr double kMaxShare = 0.001;

struct Golden {
  const char* name;
  const char* scenario;
  const char* args;
};

// The paper's Fig. 2 (two leaders two hops apart, at the first violation) and Fig. 3 (the token
// ring at the duplicated token), a 1,000-module cube coloured by hop distance, and the wall hit
// by a ball mid-motion with every moving pair highlighted; the new bodies: Catoms 3D (spheres on
// the fcc lattice) at the election's violation, Smart Blocks sliding on a plane at a same_cell
// match, 2-D catoms (discs in a vertical plane) climbing a pyramid of them mid-roll.
const Golden kGoldens[] = {
    {"leader_election", "leader_election.toml", "--step 1"},
    {"token_ring", "token_ring.toml", "--step 41"},
    {"cube_distance", "aggregation_routing.toml", "--step 30 --color-by dist"},
    {"push_wall", "push_wall.toml", "--step 80 --highlight all"},
    {"catoms3d", "catoms3d_leader_election.toml", "--step 99"},
    {"smart_blocks", "smart_blocks_flow.toml", "--step 30"},
    {"catoms2d", "catoms2d_climb.toml", "--step 40"},
};

// Names the case in gtest's messages.
void PrintTo(const Golden& g, std::ostream* os) { *os << g.name; }

class GoldenImage : public ::testing::TestWithParam<Golden> {};

TEST_P(GoldenImage, MatchesTheBlessedPicture) {
  const Golden& g = GetParam();
  const fs::path out_dir = DWATCH_GOLDEN_OUT;
  fs::create_directories(out_dir);
  const fs::path actual_path = out_dir / (std::string(g.name) + ".actual.png");
  const fs::path golden_path = fs::path(DWATCH_GOLDEN_DIR) / (std::string(g.name) + ".png");
  const std::string cmd = std::string(DWATCH_EXE) + " render " + DWATCH_SCENARIOS_DIR + "/" + g.scenario + " " +
                          g.args + " --width 800 --height 450 --out " + actual_path.string() + " >/dev/null";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;

  if (const char* bless = std::getenv("DWATCH_BLESS"); bless && std::string(bless) == "1") {
    fs::copy_file(actual_path, golden_path, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "blessed " << golden_path;
  }
  std::string error;
  const auto actual = read_png(actual_path.string(), &error);
  ASSERT_TRUE(actual) << error;
  const auto expected = read_png(golden_path.string(), &error);
  ASSERT_TRUE(expected) << error << " (scripts/bless-goldens.sh makes it)";
  const ImageDifference d = compare_images(*expected, *actual, kTolerance);
  if (!d.same_size || d.share > kMaxShare) {
    const fs::path diff_path = out_dir / (std::string(g.name) + ".diff.png");
    if (d.same_size) write_png(diff_path.string(), d.diff);
    ADD_FAILURE() << std::setprecision(3) << g.name << ": " << d.differing << " pixels (" << d.share * 100
                  << "%) differ by more than " << kTolerance << ", the largest by " << d.largest << "; allowed "
                  << kMaxShare * 100 << "%" << (d.same_size ? "" : " (the sizes differ)")
                  << "\n  expected: " << golden_path.string() << "\n  actual:   " << actual_path.string()
                  << (d.same_size ? "\n  diff:     " + diff_path.string() : "");
  }
}

INSTANTIATE_TEST_SUITE_P(Views, GoldenImage, ::testing::ValuesIn(kGoldens),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace dw::render
