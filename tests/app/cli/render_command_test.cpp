// `dwatch render` as a user meets it (app/cli/render_command.cpp): a step's picture with its
// highlighted groups, `run --render`, videos decoded frame by frame, the mistakes.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "render/image.h"
#include "tests/app/cli.h"
#include "tests/render/decoded_video.h"

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

TEST_F(Cli, RenderWritesTheViewAndNamesTheHighlightedGroup) {
  const fs::path png = dir_ / "ring.png";
  const Result r = run("render " + (kScenarios / "token_ring.toml").string() +
                       " --step 41 --width 320 --height 200 --out " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(png_size(png), std::make_pair(320u, 200u));
  EXPECT_NE(r.out.find("1 group highlighted"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("token_from_nowhere t=41: a=7 x=8 b=9"), std::string::npos) << r.out;
}

// OSMesa (LLVM with it, some 45 MiB) is opened only by what draws headless, and libav* (some 22
// MiB more) only by what writes a video: a run that writes neither loads neither. What the
// dynamic loader reports (LD_DEBUG) tells.
TEST_F(Cli, OnlyWhatDrawsLoadsOsMesaAndOnlyVideosLoadLibav) {
  struct Loaded {
    bool osmesa = false, libav = false;
  };
  const auto loaded = [&](const std::string& args) {
    const Result r = run_with_env("LD_DEBUG=files", args);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.out;
    return Loaded{r.err.find("libOSMesa") != std::string::npos, r.err.find("libavcodec") != std::string::npos};
  };
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Loaded run = loaded("run " + scenario + " --steps 5 --no-progress");
  EXPECT_FALSE(run.osmesa);
  EXPECT_FALSE(run.libav);
  EXPECT_FALSE(loaded("check 'modules(a); (a.x = 1)'").osmesa);
  const Loaded picture =
      loaded("render " + scenario + " --step 3 --width 64 --height 48 --out " + (dir_ / "r.png").string());
  EXPECT_TRUE(picture.osmesa);
  EXPECT_FALSE(picture.libav);
  EXPECT_EQ(png_size(dir_ / "r.png"), std::make_pair(64u, 48u));
  const Loaded video =
      loaded("render " + scenario + " --from 0 --to 3 --width 64 --height 48 --video " + (dir_ / "r.webm").string());
  EXPECT_TRUE(video.osmesa);
  EXPECT_TRUE(video.libav);
  EXPECT_GT(fs::file_size(dir_ / "r.webm"), 0u);
}

TEST_F(Cli, RenderHighlightsTheFirstAllOrNoneOfTheGroupsAtTheStep) {
  const std::string le = (kScenarios / "leader_election.toml").string() + " --step 1 --width 64 --height 48 --out " +
                         (dir_ / "le.png").string();
  // `dwatch run` reports 91 matches at step 1 of this scenario.
  EXPECT_NE(run("render " + le).out.find("1 group highlighted"), std::string::npos);
  EXPECT_NE(run("render " + le + " --highlight all").out.find("91 groups highlighted"), std::string::npos);
  EXPECT_NE(run("render " + le + " --highlight none").out.find("0 groups highlighted"), std::string::npos);
}

TEST_F(Cli, RunRenderDrawsThePausedStepAsRenderDoes) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Result ran = run("run " + scenario + " --render " + (dir_ / "run.png").string());
  ASSERT_EQ(ran.code, 0) << ran.err;
  EXPECT_NE(ran.out.find("view of step 41 written to"), std::string::npos) << ran.out;
  ASSERT_EQ(run("render " + scenario + " --step 41 --out " + (dir_ / "render.png").string()).code, 0);
  EXPECT_EQ(slurp(dir_ / "run.png"), slurp(dir_ / "render.png"));
  // Without a pause, the last step.
  const Result last = run("run " + (kScenarios / "token_ring_correct.toml").string() + " --steps 30 --render " +
                          (dir_ / "last.png").string());
  ASSERT_EQ(last.code, 0) << last.err;
  EXPECT_NE(last.out.find("view of step 29 written to"), std::string::npos) << last.out;
}

TEST_F(Cli, RenderMistakesAreBadInput) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Result var = run("render " + scenario + " --color-by nope --out " + (dir_ / "x.png").string());
  EXPECT_EQ(var.code, 2);
  EXPECT_NE(var.err.find("no program has a variable named \"nope\" (there are: token"), std::string::npos) << var.err;
  EXPECT_EQ(run("render " + scenario + " --out /nonexistent/dir/x.png").code, 2);
  EXPECT_EQ(run("render " + scenario + " --out " + (dir_ / "x.png").string() + " --highlight some").code, 2);
  EXPECT_EQ(run("render " + scenario + " --out " + (dir_ / "x.png").string() + " --width 0").code, 2);
  EXPECT_EQ(run("render " + (dir_ / "missing.toml").string() + " --out " + (dir_ / "x.png").string()).code, 2);
  EXPECT_EQ(run("run " + scenario + " --render /nonexistent/dir/x.png").code, 2);
  // A camera that could only draw a blank picture is refused.
  for (const std::string camera :
       {"--camera-eye 1,2,3 --camera-target 1,2,3", "--camera-eye 5,5,0 --camera-target 5,5.000001,0",
        "--camera-eye nan,0,5", "--camera-eye 0,inf,5", "--camera-eye 1e300,0,0", "--camera-target 0,0,-1e7"}) {
    const Result r = run("render " + scenario + " --out " + (dir_ / "x.png").string() + " " + camera);
    EXPECT_EQ(r.code, 2) << camera;
    EXPECT_NE(r.err.find("error: "), std::string::npos) << camera << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  // So is one that sees none of the ensemble once it is run: looking away, or from too far.
  // A target alone too, with the eye fitted from it, on the command line or in [view].
  for (const std::string camera : {"--camera-eye 6,4,30 --camera-target 6,4,100", "--camera-eye 0,0,900000",
                                   "--camera-target 1e6,1e6,1e6", "--camera-target 0,0,-1000"}) {
    const Result r = run("render " + scenario + " --out " + (dir_ / "x.png").string() + " " + camera);
    EXPECT_EQ(r.code, 2) << camera;
    EXPECT_NE(r.err.find("error: the camera at "), std::string::npos) << camera << ": " << r.err;
  }
  const std::string targeted = write("far.toml", slurp(scenario) + "camera_target = [1e6, 1e6, 1e6]\n").string();
  for (const std::string& command : {"render " + targeted + " --out " + (dir_ / "x.png").string(),
                                     "run " + targeted + " --render " + (dir_ / "x.png").string()}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_NE(r.err.find("error: the camera at "), std::string::npos) << command << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// --- dwatch render --video ----------------------------------------------------------------------

// The camera a video was drawn with, from its summary, as render's options.
std::string video_camera(const std::string& out) {
  const size_t at = out.find("  camera: ");
  if (at == std::string::npos) return "";
  return out.substr(at + 10, out.find('\n', at) - at - 10);
}

// Each frame is the step as `render --step T` draws it with the video's camera, which is fitted
// to the first frame; a step with a matched group shows its red outline and links.
TEST_F(Cli, RenderVideoDrawsEachStepAsRenderDoes) {
  namespace video = dw::render::test;
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const std::string size = " --width 640 --height 360";
  const fs::path first = dir_ / "39.png";
  ASSERT_EQ(run("render " + scenario + " --step 39 --out " + first.string() + size).code, 0);
  for (const auto& [name, codec] : {std::pair{"ring.mp4", "h264"}, {"ring.webm", "vp9"}}) {
    SCOPED_TRACE(name);
    const fs::path file = dir_ / name;
    const Result r = run("render " + scenario + " --video " + file.string() + " --from 39 --to 43" + size);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("steps 39..43, 5 frames at 10 frames/s"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 step with a group highlighted"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("first: token_from_nowhere t=41: a=7 x=8 b=9"), std::string::npos) << r.out;
    const video::DecodedVideo v = video::decode_video(file.string());
    ASSERT_EQ(v.error, "");
    EXPECT_EQ(v.codec, codec);
    EXPECT_EQ(v.width, 640);
    EXPECT_EQ(v.height, 360);
    EXPECT_NEAR(v.fps, 10, 0.01);
    ASSERT_EQ(v.frames.size(), 5u);
    // The first frame: step 39 with the fitted camera, as `render --step 39` draws it.
    const auto png = dw::render::read_png(first.string());
    ASSERT_TRUE(png);
    EXPECT_LT(video::mean_absolute_difference(v.frames[0], *png), 4.0);  // another step: 18
    // Step 41 (frame 2), drawn by `render --step 41` with the video's camera.
    const std::string camera = video_camera(r.out);
    ASSERT_NE(camera.find("--camera-eye "), std::string::npos) << r.out;
    const fs::path step41 = dir_ / "41.png";
    ASSERT_EQ(run("render " + scenario + " --step 41 --out " + step41.string() + size + " " + camera).code, 0);
    const auto highlighted = dw::render::read_png(step41.string());
    ASSERT_TRUE(highlighted);
    EXPECT_LT(video::mean_absolute_difference(v.frames[2], *highlighted), 4.0);
    EXPECT_GT(video::mean_absolute_difference(v.frames[1], *highlighted), 10.0) << "frame 1 is another step";
    const int64_t red = video::count_pixels(*highlighted, video::group_red);
    ASSERT_GT(red, 1000);
    EXPECT_GT(video::count_pixels(v.frames[2], video::group_red), red * 3 / 4);
    for (const size_t plain : {0u, 1u, 3u, 4u})
      EXPECT_LT(video::count_pixels(v.frames[plain], video::group_red), red / 20);
  }
  // --fps, and the whole scenario by default.
  const Result all =
      run("render " + scenario + " --video " + (dir_ / "all.mp4").string() + " --fps 25 --width 160 --height 96");
  ASSERT_EQ(all.code, 0) << all.err;
  const video::DecodedVideo whole = video::decode_video((dir_ / "all.mp4").string());
  EXPECT_EQ(whole.frames.size(), 100u) << "token_ring has 100 steps";
  EXPECT_NEAR(whole.fps, 25, 0.01);
}

TEST_F(Cli, RenderVideoMistakesAreBadInputAndWriteNothing) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const std::string video = " --video " + (dir_ / "v.mp4").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {video + " --out " + (dir_ / "x.png").string(), "error: --out and --video are exclusive"},
      {"", "error: render needs --out PNG (one step) or --video FILE.mp4|FILE.webm"},
      {" --video " + (dir_ / "v.avi").string(), "error: --video: " + (dir_ / "v.avi").string() +
                                                    ": a video's name ends in .mp4 (H.264) or .webm (VP9), not '.avi'"},
      {" --video /nonexistent/dir/v.mp4",
       "error: --video: cannot write /nonexistent/dir/v.mp4: No such file or directory"},
      {video + " --width 321", "error: --width 321: a video's width and height must be even"},
      {video + " --height 199", "error: --height 199: a video's width and height must be even"},
      {video + " --step 3", "error: --step is for --out"},
      {video + " --from 9 --to 3", "error: --from 9 is after --to 3"},
      {video + " --from 150", "error: --from 150 is after the last step, 99 (--to)"},
      {" --out " + (dir_ / "x.png").string() + " --from 3", "error: --from, --to and --fps are for --video"},
      {video + " --fps 0", "'fps' must be between 1 and 240, not 0"},
      {" --video - ", "error: --video needs a file name"},
      {" --video " + scenario, "would overwrite the input"},
  };
  for (const auto& [options, message] : cases) {
    const Result r = run("render " + scenario + options);
    EXPECT_EQ(r.code, 2) << options;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << ": " << r.err;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2) << "only stdout and stderr";
}

// A write that fails is exit 1 naming the path and the reason, and leaves no file.
TEST_F(Cli, RenderVideoThatCannotBeWrittenNamesTheReason) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::create_symlink("/dev/full", dir_ / "full.webm");
  const Result r = run("render " + (kScenarios / "token_ring.toml").string() + " --video " +
                       (dir_ / "full.webm").string() + " --to 3 --width 64 --height 48");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("writing " + (dir_ / "full.webm").string() + " failed: No space left on device"),
            std::string::npos)
      << r.err;
}

}  // namespace
