// `dwatch session` as a command (app/cli/session_command.cpp): its script is an input like any
// other. (The session language's own tests: tests/shell/.)
#include <gtest/gtest.h>

#include <string>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

// A session script piped in from a file is an input too: neither its name nor the standard input's
// may be recorded over.
TEST_F(Cli, ASessionScriptPipedInFromAFileIsNotOverwritten) {
  for (const std::string target : {"piped.session", "/proc/self/fd/0"}) {
    const fs::path script =
        write("piped.session", "step 2\nrecord " + (target[0] == '/' ? target : (dir_ / target).string()) + "\n");
    const std::string before = slurp(script);
    const Result r = run("session " + (fs::path(DWATCH_SCENARIOS_DIR) / "token_ring.toml").string() + " --script - < " +
                         script.string());
    EXPECT_NE(r.err.find("would overwrite the input /dev/stdin"), std::string::npos) << target << ": " << r.err;
    EXPECT_EQ(slurp(script), before) << target;
  }
}

}  // namespace
