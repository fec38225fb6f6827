// `dwatch run --record-messages` and `dwatch why TRACE M VAR T` as a user meets them
// (app/cli/why_command.cpp, docs/files.md): the trace says what each module read, and why
// answers from it what the session answers.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

TEST_F(Cli, WhyFromATraceWithMessagesAnswersAsTheSession) {
  const std::string scenario = (kScenarios / "leader_election.toml").string();
  const fs::path trace = dir_ / "le.jsonl";
  const Result ran = run("run " + scenario + " --record " + trace.string() + " --record-messages --no-progress");
  ASSERT_EQ(ran.code, 0) << ran.err;  // paused on two leaders
  std::ifstream in(trace);
  std::string header, line;
  std::getline(in, header);
  std::getline(in, line);
  EXPECT_EQ(nlohmann::json::parse(line)["recv"], nlohmann::json::array()) << "step 0 reads nothing";
  const Result why = run("why " + trace.string() + " 7 isLeader 1 --narrow");
  ASSERT_EQ(why.code, 0) << why.err;
  const auto answer = nlohmann::json::parse(why.out);
  // The 1-hop bug: 7 heard its four one-hop neighbours, no one further.
  std::set<int> senders;
  for (const auto& m : answer["messages"]) senders.insert(m["from"].get<int>());
  EXPECT_EQ(senders, (std::set<int>{6, 8, 18, 19}));
  // The session's answer, without its own fields.
  fs::path script = dir_ / "why.session";
  std::ofstream(script) << "run\nwhy 7 isLeader 1 --narrow\n";
  const Result session = run("session " + scenario + " --script " + script.string());
  ASSERT_EQ(session.code, 0) << session.err;
  auto asked = nlohmann::json::parse(session.out.substr(session.out.find("{\"cmd\":\"why\"")));
  for (const char* key : {"cmd", "current", "latest"}) asked.erase(key);
  EXPECT_EQ(answer, asked);
}

TEST_F(Cli, WhySaysWhatItCannotAnswer) {
  const std::string scenario = (kScenarios / "leader_election.toml").string();
  const fs::path plain = dir_ / "plain.jsonl";
  ASSERT_EQ(run("run " + scenario + " --record " + plain.string() + " --no-progress").code, 0);
  Result r = run("why " + plain.string() + " 7 isLeader 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no line has \"recv\""), std::string::npos) << r.err;
  r = run("run " + scenario + " --record-messages");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--record-messages requires --record"), std::string::npos) << r.err;
}

}  // namespace
