// The plausibility suite's scenes and measures (docs/design.md §8a): a scenario loaded as a user
// loads it (scenarios/physics/*.toml, push_wall, demolition) and run in a session, and what
// physics engines check their own demos by (Box2D's samples, Jolt's and Bullet's demos): how far a
// body strays from where it rests, how much energy it keeps, how deep it sinks into the ground or
// into another body, measured as Bullet measures it (GJK with the shapes' margins).
//
// Each measure goes to a Worst, which keeps the run's worst value with the body and the step it
// was seen at, and how often the bar was passed: a failing test says who, when and how much.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "physics/bullet_world.h"
#include "physics/contact_graph.h"
#include "scenarios/scenario.h"
#include "sim/session.h"
#include "sim/state.h"

namespace dw::physics::test {

// A scenario of scenarios/ (DWATCH_SCENARIOS_DIR), e.g. "physics/column.toml"; a mistake in it
// throws, with the loader's message.
inline scenarios::Scenario load_scene(const std::string& name) {
  auto loaded = scenarios::load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/" + name);
  if (auto* e = std::get_if<std::string>(&loaded)) throw std::runtime_error(*e);
  return std::move(std::get<scenarios::Scenario>(loaded));
}

inline const BulletWorld& bullet_world(const scenarios::Scenario& s) {
  const auto* world = dynamic_cast<const BulletWorld*>(s.world.get());
  if (!world) throw std::runtime_error(s.path + " has no [physics]");
  return *world;
}

// The bodies start awake (docs/design.md §8a): after step 0 no cluster that moves has been still
// for longer than that one step, so none sleeps before Bullet's deactivation time has passed, and
// the scene's numbers over its first steps are those of bodies stepped.
inline void expect_awake_at_start(const sim::State& st) {
  for (size_t c = 0; c < st.bodies.clusters.size(); ++c) {
    const sim::Cluster& cluster = st.bodies.clusters[c];
    EXPECT_TRUE(cluster.anchored || cluster.still <= 1)
        << "cluster " << c << " (module " << st.bodies.members[cluster.first] << ") still for " << cluster.still
        << " steps after step 0";
  }
}

// Runs the scenario as `dwatch run` does (its scheduled events included, no history kept) for
// `steps` steps, calling look(state, step) after each, step 0 included; the bodies start awake.
inline void run_scene(const scenarios::Scenario& s, int64_t steps,
                      const std::function<void(const sim::State&, int64_t)>& look, unsigned threads = 1) {
  sim::Session run(*s.model, *s.world, {.threads = threads, .history_bytes = 0, .events = s.events});
  while (run.current() + 1 < steps)
    run.run_until(steps, [&](const sim::State& st, const sim::StepOutput& out) {
      if (out.step == 0) expect_awake_at_start(st);
      look(st, out.step);
    });
}

// The worst of a measure over a run (the larger, the worse), whose it was and when, and how many
// times it went over the bar.
class Worst {
 public:
  Worst(std::string measure, float bar) : measure_(std::move(measure)), bar_(bar) {}

  // `value` of the body or pair `who()` names (called only when needed) at `step`.
  template <typename Who>
  void see(float value, int64_t step, Who&& who) {
    if (!(value <= bar_)) {  // NaN is over too
      if (over_++ == 0) first_ = who() + " at step " + std::to_string(step) + ": " + number(value);
    }
    if (!(value <= worst_) || step_ < 0) {
      worst_ = value;
      step_ = step;
      who_ = who();
    }
  }

  bool within() const { return over_ == 0; }
  float value() const { return worst_; }
  int64_t step() const { return step_; }
  uint64_t over() const { return over_; }
  // "ground depth: worst 0.604 (module 372 at step 251); 419 times over 0.02, first module 5 at step 40: 0.03"
  std::string report() const {
    std::string out = measure_ + ": worst " + number(worst_) + " (" + who_ + " at step " + std::to_string(step_) + ")";
    if (over_ > 0) out += "; " + std::to_string(over_) + " times over " + number(bar_) + ", first " + first_;
    return out;
  }

 private:
  static std::string number(float v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
  }

  std::string measure_;
  float bar_;
  float worst_ = -std::numeric_limits<float>::infinity();
  int64_t step_ = -1;
  std::string who_ = "nobody";
  uint64_t over_ = 0;
  std::string first_;
};

inline std::string module_name(sim::ModuleId m) { return "module " + std::to_string(m); }

// Modules are boxes one size across whose corners Bullet rounds by its default margin
// (physics/shapes.cpp: a btBoxShape of half extent 0.5, its core 0.46 grown by a ball of 0.04).
inline constexpr float kHalf = 0.5f, kMargin = 0.04f, kCore = kHalf - kMargin;

// The columns of a pose's rotation: where its x, y and z axes point in the world.
inline std::array<sim::Vec3, 3> axes(const sim::Pose& p) {
  const auto [x, y, z, w] = p.orientation;
  return {sim::Vec3{1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)},
          sim::Vec3{2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)},
          sim::Vec3{2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)}};
}

inline float dot(const sim::Vec3& a, const sim::Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline float length(const sim::Vec3& a) { return std::sqrt(dot(a, a)); }
inline sim::Vec3 minus(const sim::Vec3& a, const sim::Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// How far a module's rounded box reaches below the ground plane at z = ground (<= 0: not at all).
inline float ground_depth(const sim::Pose& p, float ground) {
  const auto a = axes(p);
  const float down = kCore * (std::abs(a[0][2]) + std::abs(a[1][2]) + std::abs(a[2][2])) + kMargin;
  return ground - (p.position[2] - down);
}

// How deep a module's rounded box and a sphere of `radius` at `centre` overlap (<= 0: apart): the
// sphere's distance to the box's core, less the margin and the radius, as GJK finds it.
inline float sphere_depth(const sim::Pose& box, const sim::Vec3& centre, float radius) {
  const auto a = axes(box);
  const sim::Vec3 d = minus(centre, box.position);
  float outside = 0, inside = kCore;
  for (int i = 0; i < 3; ++i) {
    const float along = std::abs(dot(d, a[size_t(i)]));
    outside += std::max(0.0f, along - kCore) * std::max(0.0f, along - kCore);
    inside = std::min(inside, kCore - along);
  }
  const float to_core = outside > 0 ? std::sqrt(outside) : -inside;
  return radius + kMargin - to_core;
}

// The least overlap of two whole boxes (half extent kHalf, corners not rounded) along the 15
// separating axes: their penetration depth when they overlap (<= 0: apart). The rounded boxes lie
// inside, so it bounds theirs from above: a pair under a bar here needs no GJK.
inline float box_overlap_bound(const sim::Pose& p, const sim::Pose& q) {
  const auto a = axes(p), b = axes(q);
  const sim::Vec3 t = minus(q.position, p.position);
  float least = std::numeric_limits<float>::infinity();
  const auto along = [&](const sim::Vec3& l) {
    const float n = length(l);
    if (n < 1e-5f) return;  // parallel edges: their axis is a face's, tried already
    float ra = 0, rb = 0;
    for (size_t i = 0; i < 3; ++i) {
      ra += std::abs(dot(a[i], l));
      rb += std::abs(dot(b[i], l));
    }
    least = std::min(least, (kHalf * (ra + rb) - std::abs(dot(t, l))) / n);
  };
  for (size_t i = 0; i < 3; ++i) {
    along(a[i]);
    along(b[i]);
  }
  for (size_t i = 0; i < 3; ++i)
    for (size_t j = 0; j < 3; ++j)
      along({a[i][1] * b[j][2] - a[i][2] * b[j][1], a[i][2] * b[j][0] - a[i][0] * b[j][2],
             a[i][0] * b[j][1] - a[i][1] * b[j][0]});
  return least;
}

// Every present module's overlap with the ground, the scenario's sphere props and the boxes
// whose centres are close enough to touch it (found on a grid of centres two sizes across), each
// pair once, as Bullet measures it: GJK on the rounded boxes (ContactGraph::distance, EPA for
// overlaps), asked only of pairs that the whole boxes' separating axes cannot clear. Box props of
// a module's size are boxes like the modules; other box props are left out.
class Overlaps {
 public:
  // `bar`: the depth each measure allows.
  Overlaps(const BulletWorld& world, float bar)
      : ground("depth into the ground", bar),
        centres("centre below its rest height", bar),
        pairs("pair penetration", bar),
        contacts_(world.shape(), world.settings().contact_threshold),
        ground_(world.ground_z()),
        props_(world.settings().props),
        bar_(bar) {
    if (world.shape() != ModuleShape::Box) throw std::runtime_error("the overlap measures are for boxes");
  }

  // Modules' and props' depth into the ground; module centres below the lowest a box's centre
  // rests at (half a size above the ground); the deepest overlap of two boxes or a module and a
  // sphere prop (where it is under the bar, an upper bound may stand for it).
  Worst ground, centres, pairs;

  void measure(const sim::State& st, int64_t step) {
    const sim::Bodies& b = st.bodies;
    boxes_.clear();
    for (sim::ModuleId m = 0; m < b.poses.size(); ++m)
      if (st.present[m]) boxes_.push_back({b.poses[m], m, false});
    for (size_t i = 0; i < props_.size(); ++i) {
      const sim::Pose& p = b.prop_poses[i];
      if (props_[i].shape == ModuleShape::Sphere)
        ground.see(ground_ - (p.position[2] - props_[i].size[0] / 2), step, [&] { return prop_name(i); });
      else if (props_[i].size == sim::Vec3{1, 1, 1}) boxes_.push_back({p, uint32_t(i), true});
    }
    grid_.clear();
    for (uint32_t k = 0; k < boxes_.size(); ++k) {
      const Box& box = boxes_[k];
      ground.see(ground_depth(box.pose, ground_), step, [&] { return name(box); });
      grid_[key(box.pose.position)].push_back(k);
      if (box.prop) continue;
      centres.see(ground_ + kHalf - box.pose.position[2], step, [&] { return name(box); });
      for (size_t i = 0; i < props_.size(); ++i)
        if (props_[i].shape == ModuleShape::Sphere)
          pairs.see(sphere_depth(box.pose, b.prop_poses[i].position, props_[i].size[0] / 2), step,
                    [&] { return name(box) + " and " + prop_name(i); });
    }
    for (uint32_t k = 0; k < boxes_.size(); ++k) around(k, step);
  }

 private:
  struct Box {
    sim::Pose pose;
    uint32_t id;  // a module's, or a prop's index
    bool prop;
  };
  static std::string prop_name(size_t i) { return "prop " + std::to_string(i); }
  static std::string name(const Box& box) { return box.prop ? prop_name(box.id) : module_name(box.id); }

  // Centres further apart than twice a rounded box's far corner cannot overlap; the grid's cells
  // are wider, so that the 27 around a centre hold every box that can.
  static constexpr float kApart = 2 * (kCore * 1.7320508f + kMargin), kSide = 2;
  static int64_t coordinate(float x) { return int64_t(std::floor(x / kSide)); }
  static uint64_t pack(int64_t x, int64_t y, int64_t z) {
    const auto field = [](int64_t v) { return uint64_t(v + (int64_t{1} << 20)) & 0x1fffff; };
    return field(x) | field(y) << 21 | field(z) << 42;
  }
  static uint64_t key(const sim::Vec3& at) { return pack(coordinate(at[0]), coordinate(at[1]), coordinate(at[2])); }

  // Box k against the boxes after it in the 27 cells around its own.
  void around(uint32_t k, int64_t step) {
    const sim::Pose& p = boxes_[k].pose;
    const int64_t x = coordinate(p.position[0]), y = coordinate(p.position[1]), z = coordinate(p.position[2]);
    for (int64_t dz = -1; dz <= 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const auto cell = grid_.find(pack(x + dx, y + dy, z + dz));
          if (cell == grid_.end()) continue;
          for (uint32_t o : cell->second) {
            if (o <= k) continue;
            const sim::Pose& q = boxes_[o].pose;
            const sim::Vec3 d = minus(q.position, p.position);
            if (dot(d, d) >= kApart * kApart) continue;
            float depth = box_overlap_bound(p, q);
            if (depth > bar_) depth = -contacts_.distance(p, q);  // only a deep one asks GJK
            pairs.see(depth, step, [&] { return name(boxes_[k]) + " and " + name(boxes_[o]); });
          }
        }
  }

  ContactGraph contacts_;
  float ground_;
  std::vector<PropSpec> props_;
  float bar_;
  std::vector<Box> boxes_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid_;
};

// A module's kinetic energy (J): a box one size across of `mass`, whose moment of inertia about
// any axis through its centre is mass / 6.
inline float kinetic_energy(const sim::Velocity& v, float mass) {
  return 0.5f * mass * dot(v.linear, v.linear) + 0.5f * (mass / 6) * dot(v.angular, v.angular);
}

// The farthest any corner of a box one size across at `now` is from where it was at `then`: how
// far it moved, turns included.
inline float corner_travel(const sim::Pose& then, const sim::Pose& now) {
  const auto a = axes(then), b = axes(now);
  float most = 0;
  for (float x : {-kHalf, kHalf})
    for (float y : {-kHalf, kHalf})
      for (float z : {-kHalf, kHalf}) {
        sim::Vec3 d = minus(now.position, then.position);
        for (size_t i = 0; i < 3; ++i)
          d[i] += x * (b[0][i] - a[0][i]) + y * (b[1][i] - a[1][i]) + z * (b[2][i] - a[2][i]);
        most = std::max(most, length(d));
      }
  return most;
}

// How far a pose is from another, across (in x and y) and up or down.
inline float across(const sim::Vec3& a, const sim::Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }
inline float updown(const sim::Vec3& a, const sim::Vec3& b) { return std::abs(a[2] - b[2]); }

}  // namespace dw::physics::test
