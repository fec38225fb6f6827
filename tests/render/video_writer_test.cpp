// Videos written frame by frame and read back by a decoder of their own (decoded_video.h): the
// container and codec the name asks for, every frame there in order at its size, pixels within
// what lossy compression changes, and errors that say what is wrong and leave nothing behind.
#include "render/video_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "render/osmesa_context.h"
#include "render/renderer.h"
#include "tests/render/decoded_video.h"
#include "tests/render/test_scenes.h"

namespace dw::render {
namespace {

namespace fs = std::filesystem;

class VideoWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_video_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::unique_ptr<VideoWriter> open(const fs::path& path, VideoSettings settings) {
    auto opened = VideoWriter::open(path.string(), settings);
    if (auto* error = std::get_if<std::string>(&opened)) {
      ADD_FAILURE() << *error;
      return nullptr;
    }
    return std::move(std::get<0>(opened));
  }
  std::string open_error(const fs::path& path, VideoSettings settings) {
    auto opened = VideoWriter::open(path.string(), settings);
    if (auto* error = std::get_if<std::string>(&opened)) return *error;
    return "(opened)";
  }

  fs::path dir_;
};

// Frame i: a grey field with a gradient along its top rows, and a blue square that moves 12 pixels
// a frame, so that each frame differs from the others where the square is.
Image moving_square(int width, int height, int i) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      uint8_t* p = image.pixel(x, y);
      const bool square = x >= 10 + 12 * i && x < 74 + 12 * i && y >= 60 && y < 124;
      const uint8_t ramp = uint8_t(x * 255 / width);
      p[0] = square ? 40 : y < 30 ? ramp : 150;
      p[1] = square ? 90 : y < 30 ? 255 - ramp : 150;
      p[2] = square ? 210 : 150;
      p[3] = 255;
    }
  return image;
}

void expect_moving_squares(const fs::path& path, const char* container, const char* codec, int frames) {
  const test::DecodedVideo v = test::decode_video(path.string());
  ASSERT_EQ(v.error, "") << path;
  EXPECT_EQ(v.container.find(container) != std::string::npos, true) << v.container;
  EXPECT_EQ(v.codec, codec);
  EXPECT_EQ(v.pixel_format, "yuv420p");
  EXPECT_EQ(v.width, 320);
  EXPECT_EQ(v.height, 240);
  EXPECT_NEAR(v.fps, 25, 0.01);
  ASSERT_EQ(int(v.frames.size()), frames);
  for (int i = 0; i < frames; ++i) {
    const double same = test::mean_absolute_difference(v.frames[i], moving_square(320, 240, i));
    EXPECT_LT(same, 3.0) << "frame " << i;
    // In order: the square's pixels are centred where frame i put it.
    int64_t count = 0, sum_x = 0;
    for (int y = 0; y < 240; ++y)
      for (int x = 0; x < 320; ++x) {
        const uint8_t* p = v.frames[i].pixel(x, y);
        if (p[2] > 180 && p[0] < 90) ++count, sum_x += x;
      }
    ASSERT_GT(count, 64 * 64 * 9 / 10) << "frame " << i;
    EXPECT_NEAR(double(sum_x) / double(count), 41.5 + 12 * i, 1.0) << "frame " << i;
    // The square's colour survives (not only its place): 40, 90, 210 at its middle.
    const uint8_t* middle = v.frames[i].pixel(42 + 12 * i, 92);
    EXPECT_NEAR(middle[0], 40, 8) << "frame " << i;
    EXPECT_NEAR(middle[1], 90, 8) << "frame " << i;
    EXPECT_NEAR(middle[2], 210, 8) << "frame " << i;
  }
}

TEST_F(VideoWriterTest, Mp4IsH264AndWebmIsVp9WithEveryFrameInOrder) {
  for (const auto& [name, container, codec] : {std::tuple{"v.mp4", "mp4", "h264"}, {"v.webm", "webm", "vp9"}}) {
    SCOPED_TRACE(name);
    auto video = open(dir_ / name, {320, 240, 25});
    ASSERT_TRUE(video);
    EXPECT_EQ(std::string(video->codec()), std::string(codec) == "h264" ? "H.264" : "VP9");
    for (int i = 0; i < 17; ++i) ASSERT_EQ(video->add_frame(moving_square(320, 240, i)), "");
    EXPECT_EQ(video->frames(), 17);
    EXPECT_FALSE(fs::exists(dir_ / name)) << "nothing at the path before finish()";
    ASSERT_EQ(video->finish(), "");
    expect_moving_squares(dir_ / name, container, codec, 17);
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2) << "no scratch file left";
}

TEST_F(VideoWriterTest, AHighlightedGroupKeepsItsRedOutlineThroughCompression) {
  auto context = OsMesaContext::create();
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<OsMesaContext>>(context)) << std::get<std::string>(context);
  Renderer renderer(std::get<0>(context)->gl());
  Scene plain = test::block(4, 4, 2, {0.55f, 0.63f, 0.72f});
  plain.title = "block";
  Scene highlighted = plain;
  highlighted.modules[5].highlighted = highlighted.modules[6].highlighted = true;
  highlighted.groups.push_back({"w", 1, {"a", "b"}, {5, 6}});
  const Image pictures[] = {renderer.render(plain, 480, 320), renderer.render(highlighted, 480, 320),
                            renderer.render(plain, 480, 320)};
  ASSERT_EQ(test::count_pixels(pictures[0], test::group_red), 0);
  const int64_t red = test::count_pixels(pictures[1], test::group_red);
  ASSERT_GT(red, 200);

  for (const char* name : {"h.mp4", "h.webm"}) {
    SCOPED_TRACE(name);
    auto video = open(dir_ / name, {480, 320, 10});
    ASSERT_TRUE(video);
    for (const Image& picture : pictures) ASSERT_EQ(video->add_frame(picture), "");
    ASSERT_EQ(video->finish(), "");
    const test::DecodedVideo v = test::decode_video((dir_ / name).string());
    ASSERT_EQ(v.error, "");
    ASSERT_EQ(v.frames.size(), 3u);
    for (int i = 0; i < 3; ++i) EXPECT_LT(test::mean_absolute_difference(v.frames[i], pictures[i]), 3.0) << i;
    // The outline and the link: most of their red pixels still red, and none in the plain frames.
    EXPECT_GT(test::count_pixels(v.frames[1], test::group_red), red * 7 / 10);
    EXPECT_LT(test::count_pixels(v.frames[0], test::group_red), red / 50);
    EXPECT_LT(test::count_pixels(v.frames[2], test::group_red), red / 50);
    int64_t in_place = 0;  // red where the rendered picture is red
    for (int y = 0; y < 320; ++y)
      for (int x = 0; x < 480; ++x)
        in_place += test::group_red(pictures[1].pixel(x, y)) && test::group_red(v.frames[1].pixel(x, y));
    EXPECT_GT(in_place, red * 6 / 10);
  }
}

TEST_F(VideoWriterTest, ABadNameSizeOrPathIsRefusedWithTheReason) {
  EXPECT_EQ(open_error(dir_ / "v.avi", {}),
            (dir_ / "v.avi").string() + ": a video's name ends in .mp4 (H.264) or .webm (VP9), not '.avi'");
  EXPECT_NE(open_error(dir_ / "v", {}).find("not nothing"), std::string::npos);
  EXPECT_EQ(open_error(dir_ / "v.MP4", {320, 240, 10}), "(opened)") << "the extension's case does not matter";
  EXPECT_EQ(open_error(dir_ / "odd.mp4", {321, 240, 10}),
            "a video's width and height must be even (H.264 and VP9 keep colour at half resolution, yuv420p), "
            "not 321x240");
  EXPECT_NE(open_error(dir_ / "odd.webm", {320, 239, 10}).find("must be even"), std::string::npos);
  EXPECT_NE(open_error(dir_ / "v.mp4", {320, 240, 0}).find("1 to 240 frames per second, not 0"), std::string::npos);
  EXPECT_NE(open_error(dir_ / "v.mp4", {8, 8, 10}).find("16 to 8192 pixels"), std::string::npos);
  EXPECT_EQ(open_error("/nonexistent/dir/v.mp4", {320, 240, 10}),
            "cannot write /nonexistent/dir/v.mp4: No such file or directory");
  fs::create_directories(dir_ / "d.mp4");
  EXPECT_EQ(open_error(dir_ / "d.mp4", {320, 240, 10}),
            "cannot write " + (dir_ / "d.mp4").string() + ": Is a directory");
  EXPECT_FALSE(fs::exists(dir_ / "v.mp4"));
  EXPECT_FALSE(fs::exists(dir_ / "v.MP4")) << "opened and dropped: nothing written";
}

TEST_F(VideoWriterTest, AFrameOfAnotherSizeSpendsTheWriterAndNothingIsWritten) {
  std::ofstream(dir_ / "old.webm") << "old video";
  auto video = open(dir_ / "old.webm", {320, 240, 10});
  ASSERT_TRUE(video);
  ASSERT_EQ(video->add_frame(moving_square(320, 240, 0)), "");
  const std::string error = video->add_frame(moving_square(322, 240, 1));
  EXPECT_EQ(error, "frame 1 is 322x240, the video 320x240");
  EXPECT_EQ(video->add_frame(moving_square(320, 240, 1)), error);
  EXPECT_EQ(video->finish(), error);
  video.reset();
  std::stringstream kept;
  kept << std::ifstream(dir_ / "old.webm").rdbuf();
  EXPECT_EQ(kept.str(), "old video");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1) << "no temporary left";
}

TEST_F(VideoWriterTest, AVideoDroppedBeforeFinishLeavesTheOldFile) {
  std::ofstream(dir_ / "old.mp4") << "old video";
  {
    auto video = open(dir_ / "old.mp4", {320, 240, 10});
    ASSERT_TRUE(video);
    for (int i = 0; i < 5; ++i) ASSERT_EQ(video->add_frame(moving_square(320, 240, i)), "");
  }
  std::stringstream kept;
  kept << std::ifstream(dir_ / "old.mp4").rdbuf();
  EXPECT_EQ(kept.str(), "old video");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1) << "no temporary left";
  // Finished, it replaces the old file.
  auto video = open(dir_ / "old.mp4", {320, 240, 25});
  ASSERT_TRUE(video);
  for (int i = 0; i < 4; ++i) ASSERT_EQ(video->add_frame(moving_square(320, 240, i)), "");
  ASSERT_EQ(video->finish(), "");
  EXPECT_EQ(video->add_frame(moving_square(320, 240, 4)),
            "the video " + (dir_ / "old.mp4").string() + " is finished: it takes no more frames");
  expect_moving_squares(dir_ / "old.mp4", "mp4", "h264", 4);
}

TEST_F(VideoWriterTest, AVideoWithoutFramesIsAnErrorAndWritesNothing) {
  for (const char* name : {"none.mp4", "none.webm"}) {
    auto video = open(dir_ / name, {320, 240, 10});
    ASSERT_TRUE(video);
    EXPECT_EQ(video->finish(), "the video " + (dir_ / name).string() + " has no frames: nothing written");
    EXPECT_FALSE(fs::exists(dir_ / name));
  }
}

TEST_F(VideoWriterTest, AFailedWriteNamesThePathAndTheReason) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  EXPECT_NE(open_error("/dev/full", {320, 240, 10}).find("not nothing"), std::string::npos);
  fs::create_symlink("/dev/full", dir_ / "full.mp4");
  auto full = open(dir_ / "full.mp4", {320, 240, 10});
  ASSERT_TRUE(full);
  for (int i = 0; i < 3; ++i) ASSERT_EQ(full->add_frame(moving_square(320, 240, i)), "");
  EXPECT_EQ(full->finish(), "writing " + (dir_ / "full.mp4").string() + " failed: No space left on device");
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

}  // namespace
}  // namespace dw::render
