#include "render/palette.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dw::render {
namespace {

Color hex(uint32_t rgb) {
  return {float((rgb >> 16) & 0xff) / 255, float((rgb >> 8) & 0xff) / 255, float(rgb & 0xff) / 255};
}

constexpr std::array<uint32_t, 10> kTableau10 = {0x4E79A7, 0xF28E2B, 0x59A14F, 0xE15759, 0xB07AA1,
                                                 0x76B7B2, 0xEDC948, 0xFF9DA7, 0x9C755F, 0xBAB0AC};
constexpr std::array<uint32_t, 10> kViridis = {0x440154, 0x482878, 0x3E4A89, 0x31688E, 0x26828E,
                                               0x1F9E89, 0x35B779, 0x6DCD59, 0xB4DE2C, 0xFDE725};

}  // namespace

Color category_color(size_t index) { return hex(kTableau10[index % kTableau10.size()]); }

Color gradient_color(double s) {
  s = std::clamp(s, 0.0, 1.0) * (kViridis.size() - 1);
  const size_t i = std::min(size_t(s), kViridis.size() - 2);
  const float f = float(s - double(i));
  const Color a = hex(kViridis[i]), b = hex(kViridis[i + 1]);
  return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
}

ColorScale::ColorScale(std::string variable, std::span<const int64_t> values) : variable_(std::move(variable)) {
  if (values.empty()) return;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  min_ = *lo;
  max_ = *hi;
}

Color ColorScale::color(int64_t value) const {
  if (categorical()) return category_color(size_t(std::clamp(value, min_, max_) - min_));
  return gradient_color(double(value - min_) / double(max_ - min_));
}

Legend ColorScale::legend() const {
  Legend legend{variable_, !categorical(), {}};
  if (categorical()) {
    for (int64_t v = min_; v <= max_; ++v) legend.entries.push_back({color(v), std::to_string(v)});
    return legend;
  }
  // Five stops, labelled with the values they stand for.
  for (int i = 0; i <= 4; ++i) {
    const int64_t v = min_ + int64_t(std::llround(double(max_ - min_) * i / 4));
    legend.entries.push_back({gradient_color(i / 4.0), std::to_string(v)});
  }
  return legend;
}

}  // namespace dw::render
