// A point or direction in the world: three floats, laid out as Bullet's single-precision vectors
// without their padding (docs/design.md §8).
#pragma once

#include <array>

namespace dw::sim {

using Vec3 = std::array<float, 3>;

}  // namespace dw::sim
