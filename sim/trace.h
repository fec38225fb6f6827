// Traces in wptrace v1 (DESIGN §5): JSON Lines, one line per present module per step,
//   {"t":3,"m":17,"vars":{"x1":0,"isLeader":1},"nbrs":[16,18,27]}
// after an optional header {"wptrace":1}. A module with no line at a step is absent then.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "watch/frame.h"

namespace dw::sim {

// The whole trace in memory, step-major, in the dense layout the detectors read.
class Trace {
 public:
  // Module ids ascending; variables in order of first appearance.
  const watch::Universe& universe() const { return universe_; }
  int64_t step_count() const { return static_cast<int64_t>(step_frame_.size()); }
  uint64_t line_count() const { return lines_; }
  watch::Frame frame(int64_t step) const;

  // One module's line at one step, as the reader or a recorder adds it.
  struct Entry {
    int64_t t = 0;
    watch::ModuleId m = 0;
    std::vector<std::pair<uint32_t, int64_t>> vars;  // (index into the variable names, value)
    std::vector<watch::ModuleId> nbrs;
  };
  // The trace of these lines, or why it cannot be held (more than kMaxTraceBytes of frames).
  static std::variant<Trace, std::string> build(const std::vector<Entry>& entries,
                                                std::vector<std::string> variable_names);
  static constexpr double kMaxTraceBytes = 8.0 * (1ull << 30);

 private:
  struct Step {
    std::vector<uint8_t> present;
    std::vector<int64_t> values;
    std::vector<uint8_t> has_value;
    std::vector<uint32_t> nbr_begin, nbrs;
  };
  watch::Universe universe_;
  std::vector<Step> steps_;             // distinct frames; 0 is the empty one
  std::vector<uint32_t> step_frame_;    // step -> index into steps_
  uint64_t lines_ = 0;
};

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
class TraceWriter {
 public:
  TraceWriter(std::ostream& out, const watch::Universe& universe);
  void write(const watch::Frame& frame);

 private:
  std::ostream& out_;
  const watch::Universe& universe_;
  std::vector<std::string> keys_;  // "name":
  std::string line_;
};

// Writes a trace as wptrace v1, header first, one line per present module per step, through an
// OutputFile. Empty, or the error.
std::string write_trace(const Trace& trace, const std::string& path);

}  // namespace dw::sim
