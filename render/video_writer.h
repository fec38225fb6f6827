// Videos of the 3D view (docs/design.md §9): frames handed over one at a time, as they are drawn,
// each converted and sent to the encoder at once, so that memory does not grow with the video's
// length (the encoder's look-ahead and reference frames: about 100 MiB more at 1280x720, measured
// by `dwatch bench render`). The codec and container follow the file's name:
//
//   .mp4   H.264 (libx264) in MP4: plays everywhere; x264 is GPL-2+ (docs/cli.md, "Videos")
//   .webm  VP9 (libvpx, BSD) in WebM
//
// Both store colour at half resolution (yuv420p), so width and height must be even. The file is
// written as any other output (sim/output_file.h): nothing appears at its path until finish()
// succeeds, and a writer dropped before that, or a process killed meanwhile, leaves the old file
// as it was and no temporary behind. libav* stays inside video_writer.cpp, opened there when the
// first video is written.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <variant>

#include "render/image.h"

namespace dw::render {

struct VideoSettings {
  int width = 1280, height = 720;  // pixels, even, 16..8192
  int fps = 10;                    // frames per second, 1..240
};

class VideoWriter {
 public:
  // Opens a video at `path` for frames of settings' size. The error, when the name's extension is
  // neither .mp4 nor .webm, the settings are out of range (an odd size included), this libavcodec
  // lacks the encoder, or the path cannot be written ("cannot write PATH: REASON").
  static std::variant<std::unique_ptr<VideoWriter>, std::string> open(const std::string& path,
                                                                      const VideoSettings& settings);
  ~VideoWriter();  // without a successful finish(), the file at the path is left as it was
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Encodes `frame` (RGBA, of the settings' size; alpha is ignored) as the next frame. Empty, or
  // the error; after an error the writer is spent: every later call returns that error.
  std::string add_frame(const Image& frame);
  // Encodes what the encoder still holds, completes the container and puts the file in place.
  // Empty, or the error ("writing PATH failed: REASON" for a failed write; a video without
  // frames is an error too, and writes nothing).
  std::string finish();

  int64_t frames() const { return frames_; }  // frames added so far
  const std::string& path() const { return path_; }
  const char* codec() const;  // "H.264" or "VP9"

 private:
  struct Encoder;  // the libav* contexts, the scratch file and the output
  VideoWriter(std::string path, std::unique_ptr<Encoder> encoder);
  std::string fail(std::string error);

  std::string path_;
  std::unique_ptr<Encoder> encoder_;
  int64_t frames_ = 0;
  std::string error_;  // the first error; the writer is spent once it is set
  bool finished_ = false;
};

}  // namespace dw::render
