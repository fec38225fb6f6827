// `dwatch bench render`: frames of the headless 3D view (OSMesa, llvmpipe) at 1280x720, drawing
// and reading back, for 1,000 and 10,000 boxes, plain (coloured by a gradient) and with a group
// highlighted (the rest translucent, sorted far to near), and the same drawn as the window draws
// while the camera moves (render::RenderQuality::Moving); what writing the PNG costs; and a video
// of 200 such frames of 1,000 boxes, drawn and encoded as `dwatch render --video` does, in H.264
// and VP9, with the memory it took (frames are streamed, never all held).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "bench/bench.h"
#include "render/image.h"
#include "render/osmesa_context.h"
#include "render/palette.h"
#include "render/renderer.h"
#include "render/video_writer.h"

namespace dw::bench {
namespace {

using Clock = std::chrono::steady_clock;

// A block of boxes coloured by a gradient; `step` moves the gradient on by one and the group
// (a four-slot chain through the middle) by one module along its row, as a step of a run changes
// what the view shows.
render::Scene boxes(uint32_t nx, uint32_t ny, uint32_t nz, bool highlight, uint32_t step = 0) {
  render::Scene s;
  s.title = "bench  \xC2\xB7  step " + std::to_string(step);
  const uint32_t span = nx + ny + nz;
  const render::ColorScale scale("d", std::vector<int64_t>{0, int64_t(span)});
  s.legend = scale.legend();
  for (uint32_t z = 0; z < nz; ++z)
    for (uint32_t y = 0; y < ny; ++y)
      for (uint32_t x = 0; x < nx; ++x) {
        render::SceneModule m;
        m.id = sim::ModuleId(s.modules.size());
        m.pose.position = {float(x), float(y), float(z)};
        m.color = scale.color((x + y + z + step) % span);
        s.modules.push_back(m);
      }
  if (highlight) {
    render::SceneGroup g{"bench", int64_t(step), {"a", "b", "c", "d"}, {}};
    const uint32_t row = nx * (ny / 2 + ny * (nz / 2)), first = step % (nx - 3);
    for (uint32_t i = 0; i < 4; ++i) {
      g.modules.push_back(row + first + i);
      s.modules[row + first + i].highlighted = true;
    }
    s.groups.push_back(g);
  }
  return s;
}

// Resident memory now, in MiB (/proc/self/statm: pages).
double resident_mib() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(::sysconf(_SC_PAGESIZE)) / double(1 << 20);
}

// 200 frames of 1,000 boxes at 1280x720 through a VideoWriter, as `render --video` makes them: one
// printed row with the whole time (the target), its drawing and encoding parts, the file's size,
// and the most memory the process held meanwhile.
bool bench_video(render::Renderer& renderer, const char* extension, int width, int height) {
  constexpr int kFrames = 200;
  constexpr double kTargetSeconds = 10;
  const auto path = std::filesystem::temp_directory_path() / ("dwatch_bench_" + std::to_string(::getpid()) + extension);
  auto opened = render::VideoWriter::open(path.string(), {width, height, 30});
  if (auto* error = std::get_if<std::string>(&opened)) {
    std::cerr << "dwatch bench: error: " << *error << "\n";
    return false;
  }
  render::VideoWriter& video = *std::get<0>(opened);
  const double before = resident_mib();
  double drawing = 0, encoding = 0, peak = before;
  const auto started = Clock::now();
  std::string error;
  for (uint32_t step = 0; step < kFrames && error.empty(); ++step) {
    const render::Scene scene = boxes(10, 10, 10, true, step);
    const auto draw = Clock::now();
    const render::Image frame = renderer.render(scene, width, height);
    const auto encode = Clock::now();
    error = video.add_frame(frame);
    drawing += std::chrono::duration<double>(encode - draw).count();
    encoding += std::chrono::duration<double>(Clock::now() - encode).count();
    peak = std::max(peak, resident_mib());
  }
  const auto finishing = Clock::now();
  if (error.empty()) error = video.finish();
  encoding += std::chrono::duration<double>(Clock::now() - finishing).count();
  const double total = std::chrono::duration<double>(Clock::now() - started).count();
  std::error_code ec;
  const double mib = double(std::filesystem::file_size(path, ec)) / double(1 << 20);
  std::filesystem::remove(path, ec);
  if (!error.empty()) {
    std::cerr << "dwatch bench: error: " << error << "\n";
    return false;
  }
  const double held = double(kFrames) * width * height * 4 / double(1 << 20);
  std::cout << std::left << std::setw(40) << (std::string(video.codec()) + " (" + extension + "), 200 frames")
            << std::right << std::fixed << std::setprecision(1) << std::setw(10) << total << std::setw(12)
            << kTargetSeconds << (total <= kTargetSeconds ? "  met" : "  MISSED") << "   drawing " << drawing
            << " s, encoding " << encoding << " s; " << std::setprecision(2) << mib << " MiB; resident memory "
            << std::setprecision(0) << before << " MiB before, at most " << peak
            << " MiB during (200 frames held: " << held << " MiB more)\n";
  return true;
}

}  // namespace

int bench_render(const BenchArgs& args) {
  auto context = render::OsMesaContext::create();
  if (auto* error = std::get_if<std::string>(&context)) {
    std::cerr << "dwatch bench: error: " << *error << "\n";
    return 1;
  }
  const int frames = std::max(args.repeat, 3) * 4;
  constexpr int kWidth = 1280, kHeight = 720;
  try {
    render::Renderer renderer(std::get<0>(context)->gl());
    std::cout << "bench render: OSMesa (llvmpipe), " << kWidth << "x" << kHeight << ", " << frames
              << " frames per row after one warm-up; ms per frame, drawing and reading back\n"
              << std::left << std::setw(40) << "row" << std::right << std::setw(10) << "best ms" << std::setw(12)
              << "median ms" << std::setw(12) << "target ms\n";
    struct Case {
      const char* label;
      uint32_t nx, ny, nz;
      bool highlight;
      double target;
      render::RenderQuality quality = render::RenderQuality::Full;
    };
    constexpr auto kMoving = render::RenderQuality::Moving;
    const Case cases[] = {{"1,000 boxes (10x10x10)", 10, 10, 10, false, 50},
                          {"1,000 boxes, a group highlighted", 10, 10, 10, true, 16},
                          {"10,000 boxes (25x20x20)", 25, 20, 20, false, 250},
                          {"10,000 boxes, a group highlighted", 25, 20, 20, true, 250},
                          {"1,000 boxes, highlighted, moving", 10, 10, 10, true, 16, kMoving},
                          {"10,000 boxes, highlighted, moving", 25, 20, 20, true, 50, kMoving}};
    render::Image last, last_full;  // the PNG is written from the last full-quality frame
    for (const Case& c : cases) {
      const render::Scene scene = boxes(c.nx, c.ny, c.nz, c.highlight);
      last = renderer.render(scene, kWidth, kHeight, c.quality);  // warm-up: shaders compiled, buffers sized
      std::vector<double> ms;
      for (int f = 0; f < frames; ++f) {
        const auto start = Clock::now();
        last = renderer.render(scene, kWidth, kHeight, c.quality);
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      }
      if (c.quality == render::RenderQuality::Full) last_full = last;
      std::sort(ms.begin(), ms.end());
      std::cout << std::left << std::setw(40) << c.label << std::right << std::fixed << std::setprecision(1)
                << std::setw(10) << ms.front() << std::setw(12) << ms[ms.size() / 2] << std::setw(11) << c.target
                << (ms[ms.size() / 2] <= c.target ? "  met" : "  MISSED") << "\n";
    }
    const auto path = std::filesystem::temp_directory_path() / ("dwatch_bench_" + std::to_string(::getpid()) + ".png");
    const auto start = Clock::now();
    const bool written = render::write_png(path.string(), last_full);
    const double png_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    std::filesystem::remove(path);
    if (written) std::cout << "writing that last frame as PNG: " << std::setprecision(1) << png_ms << " ms\n";
    std::cout << "\nvideo: 200 frames of 1,000 boxes (a group highlighted; colours and group move each frame), "
              << kWidth << "x" << kHeight << ", drawn and encoded as render --video does\n"
              << std::left << std::setw(40) << "row" << std::right << std::setw(10) << "total s" << std::setw(12)
              << "target s\n";
    for (const char* extension : {".mp4", ".webm"})
      if (!bench_video(renderer, extension, kWidth, kHeight)) return 1;
  } catch (const render::RenderError& e) {
    std::cerr << "dwatch bench: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace dw::bench
