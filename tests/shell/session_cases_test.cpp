// `dwatch session` scripts as case files (tests/shell/session_cases/*.session): each names its
// scenario, and after each command its expected answer as a `#> ` comment (compared as JSON);
// `# exit: N` and `# stderr: TEXT` lines give the expected exit code and lines of stderr.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<fs::path> case_files() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(DWATCH_SESSION_CASES_DIR))
    if (e.path().extension() == ".session") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

class SessionCase : public ::testing::TestWithParam<fs::path> {};

TEST_P(SessionCase, AnswersAsExpected) {
  const fs::path script = GetParam();
  std::string scenario;
  int exit_code = 0;
  std::vector<std::string> answers, stderr_lines;
  for (const std::string& line : lines_of(slurp(script))) {
    if (line.rfind("# scenario: ", 0) == 0) scenario = line.substr(12);
    else if (line.rfind("# exit: ", 0) == 0) exit_code = std::stoi(line.substr(8));
    else if (line.rfind("# stderr: ", 0) == 0) stderr_lines.push_back(line.substr(10));
    else if (line.rfind("#> ", 0) == 0) answers.push_back(line.substr(3));
  }
  ASSERT_FALSE(scenario.empty()) << "a case names its scenario: # scenario: NAME.toml";
  const fs::path dir = fs::temp_directory_path() / ("dwatch_session_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // Run from the case's folder, so that the script is named as written and files it writes stay apart.
  const std::string cmd = "cd " + dir.string() + " && cp " + script.string() + " . && " + DWATCH_EXE + " session " +
                          std::string(DWATCH_SCENARIOS_DIR) + "/" + scenario + " --script " +
                          script.filename().string() + " >stdout 2>stderr";
  const int status = std::system(cmd.c_str());
  const std::string out = slurp(dir / "stdout"), err = slurp(dir / "stderr");
  fs::remove_all(dir);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), exit_code) << err;
  const std::vector<std::string> got = lines_of(out);
  ASSERT_EQ(got.size(), answers.size()) << out << err;
  for (size_t i = 0; i < got.size(); ++i) {
    nlohmann::json a = nlohmann::json::parse(got[i]), b = nlohmann::json::parse(answers[i]);
    // How the history is kept depends on the machine's speed; it is checked to be there.
    if (a.contains("history")) {
      EXPECT_GE(a["history"]["keyframes"].get<int>(), 1);
      a.erase("history");
      b.erase("history");
    }
    EXPECT_EQ(a, b) << "answer " << i + 1;
  }
  const std::vector<std::string> err_lines = lines_of(err);
  for (const std::string& expected : stderr_lines)
    EXPECT_NE(std::find(err_lines.begin(), err_lines.end(), expected), err_lines.end())
        << "stderr lacks: " << expected << "\n"
        << err;
}

INSTANTIATE_TEST_SUITE_P(Cases, SessionCase, ::testing::ValuesIn(case_files()),
                         [](const ::testing::TestParamInfo<fs::path>& info) { return info.param.stem().string(); });

}  // namespace
