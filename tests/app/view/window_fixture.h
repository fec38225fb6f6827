// What the window's tests share: `dwatch view --script` run under Xvfb (xvfb-run) in a directory
// of the test's own, its answers as JSON lines, and `dwatch render` of a step through the camera a
// window screenshot answered with (tests/app/view/debugger_test.cpp, window_debugging_test.cpp).
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "render/image.h"

namespace dw_window_test {

namespace fs = std::filesystem;
using nlohmann::json;

inline constexpr int kTolerance = 16;  // as the golden images (tests/render/golden_test.cpp)

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Outcome {
  int exit_code = -1;
  std::vector<json> answers;
  std::string err;
};

inline const std::string kLeader = std::string(DWATCH_SCENARIOS_DIR) + "/leader_election.toml";

class Window : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_view_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  // Runs `dwatch ARGS` (under Xvfb when `window`), its stdout as JSON lines.
  Outcome dwatch(const std::string& args, const std::string& script, bool window) {
    std::ofstream(dir_ / "script") << script;
    // The X authority file in the test's own directory: xvfb-run then makes no temporary one, whose
    // removal failed now and then (its exit code 5 in place of the command's).
    const std::string prefix =
        window ? "xvfb-run -a -f " + (dir_ / "Xauthority").string() + " -s '-screen 0 1920x1080x24' " : "";
    const std::string cmd =
        "cd " + dir_.string() + " && " + prefix + DWATCH_EXE + " " + args + " --script script >stdout 2>stderr";
    Outcome r;
    const int status = std::system(cmd.c_str());
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::istringstream out(slurp(dir_ / "stdout"));
    for (std::string line; std::getline(out, line);) r.answers.push_back(json::parse(line));
    r.err = slurp(dir_ / "stderr");
    return r;
  }

  // `dwatch render` of step t at w x h through the camera a window screenshot answered with.
  std::optional<dw::render::Image> render_as_shot(const json& shot, int64_t t, int w, int h) {
    const std::string cmd = "cd " + dir_.string() + " && " + DWATCH_EXE + " render " + kLeader + " --step " +
                            std::to_string(t) + " --width " + std::to_string(w) + " --height " + std::to_string(h) +
                            " --camera-eye " + shot["camera_eye"].get<std::string>() + " --camera-target " +
                            shot["camera_target"].get<std::string>() + " --out render.png >/dev/null";
    if (std::system(cmd.c_str()) != 0) return std::nullopt;
    std::string error;
    return dw::render::read_png((dir_ / "render.png").string(), &error);
  }

  fs::path dir_;
};

}  // namespace dw_window_test
