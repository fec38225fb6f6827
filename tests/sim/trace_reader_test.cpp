#include <gtest/gtest.h>

#include "sim/trace.h"
#include "tests/sim/trace_frames.h"

namespace dw::sim {
namespace {

std::vector<TraceError> errors_of(const std::string& text) {
  auto r = read_trace_text("t.jsonl", text);
  if (auto* e = std::get_if<std::vector<TraceError>>(&r)) return *e;
  return {};
}

// The first error, formatted.
std::string first_error(const std::string& text) {
  auto e = errors_of(text);
  return e.empty() ? "no error" : e[0].format();
}

TEST(TraceReader, ReadsModulesVariablesAndNeighbours) {
  auto r = read_trace_text("t", R"({"wptrace":1}
{"t":0,"m":17,"vars":{"x":3,"isLeader":1},"nbrs":[5]}
{"t":0,"m":5,"vars":{"x":-2},"nbrs":[17]}

{"t":2,"m":5,"vars":{},"nbrs":[]}
)");
  ASSERT_TRUE(std::holds_alternative<Trace>(r)) << std::get<std::vector<TraceError>>(r)[0].format();
  const Trace& t = std::get<Trace>(r);
  EXPECT_EQ(t.universe().module_ids, (std::vector<watch::ModuleId>{5, 17}));
  EXPECT_EQ(t.universe().variables, (std::vector<std::string>{"x", "isLeader"}));
  EXPECT_EQ(t.step_count(), 3);
  EXPECT_EQ(t.line_count(), 3u);
  const test::TraceFrames frames(t);
  const watch::Frame& f0 = frames.frame(0);
  EXPECT_EQ(f0.present[0], 1);
  EXPECT_EQ(f0.values[0 * 2 + 0], -2);
  EXPECT_EQ(f0.has_value[0 * 2 + 1], 0) << "module 5 lacks isLeader";
  EXPECT_EQ(f0.values[1 * 2 + 1], 1);
  ASSERT_EQ(f0.neighbors(1).size(), 1u);
  EXPECT_EQ(f0.neighbors(1)[0], 0u) << "neighbours are dense indices";
  const watch::Frame& f1 = frames.frame(1);
  EXPECT_EQ(f1.present[0] + f1.present[1], 0) << "step 1 has no lines: everyone absent";
  EXPECT_EQ(frames.frame(2).present[0], 1);
}

TEST(TraceReader, HeaderIsOptional) {
  auto r = read_trace_text("t", R"({"t":0,"m":0,"vars":{"x":1},"nbrs":[]})");
  EXPECT_TRUE(std::holds_alternative<Trace>(r));
}

TEST(TraceReader, TheHeaderListsTheRunsWatchpointsWithTheirReadings) {
  auto r = read_trace_text(
      "t",
      R"j({"wptrace":1,"watches":[{"name":"w","text":"modules(a); (a.x = 1)","algorithm":"centralized","shape":"any","states":"consistent","action":"count"}]}
{"t":0,"m":0,"vars":{"x":1},"nbrs":[]})j");
  ASSERT_TRUE(std::holds_alternative<Trace>(r)) << std::get<std::vector<TraceError>>(r)[0].format();
  const std::vector<WatchSpec>& watches = std::get<Trace>(r).watches();
  ASSERT_EQ(watches.size(), 1u);
  EXPECT_EQ(to_json(watches[0]).dump(),
            R"j({"name":"w","text":"modules(a); (a.x = 1)","algorithm":"centralized","shape":"any",)j"
            R"("states":"consistent","action":"count"})");
  for (const char* bad : {R"({"wptrace":1,"watches":{}})", R"({"wptrace":1,"watches":[1]})",
                          R"({"wptrace":1,"watches":[{"name":"w"}]})"}) {
    const auto errors = read_trace_text("t", bad);
    ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(errors)) << bad;
    EXPECT_NE(std::get<std::vector<TraceError>>(errors)[0].message.find("\"watches\""), std::string::npos) << bad;
  }
  // As many as a scenario may hold, no more (100,000 took 2.9 GB and minutes).
  std::string many = R"({"wptrace":1,"watches":[)";
  for (size_t i = 0; i <= watch::kMaxWatchpoints; ++i)
    many +=
        std::string(i ? "," : "") + R"({"name":"w)" + std::to_string(i) +
        R"j(","text":"modules(a); (a.x = 1)","algorithm":"centralized","shape":"any","states":"consistent","action":"log"})j";
  const auto too_many = read_trace_text("t", many + "]}\n");
  ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(too_many));
  EXPECT_NE(std::get<std::vector<TraceError>>(too_many)[0].message.find(
                "\"watches\" holds at most 1000 watchpoints, not 1001"),
            std::string::npos);
  const auto late = read_trace_text("t", "{\"t\":0,\"m\":0,\"vars\":{},\"nbrs\":[]}\n{\"watches\":[]}\n");
  ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(late));
  EXPECT_NE(std::get<std::vector<TraceError>>(late)[0].message.find("belongs to the header"), std::string::npos);
}

// A run a pause stopped ends its trace with {"paused":...}; nothing may follow it, and it holds a
// watchpoint's name and a step, nothing else. The watchpoint is one of the header's.
TEST(TraceReader, APausedLineEndsTheTrace) {
  const std::string header =
      R"({"wptrace":1,"watches":[{"name":"w","text":"modules(a); a.x = 1","algorithm":"distributed",)"
      R"("shape":"chain","states":"consistent","action":"log"}]})"
      "\n";
  const std::string frame = "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n";
  auto r = read_trace_text("t", header + frame + "{\"paused\":{\"watch\":\"w\",\"t\":0}}\n\n");
  ASSERT_TRUE(std::holds_alternative<Trace>(r)) << std::get<std::vector<TraceError>>(r)[0].format();
  EXPECT_EQ(std::get<Trace>(r).paused(), (TracePause{"w", 0}));
  EXPECT_FALSE(std::get<Trace>(read_trace_text("t", header + frame)).paused());
  EXPECT_EQ(first_error(header + frame + "{\"paused\":{\"watch\":\"w\",\"t\":0}}\n" + frame),
            "t.jsonl:4:1: error: a line after the {\"paused\":...} line, which ends a trace");
  // A watchpoint the header does not hold, or a trace with no header watchpoints at all.
  EXPECT_EQ(first_error(header + frame + "{\"paused\":{\"watch\":\"v\",\"t\":0}}\n"),
            "t.jsonl:3:2: error: \"paused\" names the watchpoint 'v', which the header's \"watches\" does not hold");
  EXPECT_EQ(first_error(frame + "{\"paused\":{\"watch\":\"w\",\"t\":0}}\n"),
            "t.jsonl:2:2: error: \"paused\" names the watchpoint 'w', which the header's \"watches\" does not hold");
  // A step past the trace's last: the run did not get there.
  EXPECT_EQ(first_error(header + frame + "{\"paused\":{\"watch\":\"w\",\"t\":99999}}\n"),
            "t.jsonl:3:24: error: \"paused\" names step 99999, after the trace's last step, 0");
  EXPECT_EQ(first_error(header + "{\"paused\":{\"watch\":\"w\",\"t\":0}}\n"),
            "t.jsonl:2:24: error: \"paused\" names step 0, and the trace has no step");
  for (const char* bad : {R"({"paused":{"watch":"w"}})", R"({"paused":{"watch":1,"t":0}})", R"({"paused":"w"})",
                          R"({"paused":{"watch":"w","t":0,"x":1}})", R"({"paused":{"watch":"w","t":-1}})",
                          R"({"paused":{"watch":"w","t":0},"t":0})"}) {
    const auto errors = errors_of(header + frame + bad + "\n");
    ASSERT_EQ(errors.size(), 1u) << bad;
    EXPECT_EQ(errors[0].line, 3u) << bad;
    EXPECT_NE(errors[0].message.find("\"paused\""), std::string::npos) << bad << ": " << errors[0].message;
  }
}

// The header's watchpoints are read as the scenario loader reads [[watch]]: each reading and
// action one of its names, every name given and once, no other field; the error points at the
// field and says what it takes.
TEST(TraceReader, TheHeadersWatchpointsAreCheckedAsAScenariosAre) {
  const std::string frame = "\n{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n";
  auto header = [&](const std::string& second) {
    return R"({"wptrace":1,"watches":[{"name":"v","text":"modules(a); a.x = 1","algorithm":"centralized",)"
           R"("shape":"ordered","states":"consistent","action":"log"},{"name":"w","text":"modules(a); a.x = 1",)" +
           second + "}]}" + frame;
  };
  const std::string good = R"("algorithm":"distributed","shape":"chain","states":"consistent","action":"count")";
  ASSERT_EQ(first_error(header(good)), "no error");
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = header(good);
    const size_t at = text.rfind(from);
    return first_error(text.replace(at, from.size(), to));
  };
  EXPECT_EQ(with(R"("distributed")", R"("Centralized")"),
            "t.jsonl:1:189: error: \"algorithm\" must be \"centralized\" or \"distributed\", not \"Centralized\"");
  EXPECT_EQ(with(R"("distributed")", R"("quantum")"),
            "t.jsonl:1:189: error: \"algorithm\" must be \"centralized\" or \"distributed\", not \"quantum\"");
  EXPECT_EQ(with(R"("chain")", R"("blob")"),
            "t.jsonl:1:215: error: \"shape\" must be \"chain\", \"ordered\" or \"any\", not \"blob\"");
  EXPECT_EQ(with(R"("consistent")", R"("weird")"),
            "t.jsonl:1:231: error: \"states\" must be \"consistent\" or \"simultaneous\", not \"weird\"");
  for (const char* action : {R"("explode")", R"("")", R"("Count")"})
    EXPECT_EQ(with(R"("count")", action),
              "t.jsonl:1:253: error: \"action\" must be \"pause\", \"log\" or \"count\", not " + std::string(action));
  EXPECT_EQ(with(R"("count")", R"("count","foo":1)"),
            "t.jsonl:1:270: error: unknown field \"foo\" in a watch of \"watches\" (a watch has \"name\", \"text\", "
            "\"algorithm\", \"shape\", \"states\", \"action\")");
  EXPECT_EQ(with(R"("count")", R"("count","action":"log")"),
            "t.jsonl:1:270: error: duplicate field \"action\" in a watch of \"watches\"");
  EXPECT_EQ(with(R"("name":"w")", R"("name":"v")"), "t.jsonl:1:149: error: a second watchpoint named \"v\"");
  EXPECT_EQ(with(R"("name":"w")", R"("name":"")"), "t.jsonl:1:149: error: a watchpoint's name cannot be empty");
  EXPECT_EQ(with(R"("name":"w")", R"("name":"7")"),
            "t.jsonl:1:149: error: a watchpoint's name is not an integer ('matches 7' would be a step): add a letter");
  // Each name valid, the reading they make together not one that runs: said at the states.
  EXPECT_EQ(with(R"("chain")", R"("ordered")"),
            "t.jsonl:1:233: error: watchpoint \"w\" cannot run: shape \"ordered\" needs states = \"simultaneous\": the "
            "paper's distributed algorithm (consistent states) finds only chains");
  EXPECT_EQ(with(R"("chain","states":"consistent")", R"("ordered","states":"simultaneous")"), "no error");
}

// A header's other fields: what a run writes, nothing else.
TEST(TraceReader, TheHeadersInterventionsAndFieldsAreAsARunWritesThem) {
  const std::string frame = "\n{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n";
  EXPECT_EQ(
      first_error(R"({"wptrace":1,"bogus":1})" + frame),
      "t.jsonl:1:14: error: unknown field \"bogus\" (the header has \"wptrace\", \"interventions\", \"watches\")");
  const std::string valid =
      R"({"wptrace":1,"interventions":[{"at":40,"module":7,"set":{"x":1}},{"at":9,"module":3,"remove":true},)"
      R"({"at":5,"module":0,"push":[0,0,30.5],"scheduled":true}]})";
  EXPECT_EQ(first_error(valid + frame), "no error");
  for (const char* bad : {R"({"at":1,"module":0})", R"({"at":1,"module":0,"set":{"x":1},"remove":true})",
                          R"({"at":1,"module":0,"set":{"x":1.5}})", R"({"at":1,"module":0,"set":{}})",
                          R"({"at":1,"module":0,"remove":false})", R"({"at":1,"module":0,"push":[0,0]})",
                          R"({"module":0,"remove":true})", R"(1)"})
    EXPECT_NE(first_error(R"({"wptrace":1,"interventions":[)" + std::string(bad) + "]}" + frame)
                  .find("error: each of \"interventions\" is {\"at\": STEP"),
              std::string::npos)
        << bad;
  EXPECT_EQ(
      first_error(
          R"({"wptrace":1,"interventions":[{"at":1,"module":0,"remove":true},{"at":-1,"module":0,"remove":true}]})" +
          frame),
      "t.jsonl:1:66: error: \"at\" must be a step in 0..10000000");
  EXPECT_EQ(first_error(R"({"wptrace":1,"interventions":[{"at":1,"module":0,"remove":true,"why":"x"}]})" + frame),
            "t.jsonl:1:64: error: unknown field \"why\" in an intervention (it has \"at\", \"module\", \"set\", "
            "\"remove\", \"push\", \"scheduled\")");
}

TEST(TraceReader, NeighbourWithoutALineIsAnAbsentModule) {
  auto r = read_trace_text("t", R"({"t":0,"m":0,"vars":{},"nbrs":[9]})");
  ASSERT_TRUE(std::holds_alternative<Trace>(r));
  const Trace& t = std::get<Trace>(r);
  EXPECT_EQ(t.universe().module_count(), 2u);
  EXPECT_EQ(t.modules_with_lines(), 1u) << "9 is named, never present";
  EXPECT_EQ(test::TraceFrames(t).frame(0).present[1], 0);
}

TEST(TraceReader, MalformedLineNamesItsLine) {
  EXPECT_EQ(first_error("{\"t\":0,\"m\":0,\"vars\":{},\"nbrs\":[]}\n{\"t\":1,\"m\":0,\"vars\":{},\"nbrs\":[}\n"),
            "t.jsonl:2:1: error: malformed JSON: The JSON document has an improper structure: missing or superfluous "
            "commas, braces, missing keys, etc.");
}

TEST(TraceReader, MissingFieldIsAnError) {
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{}})"), "t.jsonl:1:1: error: missing field \"nbrs\"");
  EXPECT_EQ(first_error(R"({"nbrs":[],"vars":{}})"), "t.jsonl:1:1: error: missing field \"t\", \"m\"");
}

TEST(TraceReader, DuplicateStepAndModuleNamesBothLines) {
  EXPECT_EQ(first_error("{\"t\":0,\"m\":3,\"vars\":{},\"nbrs\":[]}\n{\"t\":1,\"m\":3,\"vars\":{},\"nbrs\":[]}\n"
                        "{\"t\":0,\"m\":3,\"vars\":{},\"nbrs\":[]}"),
            "t.jsonl:3:1: error: duplicate line for module 3 at step 0 (first at line 1)");
  // Found once the lines are read, duplicates are reported in line order among the other errors,
  // each naming the first line of its module and step; past 20, the reader says it stopped.
  const std::string line = "{\"t\":0,\"m\":3,\"vars\":{},\"nbrs\":[]}\n";
  const auto errors = errors_of(line + "{\"t\":0}\n" + line + "x\n" + line);
  ASSERT_EQ(errors.size(), 4u);
  std::vector<uint64_t> lines;
  for (const TraceError& e : errors) lines.push_back(e.line);
  EXPECT_EQ(lines, (std::vector<uint64_t>{2, 3, 4, 5}));
  EXPECT_EQ(errors[3].message, "duplicate line for module 3 at step 0 (first at line 1)");
  std::string many;
  for (int i = 0; i < 30; ++i) many += line;
  const auto capped = errors_of(many);
  ASSERT_EQ(capped.size(), 21u);
  EXPECT_EQ(capped[19].line, 21u);  // lines 2 to 21 repeat line 1
  EXPECT_EQ(capped[20].message, "too many errors; stopping here");
  EXPECT_EQ(capped[20].line, 22u);
}

TEST(TraceReader, NegativeStepPointsAtTheField) {
  EXPECT_EQ(first_error(R"({"t":-1,"m":0,"vars":{},"nbrs":[]})"), "t.jsonl:1:2: error: step \"t\" is negative");
}

TEST(TraceReader, NonIntegerValuesAreErrors) {
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{"x":1.5},"nbrs":[]})"),
            "t.jsonl:1:22: error: variable 'x' must be an integer");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{"x":"1"},"nbrs":[]})"),
            "t.jsonl:1:22: error: variable 'x' must be an integer");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{"x":true},"nbrs":[]})"),
            "t.jsonl:1:22: error: variable 'x' must be an integer");
  EXPECT_EQ(first_error(R"({"t":0.0,"m":0,"vars":{},"nbrs":[]})"), "t.jsonl:1:2: error: step \"t\" must be an integer");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{"x":18446744073709551615},"nbrs":[]})"),
            "t.jsonl:1:22: error: variable 'x' does not fit in a signed 64-bit integer");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{},"nbrs":[1.0]})"),
            "t.jsonl:1:24: error: neighbour id must be an integer");
}

TEST(TraceReader, StructuralMistakes) {
  EXPECT_EQ(first_error(R"([1,2])"), "t.jsonl:1:1: error: expected a JSON object");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":[],"nbrs":[]})"),
            "t.jsonl:1:14: error: \"vars\" must be an object of integer variables");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{},"nbrs":[0]})"),
            "t.jsonl:1:1: error: module 0 lists itself as a neighbour");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{},"nbrs":[1,1]})"),
            "t.jsonl:1:1: error: a neighbour appears twice in \"nbrs\"");
  EXPECT_EQ(first_error(R"({"t":0,"m":-4,"vars":{},"nbrs":[]})"),
            "t.jsonl:1:8: error: module id \"m\" must be in 0..4294967295");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{},"nbrs":[],"pose":[0,0,0]})"),
            "t.jsonl:1:34: error: unknown field \"pose\" (a line has \"t\", \"m\", \"vars\", \"nbrs\")");
  EXPECT_EQ(first_error("{\"t\":0,\"m\":0,\"vars\":{},\"nbrs\":[]}\n{\"wptrace\":1}"),
            "t.jsonl:2:2: error: the {\"wptrace\":1} header may only be the first line");
  EXPECT_EQ(first_error(R"({"wptrace":2})"),
            "t.jsonl:1:2: error: unsupported trace version 2 (this reader reads wptrace 1)");
  EXPECT_EQ(first_error(R"({"t":0,"m":0,"vars":{"x":1,"x":2},"nbrs":[]})"),
            "t.jsonl:1:22: error: variable 'x' appears twice");
}

TEST(TraceReader, EveryBadLineIsReportedNotJustTheFirst) {
  std::string text;
  for (int i = 0; i < 5; ++i) text += "{\"t\":" + std::to_string(i) + ",\"m\":0,\"vars\":{\"x\":0.5},\"nbrs\":[]}\n";
  const auto e = errors_of(text);
  ASSERT_EQ(e.size(), 5u);
  for (size_t i = 0; i < e.size(); ++i) EXPECT_EQ(e[i].line, i + 1);
}

TEST(TraceReader, StopsAfterTwentyErrorsAndSaysSo) {
  std::string text;
  for (int i = 0; i < 100; ++i) text += "nonsense\n";
  const auto e = errors_of(text);
  ASSERT_EQ(e.size(), 21u);
  EXPECT_NE(e.back().message.find("too many errors"), std::string::npos);
}

TEST(TraceReader, MissingFileIsAnError) {
  auto r = read_trace("/nonexistent/trace.jsonl");
  ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(r));
  EXPECT_NE(std::get<std::vector<TraceError>>(r)[0].format().find("/nonexistent/trace.jsonl: error: cannot read"),
            std::string::npos);
}

}  // namespace
}  // namespace dw::sim
