// The session's `record FILE --messages` (docs/why.md): the trace of steps 0..latest as the
// session's `record` writes it, each line also saying what its module read at its step ("recv"),
// as `run --record-messages` writes it, so that `dwatch why TRACE ...` answers what the session's
// `why` answers. The messages are not kept on a live run: the cursor walks the history a step at a
// time (each step re-simulated once from keyframe 0) and goes back where it was.
#include "sim/session.h"
#include "sim/trace.h"
#include "sim/watch_hosting.h"
#include "sim/why.h"

namespace dw::sim {

std::string record_with_messages(Session& session, std::ostream& out, const Control& control) {
  if (!session.has_history()) return "the session keeps no history to record";
  const int64_t back = session.current(), latest = session.latest();
  const Model& model = session.model();
  // As the session's `record` writes it: its header lists the branch's interventions and the watchpoints.
  TraceWriter writer(out, model.universe, session.interventions(), specs_of(session.watches().hosted()));
  // The one-step seeks report nothing of their own: the walk reports each step done.
  const Control step_control{.stop = control.stop};
  if (!session.seek(-1, step_control)) return "cancelled";
  Mailbox read = session.state().inbox;  // what step 0 reads
  for (int64_t t = 0; t <= latest; ++t) {
    if (!session.seek(t, step_control)) {
      session.seek(back);
      return "cancelled";
    }
    const State& s = session.state();
    const auto graph = std::make_shared<const NeighborGraph>(session.seen_graph());
    writer.write(make_frame(model, t, s.values, session.seen_present(), graph), &read);
    read = s.inbox;
    if (control.progress) control.progress(t + 1, latest + 1);
  }
  session.seek(back);
  out.flush();
  return out ? std::string{} : "writing the trace failed";
}

}  // namespace dw::sim
