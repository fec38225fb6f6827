// What every command shares, as a user meets it (app/main.cpp and the option helpers of
// app/cli/): mistakes on the command line, numbers in their keys' ranges, outputs that would
// clobber each other or an input, failed writes, inputs without end, summaries.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

TEST_F(Cli, BadOptionsAreBadInput) {
  EXPECT_EQ(run("replay x.jsonl -w 'modules(a); (a.x=1)' --algorithm sideways").code, 2);
  EXPECT_EQ(run("replay " + (dir_ / "missing.jsonl").string() + " -w 'modules(a); (a.x=1)'").code, 2);
  const Result unknown = run("frobnicate");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(
      unknown.err.find("unknown command 'frobnicate' (the commands: run, check, replay, render, session, view, bench"),
      std::string::npos)
      << unknown.err;
  const Result version = run("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_EQ(version.out, "dwatch " DWATCH_VERSION "\n");
  for (const std::string command : {"run ", "render --out x.png ", "replay -w 'modules(a); (a.x=1)' ", "check @"}) {
    const Result folder = run(command + dir_.string());
    EXPECT_EQ(folder.code, 2) << command;
    EXPECT_NE(folder.err.find("Is a directory"), std::string::npos) << command << ": " << folder.err;
  }
  const fs::path c = cases_ / "07_last_last_single";
  const Result unwritable = run("replay " + (c / "trace.jsonl").string() + " -w @" + (c / "watch.txt").string() +
                                " --matches /nonexistent/dir/m.jsonl");
  EXPECT_EQ(unwritable.code, 2);
  EXPECT_NE(unwritable.err.find("--matches: cannot write /nonexistent/dir/m.jsonl: No such file or directory"),
            std::string::npos)
      << unwritable.err;
  EXPECT_EQ(run("").code, 2);
  // A word a command does not take is named as given (CLI11 listed them backwards: "not expected:
  // f --scriptt").
  expect_refused("check --explainn 'modules(a); a.x = 1' f",
                 "dwatch: error: unknown option '--explainn' for 'dwatch check' (dwatch check --help lists what it "
                 "takes)\n");
  const Result extra = run("run a.toml surplus");
  EXPECT_EQ(extra.code, 2);
  EXPECT_NE(extra.err.find("unexpected argument 'surplus' for 'dwatch run'"), std::string::npos) << extra.err;
  // An option given last took the command's own word as its value: the message says which.
  expect_refused("run --record S",
                 "dwatch: error: scenario is required ('--record' took 'S' as its value: give it one of its own, or "
                 "put the option after the command's own words)\n");
  const Result valueless = run("run a.toml --max-live");
  EXPECT_EQ(valueless.code, 2);
  EXPECT_NE(valueless.err.find("dwatch: error: --max-live: 1 required"), std::string::npos) << valueless.err;
  EXPECT_NE(valueless.err.find("takes a value and was given none"), std::string::npos) << valueless.err;
  // CLI11's own checks are said as every mistake is, pointing at the command's --help.
  expect_refused("run a.toml --steps -1",
                 "dwatch: error: --steps: 'steps' must be between 0 and 10000000, not -1 (dwatch run --help lists "
                 "what it takes)\n");
  const Result bench = run("bench nosuch");
  EXPECT_EQ(bench.code, 2);
  EXPECT_EQ(bench.err.rfind("dwatch: error: name: nosuch not in {", 0), 0u) << bench.err;
  EXPECT_NE(bench.err.find("(dwatch bench --help lists what it takes)"), std::string::npos) << bench.err;
  expect_refused("render a.toml --camera-eye 1,2,3,4",
                 "dwatch: error: --camera-eye: At Most 3 required but received 4 (dwatch render --help lists what "
                 "it takes)\n");
  // What a command prints is its answer: printed nowhere, it did not succeed.
  const fs::path err = dir_ / "full_err";
  const int status =
      std::system((std::string(DWATCH_EXE) + " check 'modules(a); a.x = 1' >/dev/full 2>" + err.string()).c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(slurp(err), "dwatch: error: writing standard output failed: No space left on device\n");
  // A watchpoint the user left unnamed is not given a name the user gave another (w2 here).
  const Result named = run("check 'w2=modules(a); a.x = 1' 'modules(a b); a.x = 1'");
  EXPECT_EQ(named.code, 0) << named.err;
  EXPECT_NE(named.out.find("watchpoint w2_ (<watch 2>)"), std::string::npos) << named.out;
  expect_refused("run a.toml --steps 5 --steps 6", "dwatch: error: --steps: given more than once (give it once)\n");
  // An empty value names no file: it was taken as no --matches at all, and nothing was written.
  expect_refused("run a.toml --matches ''", "dwatch: error: --matches: the value is empty\n");
  // A reading the command line made impossible is said as the command line's, at the watchpoint
  // (it was said at the file's `algorithm = ...` line, which the user had not touched).
  const Result reading = run("run " + std::string(DWATCH_SCENARIOS_DIR) + "/leader_election.toml --shape ordered " +
                             "--algorithm distributed");
  EXPECT_EQ(reading.code, 2);
  EXPECT_NE(reading.err.find("leader_election.toml:17:8: error: with --algorithm distributed --shape ordered from the "
                             "command line: shape \"ordered\" needs states = \"simultaneous\""),
            std::string::npos)
      << reading.err;
}

// Every number on the command line takes its TOML key's range and words; none wraps.
TEST_F(Cli, CommandLineNumbersTakeTheRangesOfTheirKeys) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  for (const std::string value : {"-1", "18446744073709551615", "1000001", "0", "1e3", "x"}) {
    const Result r = run("run " + scenario + " --history-mb " + value);
    EXPECT_EQ(r.code, 2) << value << ": " << r.err;
    const std::string expected = value == "1e3" || value == "x"
                                     ? "'history_mb' must be an integer, not '" + value + "'"
                                     : "'history_mb' must be between 1 and 1000000, not " + value;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  // The same words as the scenario key.
  const fs::path bad = write(
      "bad.toml", "history_mb = -1\n[lattice]\nkind = \"ring\"\nsize = [5]\n[[program]]\nname = \"token_ring\"\n");
  EXPECT_NE(run("run " + bad.string()).err.find("'history_mb' must be between 1 and 1000000, not -1"),
            std::string::npos);
  for (const std::string option : {"--seed -1", "--steps -5", "--threads 0", "--threads 4294967297", "--print -1"})
    EXPECT_EQ(run("run " + scenario + " " + option).code, 2) << option;
  EXPECT_EQ(run("render " + scenario + " --out " + (dir_ / "x.png").string() + " --width -1").code, 2);
  EXPECT_EQ(run("replay x.jsonl -w 'modules(a); (a.x=1)' --max-live -1").code, 2);
  for (const char* gib : {"nan", "inf", "-1", "0"})
    EXPECT_EQ(run(std::string("replay x.jsonl -w 'modules(a); (a.x=1)' --max-frame-memory ") + gib).code, 2) << gib;
  EXPECT_EQ(run("bench engine --repeat 0").code, 2);
  EXPECT_EQ(run("replay x.jsonl -w 'modules(a); (a.x=1)' --max-module-steps 0").code, 2);
  // Two lines ten million steps apart: refused at once with the budget, not detected for minutes.
  const fs::path gap = write("gap.jsonl",
                             "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[1,2,3,4,5,6,7,8,9,10,"
                             "11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31,32,33,34,35,36,"
                             "37,38,39,40,41,42,43,44,45,46,47,48,49,50,51,52,53,54,55,56,57,58,59,60,61,62,"
                             "63,64,65,66,67,68,69,70,71,72,73,74,75,76,77,78,79,80,81,82,83,84,85,86,87,88,"
                             "89,90,91,92,93,94,95,96,97,98,99,100]}\n"
                             "{\"t\":9999999,\"m\":0,\"vars\":{},\"nbrs\":[]}\n");
  const Result refused = run("replay " + gap.string() + " -w 'modules(a); (a.x=1)'");
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("its 10000000 steps of 101 modules"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--max-module-steps sets the limit"), std::string::npos) << refused.err;
}

// Two outputs on one file, or an output on an input, in any spelling: bad input before any run.
TEST_F(Cli, OutputsThatWouldClobberEachOtherOrAnInputAreBadInput) {
  const fs::path scenario = dir_ / "s.toml";
  fs::copy_file(kScenarios / "token_ring.toml", scenario);
  const std::string original = slurp(scenario);
  const std::string run_it = "run " + scenario.string() + " --no-progress";
  const fs::path x = dir_ / "x.jsonl";
  fs::create_symlink(x, dir_ / "link.jsonl");
  for (const std::string& outputs : std::vector<std::string>{
           "--matches " + x.string() + " --record " + x.string(), "--matches " + x.string() + " --stats " + x.string(),
           "--matches " + x.string() + " --stats " + (dir_ / "." / "x.jsonl").string(),
           "--matches " + x.string() + " --record " + (dir_ / "link.jsonl").string(), "--stats " + scenario.string(),
           "--render " + scenario.string(), "--matches - --stats /dev/stdout"}) {
    const Result r = run(run_it + " " + outputs);
    EXPECT_EQ(r.code, 2) << outputs << "\n" << r.err;
    EXPECT_TRUE(r.err.find("name one file") != std::string::npos ||
                r.err.find("would overwrite the input") != std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(x)) << "nothing ran: " << outputs;
  }
  EXPECT_EQ(slurp(scenario), original);
  // A trace given to replay, and the watch file beside it.
  ASSERT_EQ(run(run_it + " --record " + x.string()).code, 0);
  const std::string trace = slurp(x);
  const fs::path watch = write("w.watch", "modules(a b); (a.token = 1) and (b.token = 1)");
  const Result r1 = run("replay " + x.string() + " -w @" + watch.string() + " --matches " + x.string());
  EXPECT_EQ(r1.code, 2) << r1.err;
  const Result r2 = run("replay " + x.string() + " -w @" + watch.string() + " --stats " + watch.string());
  EXPECT_EQ(r2.code, 2) << r2.err;
  EXPECT_EQ(slurp(x), trace);
  // /dev/null takes any number of outputs.
  EXPECT_EQ(run(run_it + " --matches /dev/null --stats /dev/null").code, 0);
}

// A write that fails is exit 1 naming the path and the reason, and destroys nothing.
TEST_F(Cli, AFailedWriteNamesThePathAndDestroysNothing) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Result png = run("render " + scenario + " --step 5 --out /dev/full");
  EXPECT_EQ(png.code, 1) << png.err;
  EXPECT_NE(png.err.find("writing /dev/full failed: No space left on device"), std::string::npos) << png.err;
  EXPECT_TRUE(fs::is_character_file("/dev/full")) << "the device node must survive";
  const Result matches = run("run " + scenario + " --no-progress --matches /dev/full");
  EXPECT_EQ(matches.code, 1) << matches.err;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  // A regular file that cannot grow (a file-size limit, SIGXFSZ ignored) keeps its old contents.
  const fs::path old = write("old.png", "old picture");
  const std::string limited = "sh -c 'trap \"\" XFSZ; ulimit -f 2; exec " + std::string(DWATCH_EXE) + " render " +
                              scenario + " --step 5 --out " + old.string() + "'";
  const int status = std::system((limited + " >/dev/null 2>&1").c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(slurp(old), "old picture");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 3) << "no temporary left behind";
}

// dwatch `args` with standard output a pipe nobody reads any more (its read end closed before
// dwatch starts, as `| head -1` leaves it once head has its line): its exit code (-SIGNAL when a
// signal ended it) and stderr.
Result with_closed_pipe(const fs::path& dir, const std::string& args, const std::string& input = "/dev/null") {
  int ends[2];
  if (::pipe(ends) != 0) return {-1, "", "pipe"};
  ::close(ends[0]);
  const fs::path err = dir / "closed_pipe_err";
  const std::string cmd = "exec " + std::string(DWATCH_EXE) + " " + args + " <" + input + " 2>" + err.string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(ends[1], STDOUT_FILENO);
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(ends[1]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status), "", slurp(err)};
}

// A closed pipe is a write that failed: exit 1, said, for every command and whatever writes to
// standard output (a summary, --matches -, answers, --help); never a silent end by SIGPIPE (141).
TEST_F(Cli, AClosedPipeIsAFailedWriteSaid) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const fs::path script = write("s.session", "step\nhash\n");
  const fs::path requests = write("requests", "step\nhash\nstep\n");
  for (const auto& [args, input] : std::vector<std::pair<std::string, std::string>>{
           {"run " + scenario + " --no-progress", "/dev/null"},
           {"run " + scenario + " --no-progress --matches -", "/dev/null"},
           {"replay --help", "/dev/null"},
           {"run --help", "/dev/null"},
           {"check 'modules(a); a.x = 1'", "/dev/null"},
           {"session " + scenario + " --script " + script.string(), "/dev/null"},
           {"session " + scenario + " --protocol", requests.string()}}) {
    const Result r = with_closed_pipe(dir_, args, input);
    EXPECT_EQ(r.code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("dwatch: error: writing standard output failed"), std::string::npos) << args << ": " << r.err;
  }
}

// Standard output redirected to an output's file (`--matches o.txt > o.txt`) would lose the
// summary (the output is committed over it): refused as the session refuses it, before the run.
TEST_F(Cli, AnOutputOntoStandardOutputIsRefusedWhereTheSummaryGoes) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const fs::path o = dir_ / "o.txt";
  for (const std::string option : {"--matches", "--stats", "--record"}) {
    const int status = std::system((std::string(DWATCH_EXE) + " run " + scenario + " --no-progress " + option + " " +
                                    o.string() + " >" + o.string() + " 2>" + (dir_ / "err").string())
                                       .c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << option;
    EXPECT_EQ(slurp(dir_ / "err"), "dwatch: error: " + std::string(option) + " " + o.string() +
                                       " would write where the summary goes (standard output)\n");
    EXPECT_EQ(slurp(o), "") << "nothing ran";
  }
  // replay's and render's summaries alike.
  const fs::path c = cases_ / "07_last_last_single";
  for (const std::string& command :
       {"replay " + (c / "trace.jsonl").string() + " -w @" + (c / "watch.txt").string() + " --matches ",
        "render " + scenario + " --step 1 --out "}) {
    const int status = std::system(
        (std::string(DWATCH_EXE) + " " + command + o.string() + " >" + o.string() + " 2>" + (dir_ / "err").string())
            .c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << command;
    EXPECT_NE(slurp(dir_ / "err").find("would write where the summary goes (standard output)"), std::string::npos)
        << command << ": " << slurp(dir_ / "err");
  }
  const Result through_proc = run("run " + scenario + " --no-progress --matches /proc/self/fd/1");
  EXPECT_EQ(through_proc.code, 2) << through_proc.err;
  EXPECT_NE(through_proc.err.find("would write where the summary goes (standard output)"), std::string::npos)
      << through_proc.err;
  // Standard output elsewhere, or the matches on it (the summary then goes to stderr): as before.
  EXPECT_EQ(run("run " + scenario + " --no-progress --matches " + o.string()).code, 0);
  const Result on_stdout = run("run " + scenario + " --no-progress --matches -");
  EXPECT_EQ(on_stdout.code, 0) << on_stdout.err;
  EXPECT_NE(on_stdout.err.find("token_from_nowhere"), std::string::npos) << on_stdout.err;
}

TEST_F(Cli, InputsWithoutEndAreRefusedAtTheirLimit) {
  // Each would grow to gigabytes if read whole.
  const std::string scenario = (dir_ / "z.toml").string();
  std::ofstream(scenario) << "[lattice]\nkind = \"line\"\nsize = [3]\n[[program]]\nscript = \"/dev/zero\"\n";
  for (const std::string& command :
       std::vector<std::string>{"check @/dev/zero", "run /dev/zero", "run " + scenario,
                                "session " + (kScenarios / "token_ring.toml").string() + " --script /dev/zero",
                                "replay /dev/zero --watch 'modules(a);a.token=1'"}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_NE(r.err.find("a NUL byte at line 1, column 1: it is not a text file"), std::string::npos)
        << command << ": " << r.err;
  }
  const Result endless = run("session " + (kScenarios / "token_ring.toml").string() + " --script - < /dev/urandom");
  EXPECT_EQ(endless.code, 2);
  EXPECT_NE(endless.err.find("cannot read standard input: "), std::string::npos) << endless.err;
}

// Summaries count what is there: present modules, not lattice cells; no empty lists.
TEST_F(Cli, SummariesSayWhatIsThere) {
  const Result slide = run("run " + (kScenarios / "slide.toml").string() + " --no-progress --steps 10");
  EXPECT_NE(slide.out.find(": 16 modules (cubic 12x1x2, 8 cells left empty)"), std::string::npos) << slide.out;
  const Result none = run("run " + (kScenarios / "token_ring.toml").string() + " --no-progress --steps 0");
  EXPECT_EQ(none.code, 0) << none.err;
  EXPECT_EQ(none.out.find("by slots filled"), std::string::npos) << none.out;
  const fs::path counted = write("count.toml",
                                 "[lattice]\nkind = \"ring\"\nsize = [8]\n[[program]]\nname = \"token_ring\"\n"
                                 "[[watch]]\nname = \"tokens\"\ntext = \"modules(a); (a.token = 1)\"\n"
                                 "action = \"count\"\n");
  const Result render = run("render " + counted.string() + " --step 3 --out " + (dir_ / "c.png").string());
  EXPECT_EQ(render.code, 0) << render.err;
  EXPECT_NE(render.out.find("tokens only counts its matches (action = \"count\")"), std::string::npos) << render.out;
  // What a count watchpoint counted is in the match log, never a 0: one token per step, 20 steps.
  const Result ran =
      run("run " + counted.string() + " --no-progress --steps 20 --matches " + (dir_ / "c.jsonl").string());
  EXPECT_NE(ran.out.find("tokens [distributed, count]: 20 matches"), std::string::npos) << ran.out;
  EXPECT_EQ(slurp(dir_ / "c.jsonl"), "{\"watch\":\"tokens\",\"counted\":20}\n");
  const fs::path trace = write("t.jsonl", "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[1,2]}\n");
  const Result replay = run("replay " + trace.string() + " -w 'modules(a); (a.x = 1)'");
  EXPECT_NE(replay.out.find("1 lines, 1 steps, 1 modules (and 2 named only as neighbours)"), std::string::npos)
      << replay.out;
}

}  // namespace
