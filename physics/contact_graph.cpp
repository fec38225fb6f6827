#include "physics/contact_graph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <stdexcept>

#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

#include "physics/cell_grid.h"
#include "physics/convert.h"
#include "physics/module_records.h"
#include "physics/shapes.h"

namespace dw::physics {
namespace {

// The smallest distance GJK reports between two shapes (negative: they overlap).
struct ClosestDistance final : btDiscreteCollisionDetectorInterface::Result {
  btScalar distance = BT_LARGE_FLOAT;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3&, btScalar depth) override {
    distance = std::min(distance, depth);
  }
};

// How much wider than the reach a rank's window is: rounding in a moving cluster's poses may put
// two neighbours measured in its frame a hair further apart in the world.
constexpr float kWindowMargin = 1.125f;

float squared_distance(const sim::Vec3& a, const sim::Vec3& b) {
  const float x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

}  // namespace

struct ContactGraph::Impl {
  Impl(ModuleShape kind, float threshold)
      : shape(make_module_shape(kind)),
        convex(static_cast<btConvexShape*>(shape.get())),
        kind(kind),
        threshold(threshold),
        cutoff(reach(*shape, threshold)),
        grid(cutoff) {
    // A box's core (inside its margin) and a sphere's radius, for the closed forms in touching.
    btVector3 lo, hi;
    btTransform identity;
    identity.setIdentity();
    shape->getAabb(identity, lo, hi);
    half = hi.x();
    margin = convex->getMargin();
  }

  // Centres further apart than this cannot be within the threshold: twice the radius of the
  // sphere around a module's shape, plus the threshold.
  static float reach(btCollisionShape& shape, float threshold) {
    btVector3 centre;
    btScalar radius = 0;
    shape.getBoundingSphere(centre, radius);
    return 2 * (radius + centre.length()) + threshold;
  }

  // Two modules touch when GJK puts their shapes (margins included: shapes one size apart are at
  // distance 0) at most the threshold apart, measured at `ta` and `tb`.
  // GJK's answer, in closed form where there is one (most pairs of a lattice): two spheres, and two
  // boxes both unturned. A box with its margin is its core (half - margin across) grown by a ball
  // of the margin, so two of them are within the threshold when their cores are within twice the
  // margin plus it (faces one size apart: yes; edges one size apart diagonally: 0.033 apart, no).
  // The closed form and GJK part only within rounding of the threshold itself.
  bool touching(const sim::Pose& ta, const sim::Pose& tb) const {
    const float d0 = ta.position[0] - tb.position[0], d1 = ta.position[1] - tb.position[1],
                d2 = ta.position[2] - tb.position[2];
    if (kind == ModuleShape::Sphere) {
      const float within = 2 * half + threshold;
      return d0 * d0 + d1 * d1 + d2 * d2 <= within * within;
    }
    constexpr std::array<float, 4> unturned{0, 0, 0, 1};
    if (kind == ModuleShape::Box && ta.orientation == unturned && tb.orientation == unturned) {
      const float core = 2 * (half - margin), within = 2 * margin + threshold;
      const float g0 = std::max(0.0f, std::abs(d0) - core), g1 = std::max(0.0f, std::abs(d1) - core),
                  g2 = std::max(0.0f, std::abs(d2) - core);
      return g0 * g0 + g1 * g1 + g2 * g2 <= within * within;
    }
    return distance(ta, tb) <= threshold;
  }
  // Bullet's GJK distance between two module shapes (negative: they overlap; very large: further
  // apart than the threshold reaches).
  btScalar distance(const sim::Pose& ta, const sim::Pose& tb) const {
    btGjkPairDetector::ClosestPointInput input;
    input.m_transformA = to_bt(ta);
    input.m_transformB = to_bt(tb);
    // GJK stops early on a pair it finds further apart than this.
    const btScalar reported = 2 * convex->getMargin() + threshold;
    input.m_maximumDistanceSquared = reported * reported;
    btVoronoiSimplexSolver simplex;
    btGjkEpaPenetrationDepthSolver depth;
    btGjkPairDetector gjk(convex, convex, &simplex, &depth);
    ClosestDistance result;
    gjk.getClosestPoints(input, result, nullptr);
    return result.distance;
  }

  // Where a module is, as far as its pairs are concerned: a member of a cluster that moves is
  // measured against its fellow members at its pose in the cluster (fixed while the cluster
  // lasts, however it moves), everything else at its world pose (an anchored cluster never moves).
  struct Frame {
    uint32_t cluster = sim::kNoCluster;  // a cluster that moves, or kNoCluster
    sim::Pose local;                     // the pose in it
    bool operator==(const Frame&) const = default;
  };
  static Frame frame_of(const sim::Bodies& b, size_t m) {
    if (b.cluster_of.empty()) return {};
    const uint32_t c = b.cluster_of[m];
    if (c == sim::kNoCluster || b.clusters[c].anchored || b.clusters[c].count < 2) return {};
    return {c, b.local[m]};
  }
  static bool together(const Frame& a, const Frame& b) {
    return a.cluster != sim::kNoCluster && a.cluster == b.cluster;
  }

  // Brings module m's place in the grid up to the bodies.
  void place(const sim::Bodies& bodies, std::span<const uint8_t> present, sim::ModuleId m) {
    grid.place(m, present[m] != 0, bodies.poses[m].position);
  }
  // Makes the grid's cells those of the bodies (a fresh grid, whose modules must all be placed),
  // with room for n modules. Returns whether it was made afresh.
  bool fit_grid(const sim::Bodies& bodies, size_t n) {
    const bool fresh = !(grid.rest() == bodies.poses.defaults());
    if (fresh) grid = CellGrid(cutoff, bodies.poses.defaults());
    grid.resize(n);
    return fresh;
  }

  std::unique_ptr<btCollisionShape> shape;
  btConvexShape* convex;
  ModuleShape kind;
  float threshold, cutoff;
  float half = 0.5f, margin = 0;  // half the module's size, and its margin
  CellGrid grid;                  // every present module, where it was last placed
  // Per module, a byte of marks: whether it was present at the last measurement (kept), and an
  // update's marks (all clear between updates): a byte a module, where a vector for each took six.
  enum Mark : uint8_t { kWasPresent = 1, kMoved = 2, kReframed = 4, kFlagged = 8, kSearch = 16, kRenew = 32 };
  std::vector<uint8_t> marks;
  bool marked(sim::ModuleId m, Mark k) const { return (marks[m] & k) != 0; }
  void mark(sim::ModuleId m, Mark k, bool on) { marks[m] = on ? uint8_t(marks[m] | k) : uint8_t(marks[m] & ~k); }
  // As of the last measurement, per module: its world pose and its frame. `frame` is empty while
  // every module's is the default one (a latched lattice anchored to the ground, where it would be
  // 32 bytes a module of nothing), and per module once one is not.
  // Over ranks, `world` is remembered for the modules of the window and those in its lists (the
  // only ones whose pairs it holds) and kept for every module once remembered: a module not
  // remembered counts as moved whenever it is looked at.
  PagedRecords<sim::Pose, sim::CellPose> world;
  std::vector<Frame> frame;
  const Frame& last_frame(sim::ModuleId m) const {
    static constexpr Frame kDefault{};
    return frame.empty() ? kDefault : frame[m];
  }
  void keep_frame(sim::ModuleId m, const Frame& f, size_t n) {
    if (frame.empty() && f == Frame{}) return;
    frame.resize(n);
    frame[m] = f;
  }
  // Scratch of an update, kept so that a million-module step does not fault in fresh pages.
  Ids looked, flagged_list;
  std::vector<sim::ModuleId> entering;
  std::shared_ptr<const sim::NeighborGraph> graph;

  struct Pass;  // one update, below
};

ContactGraph::ContactGraph(ModuleShape shape, float threshold) : impl_(std::make_unique<Impl>(shape, threshold)) {}
ContactGraph::~ContactGraph() = default;

void ContactGraph::reset() { impl_->graph.reset(); }

void ContactGraph::place(const sim::Bodies& bodies, std::span<const uint8_t> present) {
  Impl& s = *impl_;
  const size_t n = bodies.poses.size();
  s.fit_grid(bodies, n);
  for (size_t m = 0; m < n; ++m) s.place(bodies, present, static_cast<sim::ModuleId>(m));
}

float ContactGraph::distance(const sim::Pose& a, const sim::Pose& b) const { return impl_->distance(a, b); }

float ContactGraph::reach() const { return impl_->cutoff; }

bool ContactGraph::touching(const sim::Pose& a, const sim::Pose& b) const { return impl_->touching(a, b); }

std::vector<sim::ModuleId> ContactGraph::near(const sim::Vec3& at, float radius) const {
  const Impl& s = *impl_;
  std::vector<sim::ModuleId> found;
  s.grid.around(at, [&](sim::ModuleId m, const sim::Vec3& m_at) {
    if (squared_distance(m_at, at) < radius * radius) found.push_back(m);
  });
  std::sort(found.begin(), found.end());
  return found;
}

// Over ranks, a rank's window (docs/design.md §12a): the present modules it owns, and those whose
// centres lie within `radius` of one of them (a neighbour's centre is within the reach).
struct Window {
  const CellGrid& grid;  // where each module is
  std::span<const uint8_t> present;
  const sim::ModuleOwners& owners;
  uint32_t me;
  float radius;

  bool owned(sim::ModuleId m) const { return owners.rank_of(m) == me; }
  template <typename Visit>
  void near(const sim::Vec3& at, Visit&& visit) const {
    const sim::Vec3 lo{at[0] - radius, at[1] - radius, at[2] - radius},
        hi{at[0] + radius, at[1] + radius, at[2] + radius};
    grid.within(lo, hi, [&](sim::ModuleId o, const sim::Vec3& o_at) {
      if (squared_distance(o_at, at) <= radius * radius) visit(o);
    });
  }
  bool holds(sim::ModuleId m) const {
    if (!present[m]) return false;
    if (owned(m)) return true;
    bool found = false;
    near(grid.at(m), [&](sim::ModuleId o) { found = found || (present[o] && owned(o)); });
    return found;
  }
};

// One update (ContactGraph::update), stage by stage, each a function of its own: what changed
// since the last measurement (look), over ranks the window now (rewindow), the pairs to measure
// again as they were (read_stale), who looks for pairs (choose_searchers), the measurement itself
// (measure), what is remembered of it (remember), and the graph it makes (make_graph).
struct ContactGraph::Impl::Pass {
  using Pair = std::pair<sim::ModuleId, sim::ModuleId>;

  Pass(Impl& s, const sim::Bodies& bodies, std::span<const uint8_t> present, sim::RankExchange* ranks,
       const sim::ModuleOwners* owners)
      : s(s),
        bodies(bodies),
        poses(bodies.poses),
        present(present),
        ranks(ranks),
        owners(owners),
        n(bodies.poses.size()),
        windowed(ranks != nullptr) {
    // Poses at rest are remembered as the bodies keep them: as their cells, without pages.
    if (!(s.world.defaults() == bodies.poses.defaults())) s.world = decltype(s.world)(bodies.poses.defaults());
    const bool regrid = s.fit_grid(bodies, n);
    forget = regrid || !s.graph || s.world.size() != n || windowed != (s.graph->held != nullptr);
    s.marks.resize(n, 0);
    s.world.resize(n);
    if (!s.frame.empty()) s.frame.resize(n);
    for (const sim::Mover& mover : bodies.movers)
      if (mover.hinge < n && present[mover.module] && present[mover.hinge])
        hinges.emplace_back(std::minmax(mover.module, mover.hinge));
    std::sort(hinges.begin(), hinges.end());
  }

  bool moved(sim::ModuleId m) const { return s.marked(m, Impl::kMoved); }
  bool reframed(sim::ModuleId m) const { return s.marked(m, Impl::kReframed); }
  bool flagged(sim::ModuleId m) const { return s.marked(m, Impl::kFlagged); }
  bool was_present(sim::ModuleId m) const { return s.marked(m, Impl::kWasPresent); }
  bool renewing(sim::ModuleId m) const { return s.marked(m, Impl::kRenew); }
  bool renewed(sim::ModuleId a, sim::ModuleId b) const { return renewing(a) || renewing(b); }
  bool search(sim::ModuleId m) const { return s.marked(m, Impl::kSearch); }
  bool visits(sim::ModuleId m) const { return search(m) || (renewing(m) && present[m]); }
  // The frame a module is measured at now: the bodies' for the flagged ones (read again rather
  // than kept: 32 bytes a module), the last one for the others, which are known not to differ.
  Frame now(sim::ModuleId m) const { return flagged(m) ? Impl::frame_of(bodies, m) : s.last_frame(m); }
  // A pivot and the neighbour it turns on touch all the turn long: along the edge it turns about,
  // which GJK finds apart in the middle of a cube's turn (their edges are rounded by the margin),
  // or as a sphere rolls on it. A mover moves every step, so the pair is measured every step.
  bool hinged(sim::ModuleId a, sim::ModuleId b) const {
    return !hinges.empty() && std::binary_search(hinges.begin(), hinges.end(), Pair(std::minmax(a, b)));
  }
  // Over ranks, whether the window holds m's list now, and whether it held it before.
  bool holds(sim::ModuleId m) const { return !window || (*window)[m] != 0; }
  bool held_before(sim::ModuleId m) const { return was_held == nullptr || (*was_held)[m] != 0; }

  // A pair is measured again when what it is measured at changed: both members of one cluster
  // that moves at their poses in it, any other pair at its world poses. Every other pair keeps
  // its measurement.
  bool stale(sim::ModuleId a, sim::ModuleId b) const {
    if (forget) return true;
    // A module that came or went is flagged (moved), so an unflagged pair is present as it was.
    if (!flagged(a) && !flagged(b)) return false;
    if (!present[a] || !present[b]) return true;
    const Impl::Frame &last_a = s.last_frame(a), &last_b = s.last_frame(b);
    const Impl::Frame now_a = now(a), now_b = now(b);
    const bool was = Impl::together(last_a, last_b), is = Impl::together(now_a, now_b);
    if (was != is) return true;
    return is ? !(now_a.local == last_a.local && now_b.local == last_b.local) : moved(a) || moved(b);
  }

  // The modules to look at: those the caller says may have changed, or all. Per module, what
  // changed since the last measurement: it came or went or its world pose changed (moved), or its
  // frame did (reframed); `flagged` either. Only those look for pairs to measure. Returns whether
  // any is flagged.
  bool look(const std::vector<sim::ModuleId>* changed) {
    Ids& looked = s.looked;
    if (changed && !forget) {
      std::vector<sim::ModuleId>& list = looked.list();
      list = *changed;
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    } else {
      looked.all(n);
    }
    // Forgetting, every module is flagged.
    Ids& flagged_list = s.flagged_list;
    if (forget) flagged_list.all(n);
    else flagged_list.list().clear();
    for (sim::ModuleId m : looked) {
      s.place(bodies, present, m);
      const bool is = present[m] != 0, moved = forget || is != s.marked(m, Impl::kWasPresent) ||
                                               (is && !(s.world.known(m) && poses[m] == s.world[m]));
      const bool reframed = forget || !(Impl::frame_of(bodies, m) == s.last_frame(m));
      s.mark(m, Impl::kMoved, moved);
      s.mark(m, Impl::kReframed, reframed);
      s.mark(m, Impl::kFlagged, moved || reframed);
      if ((moved || reframed) && !forget) flagged_list.list().push_back(m);
    }
    return !flagged_list.empty();
  }

  // Over ranks, the window now: it changes only around what changed, the modules flagged and
  // those near where a flagged module of this rank's was and is. A module entering it (not
  // flagged, or flagged) has every pair measured again (`renew`): its list is made whole.
  void rewindow() {
    std::vector<sim::ModuleId>& entering = s.entering;
    entering.clear();
    was_held = forget || !s.graph ? nullptr : s.graph->held.get();
    if (!windowed) return;
    const Window w{s.grid, present, *owners, static_cast<uint32_t>(ranks->rank()), s.cutoff * kWindowMargin};
    auto held = std::make_shared<std::vector<uint8_t>>(n, 0);
    if (forget) {
      for (sim::ModuleId a = 0; a < n; ++a)
        if (present[a] && w.owned(a)) {
          (*held)[a] = 1;
          w.near(s.grid.at(a), [&](sim::ModuleId o) { (*held)[o] = present[o]; });
        }
    } else {
      *held = *was_held;
      std::vector<sim::ModuleId> again;
      for (sim::ModuleId m : s.flagged_list) {
        again.push_back(m);
        if (w.owned(m)) {
          w.near(s.grid.at(m), [&](sim::ModuleId o) { again.push_back(o); });
          if (was_present(m) && s.world.known(m))
            w.near(s.world[m].position, [&](sim::ModuleId o) { again.push_back(o); });
        }
      }
      std::sort(again.begin(), again.end());
      again.erase(std::unique(again.begin(), again.end()), again.end());
      for (sim::ModuleId m : again) {
        (*held)[m] = w.holds(m);
        if ((*held)[m] && !(*was_held)[m]) {
          entering.push_back(m);
          s.mark(m, Impl::kRenew, true);
        }
      }
    }
    window = std::move(held);
  }

  // The pairs measured again, as they were (`dropped`). Only a pair with a flagged (or renewed)
  // member can be, and a module's pairs are its neighbours in the graph last made: those lists are
  // all that is read. (The graph is the one list of pairs kept: a second, sorted, took 8 bytes a
  // pair.) Over ranks, a module whose list this rank did not hold finds its pairs in the lists held
  // near where it was measured last.
  void read_stale() {
    if (forget) return;
    const auto drop = [&](sim::ModuleId m, sim::ModuleId o) {
      if (stale(m, o) || renewed(m, o)) dropped.emplace_back(std::minmax(m, o));
    };
    const auto read = [&](sim::ModuleId m) {
      if (held_before(m)) {
        for (sim::ModuleId o : s.graph->neighbors(m))
          if (!(flagged(o) && o < m && held_before(o))) drop(m, o);  // else read from o's side
        return;
      }
      if (!was_present(m) || !s.world.known(m)) return;  // never next to the window: no pair held
      const Window w{s.grid, present, *owners, 0, s.cutoff * kWindowMargin};
      w.near(s.world[m].position, [&](sim::ModuleId o) {
        if (held_before(o) && !flagged(o) && s.graph->adjacent(o, m)) drop(m, o);
      });
    };
    for (sim::ModuleId m : s.flagged_list) read(m);
    for (sim::ModuleId m : s.entering)
      if (!flagged(m)) read(m);
    std::sort(dropped.begin(), dropped.end());
    dropped.erase(std::unique(dropped.begin(), dropped.end()), dropped.end());
  }

  // Who looks for pairs: what moved or was reframed, except the members of a cluster that moved
  // as a whole with nothing else near it (a pile free on the ground): their pairs with each other
  // keep their measurement, and nothing outside the cluster is within reach.
  void choose_searchers() {
    for (sim::ModuleId m : s.flagged_list) s.mark(m, Impl::kSearch, present[m] != 0);
    if (forget || bodies.cluster_of.empty()) return;
    for (uint32_t c = 0; c < bodies.clusters.size(); ++c) {
      const sim::Cluster& cluster = bodies.clusters[c];
      if (cluster.anchored || cluster.count < 2) continue;
      const std::span<const sim::ModuleId> members(bodies.members.data() + cluster.first, cluster.count);
      if (std::any_of(members.begin(), members.end(), [&](sim::ModuleId m) { return reframed(m) && flagged(m); }))
        continue;
      sim::Vec3 lo = poses[members[0]].position, hi = lo;
      for (sim::ModuleId m : members)
        for (int i = 0; i < 3; ++i) {
          lo[i] = std::min(lo[i], poses[m].position[i] - s.cutoff);
          hi[i] = std::max(hi[i], poses[m].position[i] + s.cutoff);
        }
      if (s.grid.cells_in(lo, hi) > 8 * uint64_t{cluster.count} + 64) continue;  // spread thin: ask each
      bool alone = true;
      s.grid.within(lo, hi, [&](sim::ModuleId o, const sim::Vec3& p) {
        alone = alone && (bodies.cluster_of[o] == c || p[0] < lo[0] || p[0] > hi[0] || p[1] < lo[1] || p[1] > hi[1] ||
                          p[2] < lo[2] || p[2] > hi[2]);
      });
      if (alone)
        for (sim::ModuleId m : members) s.mark(m, Impl::kSearch, false);
    }
  }

  // Each worker measures the stale pairs of a run of the visiting modules (the flagged ones, then
  // those entering the window); the runs are joined into `fresh`, sorted. A pair is measured from
  // its lower visiting member's side. Over ranks, a rank measures the pairs of its window, and
  // counts those one process measures from a module it owns: the same count, summed over them.
  void measure(sim::WorkerPool& workers) {
    const Ids& flagged_list = s.flagged_list;
    const std::vector<sim::ModuleId>& entering = s.entering;
    const float cutoff2 = s.cutoff * s.cutoff;
    const unsigned runs = workers.size();
    const auto visiting = [&](size_t i) {
      return i < flagged_list.size() ? flagged_list[i] : entering[i - flagged_list.size()];
    };
    const size_t count = flagged_list.size() + entering.size();
    std::vector<std::vector<Pair>> found(runs);
    std::vector<uint64_t> counted(runs, 0);
    const uint32_t me = windowed ? static_cast<uint32_t>(ranks->rank()) : 0;
    workers.run([&](unsigned run) {
      for (size_t i = count * run / runs; i < count * (run + 1) / runs; ++i) {
        const sim::ModuleId a = visiting(i);
        if (!visits(a) || (i >= flagged_list.size() && flagged(a))) continue;  // an entering module flagged: once
        // Poses are read once each (a module at rest has its cell's, computed on each read), and
        // the distance from where the grid placed b, which is where b is now: every module whose
        // pose may have changed was placed again by look().
        const sim::Pose pose_a = poses[a];
        s.grid.around(pose_a.position, [&](sim::ModuleId b, const sim::Vec3& b_at) {
          if (b == a) return;
          const bool natural = stale(a, b);
          if (!natural && !renewed(a, b)) return;
          if (squared_distance(pose_a.position, b_at) > cutoff2) return;
          if (natural && search(a) && !(b < a && search(b)) && (!windowed || owners->rank_of(a) == me)) ++counted[run];
          if (!holds(a) && !holds(b)) return;
          if (b < a && visits(b)) return;  // measured from b's side
          const Impl::Frame now_a = now(a), now_b = now(b);
          const bool local = Impl::together(now_a, now_b);
          if (hinged(a, b) || s.touching(local ? now_a.local : pose_a, local ? now_b.local : poses[b]))
            found[run].emplace_back(std::min(a, b), std::max(a, b));
        });
      }
    });
    for (unsigned run = 0; run < runs; ++run) {
      fresh.insert(fresh.end(), found[run].begin(), found[run].end());
      measured += counted[run];
    }
    if (windowed) ranks->sum(std::span(&measured, 1));
    std::sort(fresh.begin(), fresh.end());
  }

  // What is remembered: every module in one process; over ranks, those of the window and of its
  // lists (every pair found touches the window), and every module remembered before. The marks of
  // the update are cleared but kRenew, which stays until make_graph reads the lists gained.
  void remember() {
    const auto keep = [&](sim::ModuleId m) {
      if (!s.world.known(m)) s.world.set(m, poses[m]);
    };
    if (windowed) {
      for (sim::ModuleId m : s.entering) keep(m);
      for (const auto& [a, b] : fresh) keep(a), keep(b);
      if (forget)
        for (sim::ModuleId m = 0; m < n; ++m)
          if ((*window)[m]) keep(m);
    }
    for (sim::ModuleId m : s.flagged_list) {
      if (moved(m) && (!windowed || s.world.known(m))) s.world.set(m, poses[m]);
      if (reframed(m)) s.keep_frame(m, Impl::frame_of(bodies, m), n);
      s.marks[m] &= uint8_t(~(Impl::kMoved | Impl::kReframed | Impl::kFlagged | Impl::kSearch));
    }
    for (sim::ModuleId m : s.looked) s.mark(m, Impl::kWasPresent, present[m] != 0);
  }

  // The graph: made from the pairs found when every pair was measured; else the last one with the
  // pairs dropped and not found again taken out, those found that were not there put in, and the
  // lists of the modules entering the window whole; or the last one itself when the same pairs
  // were found again as were measured again, in the same window.
  std::shared_ptr<const sim::NeighborGraph> make_graph() {
    if (forget) {
      s.graph = std::make_shared<const sim::NeighborGraph>(
          sim::NeighborGraph::from_pairs(static_cast<uint32_t>(n), fresh).held_only(std::move(window)));
      return s.graph;
    }
    const bool rewindowed = windowed && *window != *was_held;
    if (fresh == dropped && !rewindowed) return s.graph;  // (and no module entered it)
    std::vector<Pair> gone, made, gained;
    std::set_difference(dropped.begin(), dropped.end(), fresh.begin(), fresh.end(), std::back_inserter(gone));
    std::set_difference(fresh.begin(), fresh.end(), dropped.begin(), dropped.end(), std::back_inserter(made));
    if (!s.entering.empty()) {
      for (const auto& [a, b] : fresh) {
        if (renewing(a)) gained.emplace_back(a, b);
        if (renewing(b)) gained.emplace_back(b, a);
      }
      for (sim::ModuleId m : s.entering) s.mark(m, Impl::kRenew, false);
      std::sort(gained.begin(), gained.end());
    }
    s.graph = std::make_shared<const sim::NeighborGraph>(
        s.graph->changed(gone, made, rewindowed ? std::move(window) : nullptr, gained));
    return s.graph;
  }

  Impl& s;
  const sim::Bodies& bodies;
  const sim::PagedArray<sim::Pose, sim::CellPose>& poses;
  std::span<const uint8_t> present;
  sim::RankExchange* ranks;
  const sim::ModuleOwners* owners;
  const size_t n;
  const bool windowed;
  bool forget = false;  // every pair is measured: the last measurement is of another state
  // Over ranks, the window now (set by rewindow) and the one the last graph held.
  std::shared_ptr<const std::vector<uint8_t>> window;
  const std::vector<uint8_t>* was_held = nullptr;
  std::vector<Pair> hinges;          // each pivot with the neighbour it turns on, as (lower, higher)
  std::vector<Pair> dropped, fresh;  // the pairs measured again as they were, and as they are
  uint64_t measured = 0;             // pairs_measured()
};

std::shared_ptr<const sim::NeighborGraph> ContactGraph::update(
    const sim::Bodies& bodies, std::span<const uint8_t> present, sim::WorkerPool& workers,
    const std::vector<sim::ModuleId>* changed, sim::RankExchange* ranks, const sim::ModuleOwners* owners) {
  if (ranks != nullptr && owners == nullptr)
    throw std::logic_error("ContactGraph::update over ranks needs the modules' owners");
  Impl::Pass pass(*impl_, bodies, present, ranks, owners);
  measured_ = 0;
  if (!pass.look(changed)) {
    // Over ranks what a rank finds changed depends on what it remembers: each takes part in the
    // sum of the counts all the same.
    if (ranks != nullptr) ranks->sum(std::span(&measured_, 1));
    return impl_->graph;
  }
  pass.rewindow();
  pass.read_stale();
  pass.choose_searchers();
  pass.measure(workers);
  measured_ = pass.measured;
  pass.remember();
  return pass.make_graph();
}

}  // namespace dw::physics
