#include "sim/state.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <type_traits>

namespace dw::sim {
namespace {

// FNV-1a over 64-bit words, with a final mix.
struct Hasher {
  uint64_t h = 0xcbf29ce484222325ull;
  void word(uint64_t w) {
    h ^= w;
    h *= 0x100000001b3ull;
    h ^= h >> 29;
  }
  template <class T>
  void words(const std::vector<T>& v) {
    word(v.size());
    for (const T& x : v) word(static_cast<uint64_t>(x));
  }
  // Plain-data records (poses, bonds, ...), hashed bit for bit.
  template <class T>
  void records(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    word(v.size());
    if (!v.empty()) bytes(reinterpret_cast<const std::byte*>(v.data()), v.size() * sizeof(T));
  }
  template <class T>
  void record(const T& x) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(reinterpret_cast<const std::byte*>(&x), sizeof x);
  }
  void bytes(const std::byte* p, size_t n) {
    for (size_t i = 0; i + 8 <= n; i += 8) {
      uint64_t w;
      std::memcpy(&w, p + i, 8);
      word(w);
    }
    uint64_t tail = 0;
    std::memcpy(&tail, p + (n & ~size_t{7}), n & 7);
    word(tail ^ n);
  }
};

uint64_t mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

WatchState::WatchState(const WatchState& other) { *this = other; }

WatchState& WatchState::operator=(const WatchState& other) {
  if (this == &other) return *this;
  detector = other.detector ? other.detector->clone() : nullptr;
  agents = other.agents;
  in_flight = other.in_flight;
  matches = other.matches;
  actions_done = other.actions_done;
  actions_skipped = other.actions_skipped;
  stopped = other.stopped;
  stop_reason = other.stop_reason;
  return *this;
}

std::string hash_text(uint64_t hash) {
  char text[19];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(hash));
  return text;
}

State simulation_part(const State& s, std::vector<int64_t> values) {
  State c;
  c.step = s.step;
  c.values = std::move(values);
  c.present = s.present;
  c.graph = s.graph;
  c.bodies = s.bodies;
  c.inbox = s.inbox;
  c.program_messages = s.program_messages;
  c.run_hash = s.run_hash;
  c.actions = s.actions;
  c.watches.resize(s.watches.size());
  return c;
}

InFlightDigest in_flight_digest(const WatchState& w) {
  InFlightDigest d;
  for (const watch::RecordBuffer& lane : w.in_flight)
    lane.visit([&](uint32_t to, const std::byte* pm, uint32_t bytes) {
      Hasher one;
      one.word(to);
      one.bytes(pm, bytes);
      d.sum += mix(one.h);
      ++d.count;
    });
  return d;
}

uint64_t StateHash::whole() const { return mix(simulation ^ mix(watches + 0x9E3779B97F4A7C15ull)); }

std::string hash_text(const StateHash& hash) {
  return hash_text(hash.whole()) + " (simulation " + hash_text(hash.simulation) + ", watchpoints " +
         hash_text(hash.watches) + ")";
}

namespace {

// hash_state's sequences, read from one process's whole state.
template <class Use>
auto with_own_pieces(const State& s, Use use) {
  const ModuleId linked = s.graph ? s.graph->module_count() : 0;
  const auto modules = static_cast<ModuleId>(s.bodies.poses.size());
  return use(HashPieces{s.values.size(), [&](uint64_t h) { return continue_hash(h, s.values); }, linked,
                        [&](uint64_t h) { return continue_hash(h, *s.graph, 0, linked); }, modules,
                        [&](uint64_t h) { return continue_hash(h, s.bodies, 0, modules); }, s.inbox.messages.size(),
                        [&](uint64_t h) { return continue_hash(h, s.inbox.messages.all()); }});
}

}  // namespace

StateHash hash_state(const State& s) {
  std::vector<InFlightDigest> digests;
  for (const WatchState& w : s.watches) digests.push_back(in_flight_digest(w));
  return with_own_pieces(s, [&](const HashPieces& pieces) { return hash_state(s, digests, pieces); });
}

uint64_t simulation_hash(const State& s) {
  return with_own_pieces(s, [&](const HashPieces& pieces) { return simulation_hash(s, pieces); });
}

uint64_t continue_hash(uint64_t h, const NeighborGraph& graph, ModuleId first, ModuleId end) {
  Hasher hasher{h};
  for (ModuleId m = first; m < end; ++m) {
    const std::span<const ModuleId> neighbors = graph.neighbors(m);
    hasher.word(neighbors.size());
    for (ModuleId n : neighbors) hasher.word(n);
  }
  return hasher.h;
}

uint64_t continue_hash(uint64_t h, std::span<const int64_t> values) {
  Hasher hasher{h};
  for (int64_t x : values) hasher.word(static_cast<uint64_t>(x));
  return hasher.h;
}

uint64_t continue_hash(uint64_t h, const Bodies& b, ModuleId first, ModuleId end) {
  // A module's three records are 80 bytes, ten words: read bit for bit, a module at a time.
  struct ModuleRecords {
    Pose pose;
    Velocity velocity;
    Pose local;
  };
  static_assert(sizeof(ModuleRecords) == 80 && std::is_trivially_copyable_v<ModuleRecords>);
  Hasher hasher{h};
  // The movers are sorted by module: each module's is the next.
  auto mover = std::lower_bound(b.movers.begin(), b.movers.end(), first,
                                [](const Mover& x, ModuleId id) { return x.module < id; });
  std::vector<ModuleId> bonded;  // a module's bonds to larger ids and the ground
  for (ModuleId m = first; m < end; ++m) {
    const ModuleRecords records{b.poses[m], b.velocities[m], b.pose_in_cluster(m)};
    uint64_t words[10];
    std::memcpy(words, &records, sizeof records);
    for (uint64_t w : words) hasher.word(w);
    hasher.word(b.cluster_of[m]);
    bonded.clear();
    b.bonds.above(m, [&](ModuleId o) { bonded.push_back(o); });
    hasher.word(bonded.size());
    for (ModuleId o : bonded) hasher.word(o);
    const bool moving = mover != b.movers.end() && mover->module == m;
    hasher.word(moving);
    if (moving) {
      hasher.record(mover->from);
      hasher.record(mover->to);
      hasher.word(static_cast<uint64_t>(mover->start));
      hasher.word(static_cast<uint64_t>(mover->steps));
      hasher.record(mover->pivot);
      hasher.record(mover->axis);
      hasher.record(mover->angle);
      hasher.record(mover->spin);
      if (mover->hinge != kNoHinge) hasher.word(mover->hinge);  // a pivot's (a lattice move hashes as before)
      ++mover;
    }
  }
  return hasher.h;
}

uint64_t continue_hash(uint64_t h, Messages messages) {
  Hasher hasher{h};
  for (const Message& m : messages) {
    hasher.word((uint64_t{m.from} << 32) | m.to);
    hasher.word((uint64_t{m.program} << 16) | m.size);
    for (int64_t w : m.payload()) hasher.word(static_cast<uint64_t>(w));
  }
  return hasher.h;
}

uint64_t simulation_hash(const State& s, const HashPieces& pieces) {
  Hasher h;
  h.word(static_cast<uint64_t>(s.step));
  h.word(pieces.value_count);
  h.h = pieces.values(h.h);
  h.words(s.present);
  h.word(pieces.graph_count);
  if (pieces.graph_count != 0) h.h = pieces.graph(h.h);
  // The bodies, when the world has any: each module's records, bonds and lattice move in module
  // order (held in pieces over ranks), then what belongs to no one module.
  const Bodies& b = s.bodies;
  if (pieces.body_count != 0 || !b.prop_poses.empty()) {
    h.word(pieces.body_count);
    if (pieces.body_count != 0) h.h = pieces.bodies(h.h);
    h.word(b.clusters.size());
    for (const Cluster& c : b.clusters) {
      h.record(c.pose);
      h.record(c.velocity);
      h.word((uint64_t{c.first} << 32) | c.count);
      h.word((uint64_t{c.still} << 1) | c.anchored);
    }
    h.words(b.members);
    h.records(b.prop_poses);
    h.records(b.prop_velocities);
    // The contact cache (design §8a), when there is one: a world without contacts hashes as before.
    if (!b.contacts.empty()) {
      h.word(b.contacts.size());
      h.records(b.contacts);
    }
  }
  h.word(pieces.message_count);
  h.h = pieces.messages(h.h);
  h.word(s.program_messages);
  // Watchpoints' actions (docs/design.md §4b), when there are any: a run without them hashes as it did.
  if (!s.actions.empty()) h.word(s.actions.size());
  for (const PendingAction& a : s.actions) {
    h.word(a.module);  // not the watchpoint's index: the simulation is the same under other watchpoints
    h.word((static_cast<uint64_t>(static_cast<uint32_t>(a.column)) << 2) | (uint64_t{a.remove} << 1) | a.known);
    h.word(static_cast<uint64_t>(a.value));
  }
  return mix(h.h);
}

uint64_t next_run_hash(uint64_t run_before, uint64_t simulation) {
  Hasher h{run_before};
  h.word(simulation);
  return mix(h.h);
}

StateHash hash_state(const State& s, std::span<const InFlightDigest> in_flight, const HashPieces& pieces) {
  const uint64_t simulation = simulation_hash(s, pieces);
  Hasher watches;
  watches.word(s.watches.size());
  for (size_t w = 0; w < s.watches.size(); ++w) {
    Hasher& h = watches;
    h.word(s.watches[w].matches);
    if (s.watches[w].actions_done || s.watches[w].actions_skipped) {
      h.word(s.watches[w].actions_done);
      h.word(s.watches[w].actions_skipped);
    }
    h.word(s.watches[w].stopped);
    h.word(in_flight[w].sum);
    h.word(in_flight[w].count);
  }
  return {simulation, mix(watches.h), s.run_hash};
}

template <class T>
size_t vector_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

size_t graph_bytes(const NeighborGraph& g) { return vector_bytes(g.begin) + vector_bytes(g.ids); }

size_t state_bytes(const State& s) {
  // A heap block costs its size plus about 16 bytes of the allocator's.
  constexpr size_t kBlock = 16;
  const Bodies& b = s.bodies;
  size_t n = sizeof(State) + vector_bytes(s.values) + vector_bytes(s.present) + b.poses.bytes() + b.velocities.bytes() +
             b.local.bytes() + b.cluster_of.bytes() + vector_bytes(b.clusters) + vector_bytes(b.members) +
             b.bonds.bytes() + vector_bytes(b.movers) + vector_bytes(b.prop_poses) + vector_bytes(b.prop_velocities) +
             vector_bytes(b.contacts) + vector_bytes(s.inbox.begin) + s.inbox.messages.bytes() +
             vector_bytes(s.actions) + 16 * kBlock;
  for (const WatchState& w : s.watches) {
    n += sizeof(WatchState) + vector_bytes(w.in_flight);
    if (w.agents) n += w.agents->bytes();
    for (const watch::RecordBuffer& lane : w.in_flight) n += lane.bytes();
    if (w.detector) n += w.detector->bytes();
  }
  return n;
}

}  // namespace dw::sim
