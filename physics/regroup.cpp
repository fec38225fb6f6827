#include "physics/regroup.h"

#include <limits>
#include <numeric>

#include "physics/clusters.h"
#include "physics/union_find.h"
#include "sim/sorted_vector.h"

namespace dw::physics {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// The listed module-module bonds of `bonds` (sorted), each as {b, a}, sorted.
std::vector<sim::Bond> reversed_listed(const sim::BondSet& set, std::span<const sim::Bond> bonds) {
  std::vector<sim::Bond> out;
  for (const sim::Bond& x : bonds)
    if (set.bit(x) == 0) out.push_back({x.b, x.a});
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

void BondIndex::rebuild(const sim::BondSet& bonds) {
  reversed_ = reversed_listed(bonds, bonds.listed());
  valid_ = true;
}

void BondIndex::apply(const sim::BondSet& bonds, std::span<const sim::Bond> removed, std::span<const sim::Bond> added) {
  sim::erase_from<sim::Bond>(reversed_, reversed_listed(bonds, removed));
  sim::merge_into<sim::Bond>(reversed_, reversed_listed(bonds, added));
}

void BondChanges::clear() {
  removed.clear();
  added.clear();
  stopped.clear();
  started.clear();
}

void BondChanges::normalize() {
  const auto sort_unique = [](auto& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  };
  sort_unique(stopped);
  sort_unique(started);
  // A bond's changes alternate (it cannot go twice without coming back between), so what it ends
  // as is told by how many times it went and came: as many, no change.
  std::sort(removed.begin(), removed.end());
  std::sort(added.begin(), added.end());
  std::vector<sim::Bond> gone, made;
  for (size_t i = 0, j = 0; i < removed.size() || j < added.size();) {
    const sim::Bond x = j == added.size() || (i < removed.size() && removed[i] < added[j]) ? removed[i] : added[j];
    size_t went = 0, came = 0;
    for (; i < removed.size() && removed[i] == x; ++i) ++went;
    for (; j < added.size() && added[j] == x; ++j) ++came;
    if (went > came) gone.push_back(x);
    if (came > went) made.push_back(x);
  }
  removed.swap(gone);
  added.swap(made);
}

// A part of the still modules found while regrouping: a piece cut off a cluster (found whole by a
// search that ran out), the rest of a cluster (what no such search found), or a module that came
// to rest. Pieces joined by bonds made form one cluster.
struct Regrouper::Piece {
  std::vector<sim::ModuleId> members;  // ascending; for a rest, filled when the clusters are put together
  uint32_t cluster = kNone;            // the cluster it was part of, or none
  bool rest = false;
};

struct Regrouper::Scratch {
  std::vector<uint32_t> label;  // per module: its piece, or its search while searching, or none
  std::vector<Piece> pieces;
  // The searches of one cluster: what each found (in order: its queue), how far it went, the
  // search it joined, and, for a search no other joined, the searches now its own.
  std::vector<std::vector<sim::ModuleId>> found;
  std::vector<size_t> next;
  std::vector<uint32_t> parent;
  std::vector<std::vector<uint32_t>> owns;
  std::vector<size_t> cursor;
  std::vector<uint8_t> done;
  std::vector<uint8_t> still;          // per module: present and not making a lattice move
  std::vector<sim::ModuleId> members;  // the next b.members
  // The clusters something changed in, and (cluster, member) for each still member that lost bonds.
  std::vector<uint32_t> dirty;
  std::vector<std::pair<uint32_t, sim::ModuleId>> seeds;
  std::vector<std::pair<uint32_t, uint32_t>> rest_of;  // (changed cluster, its rest piece), by cluster
};

Regrouper::Regrouper() : s_(std::make_unique<Scratch>()) {}
Regrouper::~Regrouper() = default;

// Searches `cluster` from `seeds` (its still members that lost bonds, ascending), a module of
// each search in turn, until one search is left: every search that ran out found a piece (added
// to the pieces); searches that meet go on as one. The pieces do not depend on the order.
void Regrouper::search(const sim::Bodies& b, const BondIndex& index, uint32_t cluster,
                       std::span<const sim::ModuleId> seeds) {
  Scratch& s = *s_;
  const auto count = static_cast<uint32_t>(seeds.size());
  s.found.assign(count, {});
  s.next.assign(count, 0);
  s.parent.resize(count);
  std::iota(s.parent.begin(), s.parent.end(), 0u);
  s.owns.assign(count, {});
  s.cursor.assign(count, 0);
  s.done.assign(count, 0);
  std::vector<uint32_t> active(count);
  for (uint32_t i = 0; i < count; ++i) {
    s.found[i].push_back(seeds[i]);
    s.label[seeds[i]] = i;
    s.owns[i].push_back(i);
    active[i] = i;
  }
  const auto inside = [&](sim::ModuleId o) { return b.cluster_of[o] == cluster && s.still[o]; };
  uint32_t live = count;
  while (live > 1) {
    for (size_t i = 0; i < active.size() && live > 1; ++i) {
      const uint32_t root = active[i];
      if (s.parent[root] != root || s.done[root]) continue;
      // Its next module, from the first of its searches with one queued (searches that joined it
      // later are listed after: one before the cursor never queues again).
      const std::vector<uint32_t>& own = s.owns[root];
      size_t& cursor = s.cursor[root];
      while (cursor < own.size() && s.next[own[cursor]] == s.found[own[cursor]].size()) ++cursor;
      if (cursor == own.size()) {  // ran out: a piece
        Piece piece{.cluster = cluster};
        for (uint32_t k : own) piece.members.insert(piece.members.end(), s.found[k].begin(), s.found[k].end());
        std::sort(piece.members.begin(), piece.members.end());
        for (sim::ModuleId m : piece.members) s.label[m] = static_cast<uint32_t>(s.pieces.size());
        s.pieces.push_back(std::move(piece));
        s.done[root] = 1;
        --live;
        continue;
      }
      const uint32_t queue = own[cursor];
      const sim::ModuleId m = s.found[queue][s.next[queue]++];
      ++searched_;
      index.partners(b.bonds, m, [&](sim::ModuleId o) {
        if (!inside(o)) return;
        if (s.label[o] == kNone) {
          s.label[o] = queue;
          s.found[queue].push_back(o);
          return;
        }
        const uint32_t me = find_root(s.parent, queue), other = find_root(s.parent, s.label[o]);
        if (me == other) return;
        // The searches met: the one owning more searches takes the other's.
        const bool keep_me = s.owns[me].size() >= s.owns[other].size();
        const uint32_t into = keep_me ? me : other, from = keep_me ? other : me;
        s.parent[from] = into;
        s.owns[into].insert(s.owns[into].end(), s.owns[from].begin(), s.owns[from].end());
        s.owns[from].clear();
        --live;
      });
    }
    std::erase_if(active, [&](uint32_t r) { return s.parent[r] != r || s.done[r]; });
  }
  // What the last search found is the rest's: unlabel it.
  for (uint32_t root : active)
    for (uint32_t k : s.owns[root])
      for (sim::ModuleId m : s.found[k]) s.label[m] = kNone;
}

// A new cluster: its frame and members (the largest piece's, with the others merged in) and the
// pieces it was made of.
struct Regrouper::Made {
  sim::Cluster c;
  std::vector<sim::ModuleId> members;
  std::vector<uint32_t> pieces;
};

void Regrouper::operator()(sim::Bodies& b, std::span<const uint8_t> present, const BondChanges& changes,
                           const BondIndex& index, btCollisionShape& module_shape) {
  Scratch& s = *s_;
  const size_t n = b.poses.size();
  s.label.resize(n, kNone);
  s.pieces.clear();
  searched_ = 0;
  s.still.assign(present.begin(), present.end());
  for (const sim::Mover& mover : b.movers) s.still[mover.module] = 0;
  find_changed(b, changes);
  cut_pieces(b, changes, index);
  std::vector<Made> made = join_pieces(b, changes);
  frame_clusters(b, changes, made, module_shape);
  put_clusters(b, changes, made);
  for (const Piece& p : s.pieces)
    if (!p.rest)  // a rest's members were never labelled
      for (sim::ModuleId m : p.members) s.label[m] = kNone;
}

// The clusters something changed in (`dirty`), and the members that lost bonds (`seeds`, where a
// split may start), each sorted.
void Regrouper::find_changed(const sim::Bodies& b, const BondChanges& changes) {
  Scratch& s = *s_;
  s.dirty.clear();
  s.seeds.clear();
  const auto touch = [&](sim::ModuleId m, bool lost_bond) {
    if (m == sim::kGround || b.cluster_of[m] == sim::kNoCluster) return;
    s.dirty.push_back(b.cluster_of[m]);
    if (lost_bond && s.still[m]) s.seeds.emplace_back(b.cluster_of[m], m);
  };
  for (const sim::Bond& x : changes.removed) {
    touch(x.a, x.b != sim::kGround);
    touch(x.b, true);
  }
  for (const sim::Bond& x : changes.added) {
    touch(x.a, false);
    touch(x.b, false);
  }
  for (sim::ModuleId m : changes.stopped) touch(m, false);
  std::sort(s.dirty.begin(), s.dirty.end());
  s.dirty.erase(std::unique(s.dirty.begin(), s.dirty.end()), s.dirty.end());
  std::sort(s.seeds.begin(), s.seeds.end());
  s.seeds.erase(std::unique(s.seeds.begin(), s.seeds.end()), s.seeds.end());
}

// The pieces: those cut off each changed cluster, then its rest (the still members no search cut
// off); and modules that came to rest alone.
void Regrouper::cut_pieces(const sim::Bodies& b, const BondChanges& changes, const BondIndex& index) {
  Scratch& s = *s_;
  s.rest_of.clear();
  for (size_t i = 0, j = 0; i < s.dirty.size(); ++i) {
    std::vector<sim::ModuleId> mine;
    for (; j < s.seeds.size() && s.seeds[j].first == s.dirty[i]; ++j) mine.push_back(s.seeds[j].second);
    if (mine.size() > 1) search(b, index, s.dirty[i], mine);
    s.rest_of.emplace_back(s.dirty[i], static_cast<uint32_t>(s.pieces.size()));
    s.pieces.push_back({.cluster = s.dirty[i], .rest = true});
  }
  for (sim::ModuleId m : changes.started)
    if (s.still[m] && s.label[m] == kNone && b.cluster_of[m] == sim::kNoCluster) {
      s.label[m] = static_cast<uint32_t>(s.pieces.size());
      s.pieces.push_back({.members = {m}});
    }
  for (Piece& p : s.pieces) {
    if (!p.rest) continue;
    const sim::Cluster& c = b.clusters[p.cluster];
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      const sim::ModuleId m = b.members[i];
      if (s.still[m] && s.label[m] == kNone) p.members.push_back(m);
    }
  }
}

// Pieces joined by bonds made are one cluster: the new clusters, each with its members and
// whether it is anchored.
std::vector<Regrouper::Made> Regrouper::join_pieces(const sim::Bodies& b, const BondChanges& changes) {
  Scratch& s = *s_;
  const auto still = [&](sim::ModuleId m) { return s.still[m] != 0; };
  const auto piece_of = [&](sim::ModuleId m) {
    if (s.label[m] != kNone) return s.label[m];
    return std::lower_bound(s.rest_of.begin(), s.rest_of.end(), std::pair{b.cluster_of[m], 0u})->second;
  };
  std::vector<uint32_t> parent(s.pieces.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const sim::Bond& x : changes.added)
    if (x.b != sim::kGround && still(x.a) && still(x.b)) {
      const uint32_t p = find_root(parent, piece_of(x.a)), q = find_root(parent, piece_of(x.b));
      parent[std::max(p, q)] = std::min(p, q);
    }
  std::vector<std::vector<uint32_t>> joined(s.pieces.size());
  for (uint32_t p = 0; p < s.pieces.size(); ++p)
    if (!s.pieces[p].members.empty()) joined[find_root(parent, p)].push_back(p);

  std::vector<Made> made;
  for (std::vector<uint32_t>& group : joined) {
    if (group.empty()) continue;
    const uint32_t largest = *std::max_element(group.begin(), group.end(), [&](uint32_t p, uint32_t q) {
      return s.pieces[p].members.size() < s.pieces[q].members.size();
    });
    std::vector<sim::ModuleId> members = s.pieces[largest].members, others;
    for (uint32_t p : group)
      if (p != largest) others.insert(others.end(), s.pieces[p].members.begin(), s.pieces[p].members.end());
    std::sort(others.begin(), others.end());
    sim::merge_into<sim::ModuleId>(members, others);
    sim::Cluster c;
    c.count = static_cast<uint32_t>(members.size());
    c.anchored = std::any_of(members.begin(), members.end(), [&](sim::ModuleId m) {
      return b.bonds.contains({m, sim::kGround});
    });
    made.push_back({c, std::move(members), std::move(group)});
  }
  return made;
}

// Frames, as settle gives them; the new clusters then sorted by smallest member. An anchored
// cluster's is the world's whatever its members, and a member that was in an anchored cluster
// already has its world pose as its pose in it and no velocity (and keeps its frame for the
// contact graph): only the others are looked at, so the rest of a latched block of a million is
// not walked. Any other member of a new cluster may be reframed.
void Regrouper::frame_clusters(sim::Bodies& b, const BondChanges& changes, std::vector<Made>& made,
                               btCollisionShape& module_shape) {
  const Scratch& s = *s_;
  reframed_.assign(changes.stopped.begin(), changes.stopped.end());
  const auto was_anchored = [&](sim::ModuleId m) {
    return b.cluster_of[m] != sim::kNoCluster && b.clusters[b.cluster_of[m]].anchored;
  };
  for (Made& k : made) {
    if (!k.c.anchored) {
      settle(b, k.c, k.members, module_shape);
      reframed_.insert(reframed_.end(), k.members.begin(), k.members.end());
      continue;
    }
    k.c.pose = sim::Pose{};
    k.c.velocity = {};
    for (uint32_t p : k.pieces) {
      const Piece& piece = s.pieces[p];
      if (piece.rest && b.clusters[piece.cluster].anchored) continue;
      for (sim::ModuleId m : piece.members) {
        if (was_anchored(m)) continue;
        b.velocities.set(m, {});
        reframed_.push_back(m);
      }
    }
  }
  std::sort(made.begin(), made.end(), [](const Made& x, const Made& y) { return x.members[0] < y.members[0]; });
}

// The clusters of b: those nothing changed in keep their place among the new ones, by smallest
// member, and every module's cluster_of follows (a moving cluster renamed reframes its members).
void Regrouper::put_clusters(sim::Bodies& b, const BondChanges& changes, const std::vector<Made>& made) {
  Scratch& s = *s_;
  std::vector<sim::Cluster> clusters;
  clusters.reserve(b.clusters.size() + made.size());
  s.members.clear();
  s.members.reserve(b.members.size() + changes.started.size());
  std::vector<std::pair<uint32_t, uint32_t>> renamed;  // (old index, new index) of kept clusters that moved
  size_t next_made = 0;
  const auto add = [&](sim::Cluster c, std::span<const sim::ModuleId> members) {
    c.first = static_cast<uint32_t>(s.members.size());
    s.members.insert(s.members.end(), members.begin(), members.end());
    clusters.push_back(c);
  };
  const auto add_made_before = [&](sim::ModuleId smallest) {
    for (; next_made < made.size() && made[next_made].members[0] < smallest; ++next_made) {
      const Made& k = made[next_made];
      const auto now = static_cast<uint32_t>(clusters.size());
      // The rest of a cluster that keeps its index keeps its members' cluster_of.
      for (uint32_t p : k.pieces)
        if (!(s.pieces[p].rest && s.pieces[p].cluster == now))
          for (sim::ModuleId m : s.pieces[p].members) b.cluster_of.set(m, now);
      add(k.c, k.members);
    }
  };
  for (uint32_t old = 0, d = 0; old < b.clusters.size(); ++old) {
    if (d < s.dirty.size() && s.dirty[d] == old) {
      ++d;
      continue;
    }
    const sim::Cluster& c = b.clusters[old];
    const std::span<const sim::ModuleId> members(b.members.data() + c.first, c.count);
    add_made_before(members[0]);
    if (clusters.size() != old) renamed.emplace_back(old, static_cast<uint32_t>(clusters.size()));
    add(c, members);
  }
  add_made_before(sim::kGround);
  for (const auto& [old, now] : renamed) {
    const sim::Cluster& c = clusters[now];
    const bool moves = !c.anchored && c.count > 1;  // its members' frames name the cluster
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      b.cluster_of.set(s.members[i], now);
      if (moves) reframed_.push_back(s.members[i]);
    }
  }
  for (sim::ModuleId m : changes.stopped)
    if (!s.still[m]) b.cluster_of.set(m, sim::kNoCluster);
  b.clusters = std::move(clusters);
  b.members.swap(s.members);
}

}  // namespace dw::physics
