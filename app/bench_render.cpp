// `dwatch bench render`: frames of the headless 3D view (OSMesa, llvmpipe) at 1280x720, drawing
// and reading back, for 1,000 and 10,000 boxes, plain (coloured by a gradient) and with a group
// highlighted (the rest translucent, sorted far to near); and what writing the PNG costs.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "app/bench.h"
#include "render/image.h"
#include "render/osmesa_context.h"
#include "render/palette.h"
#include "render/renderer.h"

namespace dw::app {
namespace {

using Clock = std::chrono::steady_clock;

render::Scene boxes(uint32_t nx, uint32_t ny, uint32_t nz, bool highlight) {
  render::Scene s;
  s.title = "bench";
  const render::ColorScale scale("d", std::vector<int64_t>{0, int64_t(nx + ny + nz)});
  s.legend = scale.legend();
  for (uint32_t z = 0; z < nz; ++z)
    for (uint32_t y = 0; y < ny; ++y)
      for (uint32_t x = 0; x < nx; ++x) {
        render::SceneModule m;
        m.id = sim::ModuleId(s.modules.size());
        m.pose.position = {float(x), float(y), float(z)};
        m.color = scale.color(x + y + z);
        s.modules.push_back(m);
      }
  if (highlight) {
    // A four-slot chain through the middle of the block.
    render::SceneGroup g{"bench", 0, {"a", "b", "c", "d"}, {}};
    const uint32_t mid = nx / 2 + nx * (ny / 2 + ny * (nz / 2));
    for (uint32_t i = 0; i < 4; ++i) {
      g.modules.push_back(mid + i);
      s.modules[mid + i].highlighted = true;
    }
    s.groups.push_back(g);
  }
  return s;
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
    };
    const Case cases[] = {{"1,000 boxes (10x10x10)", 10, 10, 10, false, 50},
                          {"1,000 boxes, a group highlighted", 10, 10, 10, true, 50},
                          {"10,000 boxes (25x20x20)", 25, 20, 20, false, 250},
                          {"10,000 boxes, a group highlighted", 25, 20, 20, true, 250}};
    render::Image last;
    for (const Case& c : cases) {
      const render::Scene scene = boxes(c.nx, c.ny, c.nz, c.highlight);
      last = renderer.render(scene, kWidth, kHeight);  // warm-up: shaders compiled, buffers sized
      std::vector<double> ms;
      for (int f = 0; f < frames; ++f) {
        const auto start = Clock::now();
        last = renderer.render(scene, kWidth, kHeight);
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      }
      std::sort(ms.begin(), ms.end());
      std::cout << std::left << std::setw(40) << c.label << std::right << std::fixed << std::setprecision(1)
                << std::setw(10) << ms.front() << std::setw(12) << ms[ms.size() / 2] << std::setw(11) << c.target
                << (ms[ms.size() / 2] <= c.target ? "  met" : "  MISSED") << "\n";
    }
    const auto path = std::filesystem::temp_directory_path() / ("dwatch_bench_" + std::to_string(::getpid()) + ".png");
    const auto start = Clock::now();
    const bool written = render::write_png(path.string(), last);
    const double png_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    std::filesystem::remove(path);
    if (written) std::cout << "writing that last frame as PNG: " << std::setprecision(1) << png_ms << " ms\n";
  } catch (const render::RenderError& e) {
    std::cerr << "dwatch bench: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace dw::app
