// Scenes the render tests draw: a block of modules on the lattice, ids x-fastest.
#pragma once

#include "render/scene.h"

namespace dw::render::test {

inline Scene block(int nx, int ny, int nz, Color color = {}) {
  Scene s;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        SceneModule m;
        m.id = sim::ModuleId(s.modules.size());
        m.pose.position = {float(x), float(y), float(z)};
        m.color = color;
        s.modules.push_back(m);
      }
  return s;
}

}  // namespace dw::render::test
