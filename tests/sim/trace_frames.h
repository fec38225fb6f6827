// Every frame of a trace at once, over all its variables, for tests that hold several frames.
#pragma once

#include <vector>

#include "sim/trace.h"

namespace dw::sim::test {

class TraceFrames {
 public:
  explicit TraceFrames(const Trace& trace)
      : reader_(std::get<FrameReader>(FrameReader::make(trace, std::nullopt, default_frame_budget()))),
        buffers_(static_cast<size_t>(trace.step_count())) {
    for (int64_t s = 0; s < trace.step_count(); ++s) frames_.push_back(reader_.frame(s, buffers_[size_t(s)]));
  }
  const watch::Universe& universe() const { return reader_.universe(); }
  const watch::Frame& frame(int64_t step) const { return frames_[size_t(step)]; }
  const std::vector<watch::Frame>& all() const { return frames_; }

 private:
  FrameReader reader_;
  std::vector<FrameBuffer> buffers_;
  std::vector<watch::Frame> frames_;
};

}  // namespace dw::sim::test
