// Traces in wptrace v1 (docs/design.md §5): JSON Lines, one line per present module per step,
//   {"t":3,"m":17,"vars":{"x1":0,"isLeader":1},"nbrs":[16,18,27]}
// after an optional header {"wptrace":1}. A module with no line at a step is absent then. A
// recorded run's header also lists its interventions and its watchpoints, with their readings:
//   {"wptrace":1,"watches":[{"name":"w","text":"modules(a); ...","algorithm":"distributed",
//                            "shape":"chain","states":"consistent","action":"log"}]}
// and, when a `pause` watchpoint stopped the run, a last line {"paused":{"watch":"w","t":41}}.
// A run recorded with its messages (`run --record-messages`) gives each line what the module read
// at that step: "recv":[{"from":3,"sent":11,"words":[5,1]}] (docs/files.md).
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "sim/intervention.h"
#include "sim/message.h"
#include "sim/model.h"
#include "sim/watch_spec.h"
#include "watch/frame.h"

namespace dw::sim {

// The pause that stopped a recorded run (its trace's last line): the run ended there without
// deciding its last steps, so a replay of its watchpoints does not decide them either (no drain).
struct TracePause {
  std::string watch;
  int64_t t = 0;  // the match's step
  bool operator==(const TracePause&) const = default;
};

// An intervention the header lists (sim::intervention_json): at step `at`, module `module` (its id)
// had `variable` set to `value`, or was removed, or pushed; `scheduled` when the scenario's own.
struct TraceIntervention {
  int64_t at = 0;
  watch::ModuleId module = 0;
  std::string variable;  // empty but for a set
  int64_t value = 0;
  bool remove = false;
  bool scheduled = false;
  bool operator==(const TraceIntervention&) const = default;
};

// The whole trace in memory, as its lines were: sorted by (step, module), each with its variables
// and neighbours, in flat arrays. Memory is in proportion to what the lines hold, however many
// modules, variables and steps they name; dense frames are made one step at a time (FrameReader).
class Trace {
 public:
  // Every module with a line or named as a neighbour, ids ascending; variables in order of first
  // appearance.
  const watch::Universe& universe() const { return universe_; }
  int64_t step_count() const { return step_count_; }
  uint64_t line_count() const { return line_module_.size(); }
  // Modules that have at least one line (the universe also holds ids named only as neighbours).
  uint32_t modules_with_lines() const { return modules_with_lines_; }

  // A message a module read at a step: its sender's id, the step it was sent, its words.
  struct Received {
    watch::ModuleId from = 0;
    int64_t sent = 0;
    std::vector<int64_t> words;
  };
  // One module's line at one step, as the reader or a recorder adds it.
  struct Entry {
    int64_t t = 0;
    watch::ModuleId m = 0;
    std::vector<std::pair<uint32_t, int64_t>> vars;  // (index into the variable names, value)
    std::vector<watch::ModuleId> nbrs;
    uint64_t line = 0;  // in the file it was read from, for messages
    bool has_recv = false;
    std::vector<Received> recv;
  };
  static Trace build(std::vector<Entry> entries, std::vector<std::string> variable_names);

  // Lines as columns, as a caller's arrays hold them (the Python package's numpy columns): line i
  // is module m[i] at step t[i], with neighbours nbrs[nbr_begin[i] .. nbr_begin[i + 1]) and the
  // value values[v][i] of each variable v. Lines in any order. The trace, or what is wrong with
  // the first bad line ("line 7 (t=3, m=17): ...", lines counted from 0) in the words of the
  // file reader.
  struct Columns {
    std::span<const int64_t> t, m, nbr_begin, nbrs;
    std::vector<std::string> variables;
    std::vector<std::span<const int64_t>> values;
  };
  static std::variant<Trace, std::string> from_columns(const Columns& columns);

  // Ten million steps (eleven days at 10 Hz); every step up to the largest is part of the run.
  static constexpr int64_t kMaxStep = 10'000'000;

  // The watchpoints of the run that recorded it (its header's "watches"): what `replay` with no
  // --watch replays, with the same reading (the budget and optimizations are the default ones).
  const std::vector<WatchSpec>& watches() const { return watches_; }
  void set_watches(std::vector<WatchSpec> watches) { watches_ = std::move(watches); }
  // Whether its lines say what each module read ("recv"); then, the lines of step t ([first,
  // last), in module order), the dense module of a line, and the messages it read: the sender as a
  // dense index, the step sent, the words.
  bool has_messages() const { return !recv_begin_.empty(); }
  std::pair<uint64_t, uint64_t> lines_at(int64_t t) const;
  uint32_t line_module(uint64_t line) const { return line_module_[line]; }
  // Dense module m's line at step t, and the value of variable `var` on a line (none: not there).
  std::optional<uint64_t> line_of(int64_t t, uint32_t m) const;
  std::optional<int64_t> value(uint64_t line, uint32_t var) const;
  struct Read {
    uint32_t from = 0;
    int64_t sent = 0;
    std::span<const int64_t> words;
  };
  std::vector<Read> received(uint64_t line) const;

  // The interventions its header lists (the frames carry their effects; `why` names their writer).
  const std::vector<TraceIntervention>& interventions() const { return interventions_; }
  void set_interventions(std::vector<TraceIntervention> list) { interventions_ = std::move(list); }

  // The pause that stopped the run that recorded it, if one did.
  const std::optional<TracePause>& paused() const { return paused_; }
  void set_paused(std::optional<TracePause> paused) { paused_ = std::move(paused); }

 private:
  friend class FrameReader;
  watch::Universe universe_;
  int64_t step_count_ = 0;
  uint32_t modules_with_lines_ = 0;
  std::vector<int64_t> busy_steps_;    // the steps that have lines, ascending
  std::vector<uint64_t> busy_begin_;   // [busy steps + 1]: each one's first line
  std::vector<uint32_t> line_module_;  // dense module index per line
  std::vector<uint64_t> value_begin_;  // [lines + 1] into value_var_ / value_
  std::vector<uint32_t> value_var_;
  std::vector<int64_t> value_;
  std::vector<uint64_t> nbr_begin_;  // [lines + 1] into nbrs_
  std::vector<uint32_t> nbrs_;       // dense module indices
  std::vector<WatchSpec> watches_;
  std::vector<TraceIntervention> interventions_;
  std::optional<TracePause> paused_;
  // With messages: [lines + 1] into the messages read, each a dense sender, a step and its words.
  std::vector<uint64_t> recv_begin_;
  std::vector<uint32_t> recv_from_;
  std::vector<int64_t> recv_sent_;
  std::vector<uint64_t> recv_words_begin_;  // [messages + 1]
  std::vector<int64_t> recv_words_;
};

// The storage of one dense frame.
struct FrameBuffer {
  std::vector<uint8_t> present;
  std::vector<int64_t> values;
  std::vector<uint8_t> has_value;
  std::vector<uint32_t> nbr_begin, nbrs;
};

// Dense frames of a trace over chosen variables, made one step at a time: what the detectors read.
// A frame holds every module, so its size is modules x chosen variables, refused past a budget.
class FrameReader {
 public:
  // Frames over `variables` (those the trace has; all of the trace's when nothing is given), or
  // why one frame would not fit in `max_frame_bytes`.
  static std::variant<FrameReader, std::string> make(const Trace& trace,
                                                     const std::optional<std::vector<std::string>>& variables,
                                                     double max_frame_bytes);
  // The trace's modules, and the chosen variables as the frames' columns.
  const watch::Universe& universe() const { return universe_; }
  // Step `step` in `buffer`'s storage; the frame is valid while `buffer` is not reused.
  watch::Frame frame(int64_t step, FrameBuffer& buffer) const;
  // The same in the reader's own buffer: valid until the next call.
  watch::Frame frame(int64_t step) { return frame(step, own_); }

 private:
  explicit FrameReader(const Trace& trace) : trace_(&trace) {}
  const Trace* trace_;
  watch::Universe universe_;
  std::vector<int32_t> column_of_;  // trace variable -> frame column, or -1
  FrameBuffer own_;
};

// What a dense frame may take by default: a quarter of the machine's physical memory.
double default_frame_budget();

struct TraceError {
  std::string file;
  uint64_t line = 0;
  uint64_t column = 0;
  std::string message;
  std::string format() const;  // file:line:col: error: message
};

// Reads a trace file. Every bad line is reported (up to a limit); nothing is skipped silently.
std::variant<Trace, std::vector<TraceError>> read_trace(const std::string& path);
std::variant<Trace, std::vector<TraceError>> read_trace_text(const std::string& name, const std::string& text);

// Writes frames as wptrace v1 as they come: the header first, then one line per present module.
// The header lists the interventions the run was made with (its provenance; readers skip them).
class TraceWriter {
 public:
  TraceWriter(std::ostream& out, const watch::Universe& universe, std::span<const Intervention> interventions = {},
              std::span<const WatchSpec> watches = {});
  // `read`, when given, is what the frame's modules read at its step (a runtime's inbox, grouped
  // by receiver in module order): each line then says it under "recv".
  void write(const watch::Frame& frame, const Mailbox* read = nullptr);
  // The last line, when a pause stopped the run.
  void write_paused(const TracePause& pause);

 private:
  std::ostream& out_;
  const watch::Universe& universe_;
  std::vector<std::string> keys_;  // "name":
  std::string line_;
};

// A trace's watchpoints (its header's, Trace::watches) compiled to replay them: each with its
// reading and action, over `base`'s budget and optimizations (the replaying command's), its
// diagnostics naming `trace_path`; or the first one's compile errors.
std::variant<std::vector<HostedWatchpoint>, std::string> hosted_watches(std::span<const WatchSpec> watches,
                                                                        const std::string& trace_path,
                                                                        const watch::DetectorOptions& base);

// Writes a trace as wptrace v1, header first, one line per present module per step, through an
// OutputFile. Empty, or the error.
std::string write_trace(const Trace& trace, const std::string& path);

}  // namespace dw::sim
