// Why over a trace recorded with its messages ("recv", docs/files.md): the trace's cone equals the
// session's, and both equal a happens-before walk of the test's own over the trace's JSON lines.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sim/session.h"
#include "sim/trace_history.h"
#include "sim/why.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

// A run's trace with what each module read at each step, as `run --record-messages` writes it.
std::string recorded_with_messages(Session& session, int64_t steps) {
  std::ostringstream out;
  TraceWriter writer(out, session.model().universe);
  Mailbox read = session.state().inbox;  // what step 0 reads
  session.run_until(steps, [&](const State& s, const StepOutput& o) {
    writer.write(observed_frame(session.model(), s, o), &read);
    read = s.inbox;
  });
  return out.str();
}

// The test's own walk over the JSON lines: the origin of (m, var, t), then each (step, module)
// from which the messages read ("recv") and each module's own steps lead to it.
std::set<std::pair<int64_t, uint32_t>> walk_lines(const std::string& text, uint32_t m, const std::string& var,
                                                  int64_t t, int depth) {
  std::map<std::pair<int64_t, uint32_t>, nlohmann::json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    if (j.contains("t")) lines[{j["t"].get<int64_t>(), j["m"].get<uint32_t>()}] = j;
  }
  int64_t w = t;
  while (w > 0 && lines.at({w, m})["vars"][var] == lines.at({w - 1, m})["vars"][var]) --w;
  std::set<std::pair<int64_t, uint32_t>> cone{{w, m}};
  std::vector<std::pair<int64_t, uint32_t>> todo{{w, m}};
  while (!todo.empty()) {
    const auto [s, x] = todo.back();
    todo.pop_back();
    std::vector<std::pair<int64_t, uint32_t>> causes;
    if (s > 0) causes.emplace_back(s - 1, x);
    for (const auto& r : lines.at({s, x})["recv"])
      causes.emplace_back(r["sent"].get<int64_t>(), r["from"].get<uint32_t>());
    for (const auto& c : causes)
      if (c.first >= w - depth && cone.insert(c).second) todo.push_back(c);
  }
  return cone;
}

TEST(WhyTrace, ATraceWithMessagesAnswersAsTheSessionDid) {
  const auto model = test_programs::gossip_model({LatticeKind::Cubic, {3, 3, 3}}, {}, 11);
  StaticLatticeWorld world;
  Session session(*model, world, {.threads = 2});
  const std::string text = recorded_with_messages(session, 30);
  EXPECT_NE(text.find("\"recv\":[{\"from\":"), std::string::npos);
  auto read = read_trace_text("run.jsonl", text);
  ASSERT_TRUE(std::holds_alternative<Trace>(read));
  const Trace& trace = std::get<Trace>(read);
  ASSERT_TRUE(trace.has_messages());
  int compared = 0;
  for (uint32_t m : {0u, 13u, 26u})
    for (int column : {1, 2})
      for (int64_t t : {12, 29})
        for (int depth = 1; depth <= 4; ++depth)
          for (bool narrow : {false, true}) {
            const auto asked = why_value(session, m, column, t, depth, narrow, {});
            ASSERT_TRUE(asked);
            const ValueAsked value{m, column, t, trace_origin(trace, m, static_cast<uint32_t>(column), t)};
            ASSERT_EQ(value.origin, asked->values[0].asked.origin);
            auto window = trace_window(trace, window_start({&value, 1}, depth), value.origin);
            ASSERT_TRUE(std::holds_alternative<CausalHistory>(window));
            const Cone cone = cone_of(std::get<CausalHistory>(window), {&value, 1}, depth, narrow);
            EXPECT_EQ(cone_json(cone, trace.universe(), {}), cone_json(*asked, model->universe, {}))
                << "module " << m << " column " << column << " t " << t << " depth " << depth << " narrow " << narrow;
            if (!narrow) {
              std::set<std::pair<int64_t, uint32_t>> events;
              for (const ConeEvent& e : cone.events) events.emplace(e.step, e.module);
              EXPECT_EQ(events, walk_lines(text, m, model->universe.variables[size_t(column)], t, depth));
            }
            ++compared;
          }
  EXPECT_EQ(compared, 96);
}

// The lines of a trace after its header.
std::string body(const std::string& text) { return text.substr(text.find('\n') + 1); }

// The session's `record FILE --messages` writes the lines `run --record-messages` writes, the
// cursor staying where it was, and the trace's cones equal the session's `why`; over a branch, the
// header lists the intervention.
TEST(WhyTrace, TheSessionsRecordWithMessagesAnswersAsTheSessionsWhy) {
  const auto model = test_programs::gossip_model({LatticeKind::Cubic, {3, 3, 3}}, {}, 5);
  StaticLatticeWorld world;
  Session session(*model, world, {.threads = 2});
  const std::string ran = recorded_with_messages(session, 24);
  ASSERT_TRUE(session.seek(6));
  std::ostringstream recorded;
  ASSERT_EQ(record_with_messages(session, recorded, {}), "");
  EXPECT_EQ(session.current(), 6);
  EXPECT_EQ(body(recorded.str()), body(ran));
  auto read = read_trace_text("session.jsonl", recorded.str());
  ASSERT_TRUE(std::holds_alternative<Trace>(read));
  const Trace& trace = std::get<Trace>(read);
  ASSERT_TRUE(trace.has_messages());
  for (uint32_t m : {13u, 4u})
    for (int64_t t : {11, 23})
      for (bool narrow : {false, true}) {
        const auto asked = why_value(session, m, 1, t, 3, narrow, {});
        ASSERT_TRUE(asked);
        const auto answered = why_in_trace(trace, model->universe.id(m), model->universe.variables[1], t, 3, narrow);
        ASSERT_TRUE(std::holds_alternative<Cone>(answered));
        EXPECT_EQ(cone_json(std::get<Cone>(answered), trace.universe(), {}), cone_json(*asked, model->universe, {}))
            << "module " << m << " t " << t << " narrow " << narrow;
      }

  // A branch: module 13's variable 1 set at the start of step 11.
  ASSERT_TRUE(session.seek(10));
  ASSERT_EQ(session.intervene(Intervention{.module = 13, .column = 1, .value = 99}), "");
  session.run_until(24);
  std::ostringstream branch;
  ASSERT_EQ(record_with_messages(session, branch, {}), "");
  EXPECT_NE(branch.str().find("\"interventions\":[{"), std::string::npos);
  EXPECT_NE(branch.str().find("\"recv\":[{\"from\":"), std::string::npos);
  // The trace names the intervention as the writer of the value it set, as the session does.
  auto branched = read_trace_text("branch.jsonl", branch.str());
  ASSERT_TRUE(std::holds_alternative<Trace>(branched));
  for (int64_t t : {11, 14})
    for (bool narrow : {false, true}) {
      const auto asked = why_value(session, 13, 1, t, 3, narrow, {});
      ASSERT_TRUE(asked);
      const auto answered =
          why_in_trace(std::get<Trace>(branched), model->universe.id(13), model->universe.variables[1], t, 3, narrow);
      ASSERT_TRUE(std::holds_alternative<Cone>(answered));
      const std::string json = cone_json(std::get<Cone>(answered), std::get<Trace>(branched).universe(), {});
      EXPECT_EQ(json, cone_json(*asked, model->universe, {})) << "t " << t << " narrow " << narrow;
      if (t == 11) {
        EXPECT_NE(json.find("intervention"), std::string::npos) << json;
      }
    }
}

TEST(WhyTrace, ALineReadsBackWhatItRead) {
  const std::string text =
      "{\"t\":0,\"m\":1,\"vars\":{\"x\":0},\"nbrs\":[2],\"recv\":[]}\n"
      "{\"t\":0,\"m\":2,\"vars\":{\"x\":0},\"nbrs\":[1],\"recv\":[]}\n"
      "{\"t\":1,\"m\":1,\"vars\":{\"x\":4},\"nbrs\":[2],\"recv\":[{\"from\":2,\"sent\":0,\"words\":[4,-1]}]}\n";
  auto read = read_trace_text("t.jsonl", text);
  ASSERT_TRUE(std::holds_alternative<Trace>(read));
  const Trace& trace = std::get<Trace>(read);
  const auto line = trace.line_of(1, 0);
  ASSERT_TRUE(line);
  const auto got = trace.received(*line);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(trace.universe().id(got[0].from), 2u);
  EXPECT_EQ(got[0].sent, 0);
  EXPECT_EQ(std::vector<int64_t>(got[0].words.begin(), got[0].words.end()), (std::vector<int64_t>{4, -1}));
  // A malformed "recv" is said so.
  auto bad = read_trace_text("b.jsonl", "{\"t\":0,\"m\":1,\"vars\":{},\"nbrs\":[],\"recv\":[{\"from\":2}]}\n");
  ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(bad));
  EXPECT_NE(std::get<std::vector<TraceError>>(bad)[0].message.find("\"recv\" must be an array"), std::string::npos);
}

}  // namespace
}  // namespace dw::sim
