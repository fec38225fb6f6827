// The window's Record button: a video of the 3D view as the session's steps show, one frame each
// time the shown step changes, drawn at full quality at the size the view had when recording
// began (render/video_writer.h: H.264/MP4 or VP9/WebM by the file's name, streamed to the encoder
// frame by frame, nothing at the path until it is stopped).
#include "app/view/debugger.h"
#include "shell/output_files.h"

namespace dw::view {

void Debugger::start_recording(const std::string& path) {
  if (std::string clash = shell::file_clash(scenario_.inputs, {{"the video", path}}); !clash.empty())
    return status(clash, true);
  // yuv420p: even sizes.
  const render::VideoSettings settings{view_.width & ~1, view_.height & ~1, 10};
  auto opened = render::VideoWriter::open(path, settings);
  if (auto* error = std::get_if<std::string>(&opened)) return status(*error, true);
  video_ = std::move(std::get<std::unique_ptr<render::VideoWriter>>(opened));
  video_settings_ = settings;
  video_step_ = -1;  // the step shown now is the first frame
  status("recording the 3D view to " + path + " (" + std::to_string(settings.width) + "x" +
         std::to_string(settings.height) + ", a frame per step shown)");
}

void Debugger::record_frame() {
  if (!video_ || readout_.at.current == video_step_ || readout_.at.current < 0) return;
  video_step_ = readout_.at.current;
  window_.make_current();
  std::string error;
  try {
    error = video_->add_frame(renderer_->render(camera_scene(), video_settings_.width, video_settings_.height));
  } catch (const render::RenderError& e) {
    error = e.what();
  }
  drawn_key_.clear();  // the renderer drew elsewhere: the view's texture is drawn again
  if (!error.empty()) {
    video_.reset();  // nothing is left at the path
    status("recording stopped: " + error, true);
  }
}

void Debugger::stop_recording() {
  if (!video_) return;
  const std::string error = video_->finish();
  if (error.empty())
    status("recorded " + std::to_string(video_->frames()) + " frames (" + video_->codec() + ") -> " + video_->path());
  else status(error, true);
  video_.reset();
}

}  // namespace dw::view
