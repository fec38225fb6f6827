// The PatternMatcher (paper §III, Fig. 4) as a compact byte record, laid out once per Program, so
// that creating, filling and sending one never allocates:
//
//   uint32 header (filled: low 8 bits, bytes: high 24) | uint32 ids[k] | int64 cells[C] |
//   Truth leaves[L] | uint8 cell_known[C] | pad to 4 | sets: (uint32 count, uint32 ids[count])*
//
// where a record of the sets may instead be a table of an aggregate's neighbours (docs/design.md §4b):
// uint32 count | uint32 words | rows, each uint32 id | (int64 value, uint32 known) per read |
// (uint32 count, uint32 ids[count]) per neighbour set read; `words` counts the rows' words.
//
// For a plain conjunction (Program::Shape::Conjunction) `leaves` is a single Truth: the and of
// every leaf decided so far, which is all the expression needs (and with U never undoes an F).
// `ids` are the modules in the filled slots; `leaves` the truth of every leaf decided so far
// (Unknown until its decide slot fills); `cells` the carried values; `sets` the carried neighbour
// sets, appended as the slots that own them fill. A set whose module was absent has count
// kUnknownSet and no ids.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "watch/kleene.h"
#include "watch/program.h"

namespace dw::watch {

constexpr uint32_t kUnknownSet = 0xFFFFFFFFu;
// The header keeps a record's size in 24 bits.
constexpr uint32_t kMaxPatternMatcherBytes = (1u << 24) - 4;

struct PatternMatcherLayout {
  explicit PatternMatcherLayout(const Program& p)
      : slots(static_cast<uint32_t>(p.slot_count())),
        leaf_count(p.shape == Program::Shape::Conjunction ? 1 : static_cast<uint32_t>(p.leaves.size())),
        cell_count(static_cast<uint32_t>(p.cells.size())),
        conjunction(p.shape == Program::Shape::Conjunction) {
    for (const CarriedSet& s : p.sets) table.push_back(s.aggregate >= 0);
    ids = 4;
    cells = ids + 4 * slots;
    leaves = cells + 8 * cell_count;
    known = leaves + leaf_count;
    sets = (known + cell_count + 3) & ~3u;
  }

  uint32_t slots, leaf_count, cell_count;  // leaf_count: Truth bytes in the record
  bool conjunction;
  std::vector<uint8_t> table;                // per carried record: a table rather than a set
  uint32_t cells, ids, leaves, known, sets;  // byte offsets; `sets` is also the size with no sets
};

// A view of one record in a buffer owned elsewhere.
class PatternMatcherRef {
 public:
  PatternMatcherRef(std::byte* data, const PatternMatcherLayout& layout) : d_(data), l_(&layout) {}

  // The size of the record at `data`, read from its header.
  static uint32_t bytes_of(const std::byte* data) {
    uint32_t header;
    std::memcpy(&header, data, 4);
    return header >> 8;
  }

  uint32_t filled() const { return load32(0) & 0xFF; }
  void set_filled(uint32_t n) { store32(0, (load32(0) & ~0xFFu) | n); }
  uint32_t bytes() const { return load32(0) >> 8; }
  void set_bytes(uint32_t n) { store32(0, (load32(0) & 0xFFu) | (n << 8)); }

  uint32_t id(uint32_t slot) const { return load32(l_->ids + 4 * slot); }
  void set_id(uint32_t slot, uint32_t m) { store32(l_->ids + 4 * slot, m); }

  Truth* leaves() { return reinterpret_cast<Truth*>(d_ + l_->leaves); }
  const Truth* leaves() const { return reinterpret_cast<const Truth*>(d_ + l_->leaves); }

  bool cell(uint32_t c, int64_t& value) const {
    std::memcpy(&value, d_ + l_->cells + 8 * c, 8);
    return static_cast<bool>(d_[l_->known + c]);
  }
  void set_cell(uint32_t c, int64_t value, bool known) {
    std::memcpy(d_ + l_->cells + 8 * c, &value, 8);
    d_[l_->known + c] = static_cast<std::byte>(known);
  }

  // The carried neighbour set number `index` (in Program::sets order); count kUnknownSet when the
  // module was absent at that step.
  const uint32_t* set(uint32_t index, uint32_t& count) const {
    const uint32_t at = record(index);
    count = load32(at);
    return reinterpret_cast<const uint32_t*>(d_ + at + 4);
  }
  // Where carried record `index` (a set or a table) starts.
  uint32_t record(uint32_t index) const {
    uint32_t at = l_->sets;
    for (uint32_t i = 0; i < index; ++i) {
      const uint32_t count = load32(at);
      if (l_->table[i]) at += 8 + 4 * load32(at + 4);
      else at += 4 + (count == kUnknownSet ? 0 : 4 * count);
    }
    return at;
  }

  // Starts an empty record: nothing filled, every leaf Unknown.
  void init() {
    store32(0, l_->sets << 8);  // nothing filled
    // Every byte defined (ids of empty slots, unknown cells, padding): a record is hashed and
    // compared bit for bit, and must not carry what the scratch buffer held before.
    std::memset(d_ + 4, 0, l_->sets - 4);
    std::memset(d_ + l_->leaves, l_->conjunction ? kTrue : kUnknown, l_->leaf_count);
  }

  std::byte* data() { return d_; }
  const std::byte* data() const { return d_; }
  uint32_t word(uint32_t at) const { return load32(at); }

 private:
  uint32_t load32(uint32_t at) const {
    uint32_t v;
    std::memcpy(&v, d_ + at, 4);
    return v;
  }
  void store32(uint32_t at, uint32_t v) { std::memcpy(d_ + at, &v, 4); }

  std::byte* d_;
  const PatternMatcherLayout* l_;
};

}  // namespace dw::watch
