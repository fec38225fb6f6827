// Colouring modules by a state variable: a categorical palette when the values span a small range
// (each value its own colour, told apart at a glance), a gradient otherwise; and the legend that
// explains either.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "render/scene.h"

namespace dw::render {

// Module colour when nothing colours them.
inline constexpr Color kNeutralModule{0.55f, 0.63f, 0.72f};

class ColorScale {
 public:
  // Ranges of at most this many values get a categorical palette.
  static constexpr int64_t kMaxCategories = 10;

  // The scale for a variable taking `values` (empty: a scale of the single value 0).
  ColorScale(std::string variable, std::span<const int64_t> values);

  Color color(int64_t value) const;
  Legend legend() const;
  bool categorical() const { return max_ - min_ < kMaxCategories; }
  int64_t min() const { return min_; }
  int64_t max() const { return max_; }

 private:
  std::string variable_;
  int64_t min_ = 0, max_ = 0;
};

// The categorical palette (Tableau 10: distinct in hue and lightness), cycled.
Color category_color(size_t index);
// A perceptually uniform gradient (viridis) at s in [0, 1].
Color gradient_color(double s);

}  // namespace dw::render
