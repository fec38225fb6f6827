#include "physics/pivot.h"

#include <cmath>

#include "physics/convert.h"

namespace dw::physics {
namespace {

constexpr btScalar kSlack = 1e-3f;  // lattice positions are exact to far better than this

bool unit(const btVector3& v) { return std::abs(v.length() - 1) < kSlack; }

}  // namespace

std::variant<std::vector<PivotArc>, std::string> pivot_arcs(ModuleShape shape, const sim::Vec3& from,
                                                            const sim::Vec3& about, const sim::Vec3& offset) {
  const btVector3 c = to_bt(from), p = to_bt(about), o = to_bt(offset), d = c + o;
  const btVector3 n = c - p;  // from the neighbour to the module
  if (shape == ModuleShape::Box) {
    if (!unit(n) || std::abs(std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z()) - 1) > kSlack)
      return std::string("a cube pivots about a neighbour it shares a face with");
    // 90 degrees: the offset runs along the neighbour's face; 180: it also goes down past it.
    const bool roll = unit(o) && std::abs(o.dot(n)) < kSlack;
    const btVector3 over = o + n;
    const bool flip = !roll && unit(over) && std::abs(over.dot(n)) < kSlack;
    if (!roll && !flip)
      return std::string(
          "a cube pivots about a neighbour by one cell along its face (offset perpendicular to the way "
          "to it) or over its edge (that offset, less the way to it)");
    const btVector3 u = roll ? o : over;
    PivotArc arc;
    arc.pivot = from_bt(c - n / 2 + u / 2);       // the edge the two cubes share on the side of u
    arc.axis = from_bt(n.cross(u).normalized());  // turning n towards u
    arc.angle = roll ? SIMD_HALF_PI : SIMD_PI;
    arc.spin = 1;
    return std::vector<PivotArc>{arc};
  }
  // Round modules roll over the neighbour, a Hexanode turns about a corner of it: both cells touch
  // it and each other.
  const btVector3 m = d - p;
  if (!unit(n) || !unit(m) || !unit(o))
    return std::string(shape == ModuleShape::HexPrism ? "a Hexanode" : "a round module") +
           " pivots about a touching neighbour into a cell next to its own that also touches the neighbour";
  const btVector3 axis = n.cross(m);
  if (axis.length() < kSlack) return std::string("the cell is on the far side of the neighbour");
  std::vector<PivotArc> arcs;
  if (shape == ModuleShape::HexPrism) {
    // The three cells touch pairwise: their shared corner is the middle of their triangle, and a
    // turn of 120 degrees about it takes the module's cell onto the one it goes to (turning n
    // towards m, as the round modules do about the neighbour).
    PivotArc corner;
    corner.pivot = from_bt((c + d + p) / 3);
    corner.axis = from_bt(axis.normalized());
    corner.angle = 2 * SIMD_PI / 3;
    corner.spin = 1;
    arcs.push_back(corner);
    return arcs;
  }
  PivotArc over;
  over.pivot = about;
  over.axis = from_bt(axis.normalized());
  over.angle = n.angle(m);
  over.spin = 2;  // rolling without slipping on a module of its own size
  arcs.push_back(over);
  if (shape == ModuleShape::Sphere) {
    // The two cells touching the module, the cell and the neighbour (three mutually touching
    // spheres: the centroid of their triangle, plus or minus its normal times sqrt(2/3)). About
    // the line from the neighbour to either, the sphere keeps its distance to both.
    const btVector3 centroid = (c + d + p) / 3, normal = axis.normalized() * std::sqrt(btScalar(2) / 3);
    for (const btVector3& q : {centroid + normal, centroid - normal}) {
      const btVector3 line = (q - p).normalized();
      const btVector3 a = n - line * n.dot(line), b = m - line * m.dot(line);  // square to the line
      PivotArc groove;
      groove.pivot = about;
      groove.axis = from_bt(line);
      groove.angle = std::atan2(a.cross(b).dot(line), a.dot(b));
      groove.spin = 1;
      arcs.push_back(groove);
    }
  }
  return arcs;
}

std::optional<std::string> unsupported_in_vertical_plane(const sim::Vec3& cell, float ground_z,
                                                         std::span<const Holder> touching) {
  constexpr float kOnGround = 0.01f;  // the contact threshold's default: within it, it rests there
  constexpr float kBelow = 0.25f;     // a module under it sits sqrt(3)/2 lower, one beside it level
  if (cell[2] - 0.5f - ground_z <= kOnGround) return std::nullopt;
  for (const Holder& h : touching)
    if (h.centre[2] < cell[2] - kBelow) return std::nullopt;
  if (touching.size() >= 2) return std::nullopt;
  if (touching.empty()) return std::string("nothing would hold it there (it would float)");
  return "it would hang from module " + std::to_string(touching[0].id) +
         " alone (in a vertical plane a module rests on the ground or on a module below it, or is held by two)";
}

}  // namespace dw::physics
