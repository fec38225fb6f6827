// `dwatch session --protocol` driven as another program drives it: a request written, its answer
// read before the next is sent (a controller decides as it goes), over two pipes to the real
// process. Answers carry ids, mistakes are answers, a long run reports progress and stops on
// `cancel`, and the end of the input ends the session.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/app/cli.h"

namespace dw::cli_test {
namespace {

using json = nlohmann::json;

constexpr size_t kTooLong = (size_t{1} << 20) + 10;  // past the protocol's request limit

// dwatch session SCENARIO --protocol, its standard input and output as pipes.
class Protocol {
 public:
  explicit Protocol(const std::string& scenario) {
    int in[2], out[2];
    if (::pipe(in) != 0 || ::pipe(out) != 0) throw std::runtime_error("pipe");
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(in[0], STDIN_FILENO);
      ::dup2(out[1], STDOUT_FILENO);
      ::close(in[1]);
      ::close(out[0]);
      ::execl(DWATCH_EXE, DWATCH_EXE, "session", scenario.c_str(), "--protocol", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(in[0]);
    ::close(out[1]);
    to_ = in[1];
    from_ = out[0];
  }
  ~Protocol() {
    if (to_ >= 0) ::close(to_);
    if (pid_ > 0 && !waited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    ::close(from_);
  }

  void send(const std::string& line) { write(line + "\n"); }
  void write(const std::string& text) {
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = ::write(to_, text.data() + done, text.size() - done);
      ASSERT_GT(n, 0);
      done += size_t(n);
    }
  }
  // The next answer line, waiting at most 20 s for it (nothing when none came).
  std::optional<json> next() {
    for (;;) {
      if (const size_t nl = buffer_.find('\n'); nl != std::string::npos) {
        const std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return json::parse(line);
      }
      pollfd p{from_, POLLIN, 0};
      if (::poll(&p, 1, 20000) <= 0) return std::nullopt;
      char chunk[4096];
      const ssize_t n = ::read(from_, chunk, sizeof chunk);
      if (n <= 0) return std::nullopt;
      buffer_.append(chunk, size_t(n));
    }
  }
  // Closes the input; the exit code.
  int finish() {
    ::close(to_);
    to_ = -1;
    int status = 0;
    ::waitpid(pid_, &status, 0);
    waited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
  bool waited_ = false;
  std::string buffer_;
};

using SessionProtocol = Cli;

TEST_F(SessionProtocol, EachRequestIsAnsweredBeforeTheNextIsSent) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml");
  p.send(R"({"id": 1, "cmd": "run 10"})");
  const auto ran = p.next();
  ASSERT_TRUE(ran) << "no answer while the input stays open";
  EXPECT_EQ((*ran)["id"], 1);
  EXPECT_EQ((*ran)["current"], 10);
  // A plain command line: answered without an id. Its hash is a script's at the same step.
  p.send("hash");
  const auto hash = p.next();
  ASSERT_TRUE(hash);
  EXPECT_FALSE(hash->contains("id"));
  const Result script = run("session " + std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml --script " +
                            write("s.session", "run 10\nhash\n").string());
  ASSERT_EQ(script.code, 0) << script.err;
  EXPECT_EQ((*hash)["hash"], json::parse(script.out.substr(script.out.find('\n') + 1))["hash"]);
  // Mistakes and failures are answers with where and what; the session goes on.
  p.send(R"({"id": "s", "cmd": "seek x"})");
  const auto mistake = p.next();
  ASSERT_TRUE(mistake);
  EXPECT_EQ((*mistake)["id"], "s");
  EXPECT_EQ((*mistake)["error"]["col"], 6);
  EXPECT_EQ((*mistake)["error"]["message"], "T must be an integer between 0 and 10000000, not 'x'");
  EXPECT_NE((*mistake)["error"]["text"].get<std::string>().find("seek x\n     ^"), std::string::npos);
  p.send("seek 500");
  const auto failure = p.next();
  ASSERT_TRUE(failure);
  EXPECT_NE((*failure)["error"]["message"].get<std::string>().find("has not been simulated"), std::string::npos);
  p.send("{\"id\": 3, \"cmd\": ");
  const auto broken = p.next();
  ASSERT_TRUE(broken);
  EXPECT_TRUE(broken->contains("error"));
  p.send("{\"id\": " + std::string(100'000, '[') + std::string(100'000, ']') + ", \"cmd\": \"status\"}");
  const auto deep = p.next();
  ASSERT_TRUE(deep) << "a deep id is refused, not echoed until the stack overflows";
  EXPECT_NE((*deep)["error"]["message"].get<std::string>().find("more than 64 deep"), std::string::npos);
  p.send(std::string(kTooLong, 'x'));
  const auto too_long = p.next();
  ASSERT_TRUE(too_long);
  EXPECT_NE((*too_long)["error"]["message"].get<std::string>().find("longer than"), std::string::npos);
  p.send(R"({"id": "two", "cmd": "step"})");
  const auto stepped = p.next();
  ASSERT_TRUE(stepped);
  EXPECT_EQ((*stepped)["id"], "two");
  EXPECT_EQ((*stepped)["current"], 11);
  EXPECT_EQ(p.finish(), 0) << "the end of the input ends the session";
}

TEST_F(SessionProtocol, ALongRunReportsProgressAndStopsOnCancel) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring_correct.toml");
  p.send(R"({"id": "long", "cmd": "run 10000000"})");
  const auto progress = p.next();
  ASSERT_TRUE(progress);
  ASSERT_TRUE(progress->contains("progress")) << *progress;
  EXPECT_EQ((*progress)["id"], "long");
  EXPECT_GT((*progress)["progress"]["done"], 0);
  EXPECT_EQ((*progress)["progress"]["total"], 10000001);
  p.send(R"({"id": "c", "cmd": "cancel"})");
  std::optional<json> cancel, run;
  while (!cancel || !run) {
    auto a = p.next();
    ASSERT_TRUE(a) << "no answer to the run or the cancel";
    if ((*a)["id"] == "c") cancel = a;
    else if (!a->contains("progress")) run = a;
  }
  EXPECT_EQ((*cancel)["cancelled"], true);
  EXPECT_EQ((*run)["id"], "long");
  EXPECT_EQ((*run)["cancelled"], true);
  EXPECT_LT((*run)["current"], 10000000);
  // The session stands where the run got to, and goes on from there.
  p.send("step");
  const auto stepped = p.next();
  ASSERT_TRUE(stepped);
  EXPECT_EQ((*stepped)["current"], (*run)["current"].get<int64_t>() + 1);
  p.send("cancel");
  const auto idle = p.next();
  ASSERT_TRUE(idle);
  EXPECT_EQ((*idle)["cancelled"], false) << "nothing was running";
  EXPECT_EQ(p.finish(), 0);
}

// A cancel sent with its run, both read before the run starts, stops it (it found nothing under
// way and was lost: the run went on to its end); each cancel takes the oldest request not yet
// answered nor cancelled, so a second one stops the second run, waiting or under way.
TEST_F(SessionProtocol, ACancelSentWithItsRequestStopsIt) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring_correct.toml");
  p.send("status");
  const auto before = p.next();
  ASSERT_TRUE(before);
  int64_t current = (*before)["current"].get<int64_t>();  // where it stands until a run runs
  p.write(R"({"id": "r1", "cmd": "run 10000000"})"
          "\n"
          R"({"id": "c1", "cmd": "cancel"})"
          "\n"
          R"({"id": "r2", "cmd": "run 10000000"})"
          "\n"
          R"({"id": "c2", "cmd": "cancel"})"
          "\n");
  std::map<std::string, json> answers;
  while (answers.size() < 4) {
    auto a = p.next();
    ASSERT_TRUE(a) << "a request sent with its cancel was not stopped";
    if (!a->contains("progress")) answers[(*a)["id"].get<std::string>()] = *a;
  }
  EXPECT_EQ(answers["c1"]["cancelled"], true);
  EXPECT_EQ(answers["c2"]["cancelled"], true);
  for (const char* id : {"r1", "r2"}) {
    const json& run = answers[id];
    if (run.contains("error")) {
      EXPECT_EQ(run["error"]["message"], "cancelled before it ran") << run;
    } else {
      EXPECT_EQ(run["cancelled"], true) << run;
      current = run["current"].get<int64_t>();
      EXPECT_LT(current, 10000000);
    }
  }
  p.send("status");
  const auto status = p.next();
  ASSERT_TRUE(status);
  EXPECT_EQ((*status)["current"], current) << "the session stands where the stopped runs got to";
  p.send("cancel");
  const auto idle = p.next();
  ASSERT_TRUE(idle);
  EXPECT_EQ((*idle)["cancelled"], false) << "every request before it was answered";
  EXPECT_EQ(p.finish(), 0);
}

// A JSON request is answered whatever it holds, as its controller waits for the answer: a blank
// or comment command, or a key given twice (which of the two would run?), is an error answer.
TEST_F(SessionProtocol, EveryJsonRequestIsAnswered) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml");
  for (const std::string blank : {R"({"id": 11, "cmd": ""})", R"({"id": 12, "cmd": "   "})", R"({"cmd": "# c"})"}) {
    p.send(blank);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << blank;
    EXPECT_EQ(answer->value("id", json()), json::parse(blank).value("id", json())) << blank;
    EXPECT_EQ((*answer)["error"]["message"], "a request's command is empty (blank, or a # comment)") << *answer;
  }
  for (const std::string twice :
       {R"({"id": 14, "cmd": "step 1", "cmd": "step 3"})", R"({"id": {"a": 1, "a": 2}, "cmd": "step"})"}) {
    p.send(twice);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << twice;
    EXPECT_NE((*answer)["error"]["message"].get<std::string>().find("gives the key"), std::string::npos) << *answer;
  }
  // An id comes back as sent, or the request is refused: a fraction or an integer past 64 bits
  // would come back rounded (18446744073709551616 as 1.8446744073709552e+19).
  for (const std::string odd : {R"({"id": 18446744073709551616, "cmd": "step"})", R"({"id": 1e2, "cmd": "step"})",
                                R"({"id": [1], "cmd": "step"})", R"({"id": true, "cmd": "step"})"}) {
    p.send(odd);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << odd;
    EXPECT_FALSE(answer->contains("id")) << *answer;
    EXPECT_NE((*answer)["error"]["message"].get<std::string>().find("a request's id is a string or an integer"),
              std::string::npos)
        << *answer;
  }
  for (const std::string kept : {R"({"id": null, "cmd": "status"})", R"({"id": 18446744073709551615, "cmd": "status"})",
                                 R"({"id": -9223372036854775808, "cmd": "status"})"}) {
    p.send(kept);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << kept;
    ASSERT_TRUE(answer->contains("id")) << *answer;
    EXPECT_EQ((*answer)["id"], json::parse(kept)["id"]) << *answer;
    EXPECT_EQ((*answer)["id"].dump(), json::parse(kept)["id"].dump()) << *answer;
  }
  p.send(R"({"id": 15, "cmd": "step"})");
  const auto stepped = p.next();
  ASSERT_TRUE(stepped);
  EXPECT_EQ((*stepped)["id"], 15);
  EXPECT_EQ((*stepped)["current"], 0) << "no refused request ran";
  EXPECT_EQ(p.finish(), 0);
}

// Bytes that are not UTF-8 never end the session (the JSON writer threw on them): a request that
// is not UTF-8 (a surrogate, an overlong form, a code point past U+10FFFF, a stray byte; in a
// command line or in JSON) gets an error answer saying so, at its byte, and nothing of it runs; a
// Lua program's error string holding them is answered with U+FFFD in their place.
TEST_F(SessionProtocol, BytesThatAreNotUtf8AreAnsweredNeverTheEnd) {
  write("bad.lua",
        "program = { vars = { 'x' } }\nfunction init(m) end\n"
        "function step(m) if m.step == 2 then error('bad \\xff\\xed\\xa0\\x80 end') end end\n");
  const fs::path scenario = write(
      "bad.toml", "name = 'bad'\nsteps = 10\n[lattice]\nkind = 'ring'\nsize = [4]\n[[program]]\nscript = 'bad.lua'\n");
  Protocol p(scenario.string());
  const std::string save = "save " + (dir_ / "\xED\xA0\x80.toml").string();
  for (const std::string& request :
       {std::string("\xED\xA0\x80"), save, std::string("step \xE0\x80\xB1"), std::string("seek \xF4\x90\x80\x80"),
        std::string("status \xFF"), std::string("{\"id\": 1, \"cmd\": \"save \xED\xA0\x80.toml\"}")}) {
    p.send(request);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << "no answer to a request that is not UTF-8: the session ended";
    EXPECT_NE((*answer)["error"]["message"].get<std::string>().find("a request is UTF-8 text"), std::string::npos)
        << *answer;
    EXPECT_EQ((*answer)["error"]["col"], request.find_first_of("\xED\xE0\xF4\xFF") + 1) << *answer;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2) << "no file was saved";
  p.send("run 5");
  const auto failed = p.next();
  ASSERT_TRUE(failed) << "no answer to a Lua error that is not UTF-8: the session ended";
  EXPECT_NE((*failed)["error"]["message"].get<std::string>().find("bad \xEF\xBF\xBD\xEF\xBF\xBD"), std::string::npos)
      << *failed;
  p.send("hash");
  const auto hash = p.next();
  ASSERT_TRUE(hash);
  EXPECT_TRUE(hash->contains("hash")) << *hash;
  EXPECT_EQ(p.finish(), 0);
}

// An endless line (`session --protocol < /dev/zero`) is answered when it goes over the limit, not
// at a newline that never comes; the rest of it is skipped and the next request answered.
TEST_F(SessionProtocol, ARequestGoingOverTheLimitIsAnsweredBeforeItsNewline) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml");
  p.write(std::string(kTooLong, '\0'));
  const auto too_long = p.next();
  ASSERT_TRUE(too_long) << "no answer while the line goes on";
  EXPECT_NE((*too_long)["error"]["message"].get<std::string>().find("longer than"), std::string::npos);
  p.write(std::string(kTooLong, '\0'));  // still the same line: skipped, no second answer
  p.send("");
  p.send(R"({"id": 7, "cmd": "step"})");
  const auto stepped = p.next();
  ASSERT_TRUE(stepped);
  EXPECT_EQ((*stepped)["id"], 7);
  EXPECT_EQ((*stepped)["current"], 0);
  EXPECT_EQ(p.finish(), 0);
}

// Requests read from a file (`--protocol < requests`) are an input as a script is: a `record`
// onto that file was written, and replaced the requests.
TEST_F(SessionProtocol, TheRequestsFileIsAnInputNoCommandOverwrites) {
  const fs::path requests = dir_ / "requests";
  const std::string text = "step 2\nrecord " + requests.string() + "\n";
  write("requests", text);
  const Result r =
      run("session " + std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml --protocol < " + requests.string());
  EXPECT_NE(r.out.find(requests.string() + " would overwrite the input /dev/stdin"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(requests), text);
}

// With physics, `state M` names both poses (docs/session.md, "Which pose `state` shows"): `pose`
// after step t's physics, and `nbrs_measured_from`, the one N(m, t) was measured from: the pose
// after step t - 1, at the latest step and at a step sought alike; before step 0, the initial one.
TEST_F(SessionProtocol, StateNamesThePoseTheNeighboursWereMeasuredFrom) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/slide.toml");
  const auto ask = [&](const std::string& line) {
    p.send(line);
    const auto answer = p.next();
    EXPECT_TRUE(answer && !answer->contains("error")) << line << ": " << answer.value_or(json());
    return answer.value_or(json());
  };
  constexpr int kModules = 16;  // a row of 12 and 4 sliders on it
  constexpr int kLast = 12;     // the first slider glides from step 1 to 21
  // state[t + 1][m]: module m's answer at step t: before step 0 (the session's start), at the
  // latest step, then at each step sought.
  std::vector<std::vector<json>> state(kLast + 2);
  const auto ask_all = [&](int t) {
    for (int m = 0; m < kModules; ++m) state[size_t(t + 1)].push_back(ask("state " + std::to_string(m)));
  };
  ask_all(-1);
  ask("unwatch set_off_together");  // no lag: the latest step is current after the run
  ASSERT_EQ(ask("run " + std::to_string(kLast))["latest"], kLast);
  for (int t = kLast; t >= 0; --t) {
    if (t < kLast) ask("seek " + std::to_string(t));
    ask_all(t);
  }
  int moved = 0;
  for (int t = -1; t <= kLast; ++t)
    for (int m = 0; m < kModules; ++m) {
      const json& now = state[size_t(t + 1)][size_t(m)];
      ASSERT_TRUE(now.contains("nbrs_measured_from")) << "step " << t << " module " << m << ": " << now;
      const json& from = now["nbrs_measured_from"];
      const json& before = state[size_t(std::max(t, 0))][size_t(m)]["pose"];  // after step t - 1
      EXPECT_EQ(from["t"], std::max(t - 1, -1)) << "step " << t << " module " << m;
      EXPECT_EQ(from["position"], before["position"]) << "step " << t << " module " << m;
      EXPECT_EQ(from["orientation"], before["orientation"]) << "step " << t << " module " << m;
      moved += now["pose"] != before;
    }
  EXPECT_GE(moved, kLast - 1) << "a slider glides at every step after the first: its two poses differ";
  EXPECT_EQ(p.finish(), 0);
}

// An error for a request that could not be read whole carries the id when one could be read
// before what went wrong (issue 65, 7): JSON cut short, bytes that are not UTF-8 after the id, an
// object nested too deep. One read nowhere gets none.
TEST_F(SessionProtocol, AnUnreadableRequestsErrorCarriesItsIdWhenOneWasRead) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml");
  const std::string deep = std::string(100, '[') + std::string(100, ']');
  const std::vector<std::pair<std::string, json>> requests{
      {R"({"id": 9, "cmd": "step")", 9},
      {"{\"id\": \"x\", \"cmd\": \"step \xFF\"}", "x"},
      {R"({"id": null, "cmd": "step", "more": )" + deep + "}", nullptr},
      {R"({"cmd": "step", "x": [1, {"id": 4}], "id": -3, )", -3},
  };
  for (const auto& [request, id] : requests) {
    p.send(request);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << request;
    EXPECT_TRUE(answer->contains("error")) << *answer;
    ASSERT_TRUE(answer->contains("id")) << request << " -> " << *answer;
    EXPECT_EQ((*answer)["id"], id) << *answer;
  }
  for (const std::string request : {R"({"cmd": "step", "x": {"id": 4})", R"({"id": [1], "cmd": )"}) {
    p.send(request);
    const auto answer = p.next();
    ASSERT_TRUE(answer) << request;
    EXPECT_FALSE(answer->contains("id")) << request << " -> " << *answer;
  }
  EXPECT_EQ(p.finish(), 0);
}

// Requests sent faster than they are answered (`yes hash | dwatch session X --protocol` held
// 7.6 GB in 40 s) wait up to a bound; past it each is refused at once with an error saying so,
// and those that waited are all answered once the long one is cancelled.
TEST_F(SessionProtocol, RequestsPastWhatMayWaitAreRefusedAtOnce) {
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring_correct.toml");
  p.send(R"({"id": "long", "cmd": "run 10000000"})");
  std::string flood;
  for (int i = 0; i < 1200; ++i)
    flood += R"({"id": )" + std::to_string(i) +
             R"(, "cmd": "hash"})"
             "\n";
  p.write(flood);
  std::optional<json> refused;
  while (!refused) {
    auto a = p.next();
    ASSERT_TRUE(a) << "no refusal while the run goes on";
    if (a->contains("error")) refused = a;
  }
  EXPECT_NE((*refused)["error"]["message"].get<std::string>().find("already wait to be answered"), std::string::npos)
      << *refused;
  EXPECT_GE((*refused)["id"], 1000) << "the first requests wait";
  p.send(R"({"id": "c", "cmd": "cancel"})");
  size_t hashes = 1;  // the refusal read above
  bool cancelled = false, ran = false;
  while (hashes < 1200 || !cancelled || !ran) {
    auto a = p.next();
    ASSERT_TRUE(a) << hashes << " of 1200 answered";
    if (a->contains("progress")) continue;
    if ((*a)["id"] == "c") cancelled = true;
    else if ((*a)["id"] == "long") ran = true;
    else ++hashes;
  }
  EXPECT_EQ(p.finish(), 0);
}

// Two watchpoints that explode, one past its own max_live, the other past the whole run's budget
// (issue 62): the session's answers said only "stopped": true. The answer of the step that stopped
// them and `status` say why, with the figure and what raises the budget, as `dwatch run` says it.
TEST_F(SessionProtocol, AWatchpointABudgetStoppedSaysWhyAsRunDoes) {
  const fs::path scenario = write("budget.toml", R"(steps = 4
[lattice]
kind = "hex2d"
size = [12, 10]
[[program]]
name = "leader_election"
bug = true
[[watch]]
name = "own"
text = "modules(a b c); a.isLeader = 0 and b.isLeader = 0 and c.isLeader = 0"
algorithm = "centralized"
shape = "any"
max_live = 30
[[watch]]
name = "many"
text = "modules(a b c); a.isLeader = 0 and b.isLeader = 0 and c.isLeader = 0"
algorithm = "distributed"
shape = "any"
states = "simultaneous"
)");
  const Result ran = run("run " + scenario.string() + " --max-live-all 40");
  ASSERT_EQ(ran.code, 1) << ran.err;
  std::map<std::string, std::string> said;  // what `run` says of each: "dwatch: NAME: stopped: WHY"
  std::istringstream lines(ran.err);
  for (std::string line; std::getline(lines, line);)
    if (const size_t at = line.find(": stopped: "); line.rfind("dwatch: ", 0) == 0 && at != std::string::npos)
      said[line.substr(8, at - 8)] = line.substr(at + 11);
  ASSERT_EQ(said.size(), 2u) << ran.err;
  EXPECT_NE(said["own"].find("more than 30"), std::string::npos) << said["own"];
  EXPECT_NE(said["own"].find("max_live sets the budget"), std::string::npos) << said["own"];
  EXPECT_NE(said["many"].find("budget of 40"), std::string::npos) << said["many"];
  EXPECT_NE(said["many"].find("--max-live-all raises it"), std::string::npos) << said["many"];
  EXPECT_EQ(said["many"].find("max_live sets"), std::string::npos) << "its own budget did not stop it";
  const Result session = run("session " + scenario.string() + " --max-live-all 40 --script " +
                             write("s.session", "step 2\nstatus\nstep 1\n").string());
  ASSERT_EQ(session.code, 0) << session.err;
  std::istringstream answers(session.out);
  std::string line;
  ASSERT_TRUE(std::getline(answers, line));
  const json stepped = json::parse(line);
  ASSERT_TRUE(stepped.contains("stopped")) << stepped;
  ASSERT_EQ(stepped["stopped"].size(), 2u) << stepped;
  for (const json& stop : stepped["stopped"])
    EXPECT_EQ(stop["stop_reason"], said[stop["watch"].get<std::string>()]) << stop;
  ASSERT_TRUE(std::getline(answers, line));
  const json status = json::parse(line);
  for (const json& w : status["watches"]) {
    EXPECT_EQ(w["stopped"], true) << w;
    EXPECT_EQ(w["stop_reason"], said[w["name"].get<std::string>()]) << w;
  }
  ASSERT_TRUE(std::getline(answers, line));
  EXPECT_FALSE(json::parse(line).contains("stopped")) << "a step stopping none says none: " << line;
}

// `record f`, f a FIFO no process reads, blocked for ever, and after `cancel` nothing more was
// answered (issue 62, 4): the cancel ends the wait for a reader at once, and later requests are
// answered.
TEST_F(SessionProtocol, ACancelEndsARecordWaitingForAFifosReader) {
  const fs::path fifo = dir_ / "f";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  Protocol p(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml");
  p.send(R"({"id": "r", "cmd": "record )" + fifo.string() + R"("})");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the record is under way, waiting
  const auto cancelled = std::chrono::steady_clock::now();
  p.send(R"({"id": "c", "cmd": "cancel"})");
  std::map<std::string, json> answers;
  while (answers.size() < 2) {
    auto a = p.next();
    ASSERT_TRUE(a) << "no answer to the record or the cancel";
    answers[(*a)["id"].get<std::string>()] = *a;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - cancelled, std::chrono::seconds(3)) << "the wait went on";
  EXPECT_EQ(answers["c"]["cancelled"], true);
  EXPECT_TRUE(answers["r"].contains("error")) << answers["r"];
  p.send(R"({"id": "h", "cmd": "hash"})");
  const auto hash = p.next();
  ASSERT_TRUE(hash) << "nothing answered after the cancel";
  EXPECT_EQ((*hash)["id"], "h");
  EXPECT_EQ(p.finish(), 0);
}

}  // namespace
}  // namespace dw::cli_test
