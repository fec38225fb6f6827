// Notes on steps of the history (docs/session.md, `mark`; the window's timeline): a person's marks,
// one per step, kept across branches (a mark names a step, not what happened there) and saved with
// the scenario as [[bookmark]] tables.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace dw::sim {

struct Bookmark {
  int64_t at = 0;
  std::string note;
  bool operator==(const Bookmark&) const = default;
};

class Bookmarks {
 public:
  Bookmarks() = default;
  // By step; of two on one step, the later in `marks` stays.
  explicit Bookmarks(const std::vector<Bookmark>& marks) {
    for (const Bookmark& b : marks) mark(b.at, b.note);
  }
  // Marks step `at`, replacing its note if it had one.
  void mark(int64_t at, std::string note) {
    const auto it =
        std::lower_bound(marks_.begin(), marks_.end(), at, [](const Bookmark& b, int64_t t) { return b.at < t; });
    if (it != marks_.end() && it->at == at) it->note = std::move(note);
    else marks_.insert(it, Bookmark{at, std::move(note)});
  }
  // False when step `at` has no mark.
  bool unmark(int64_t at) {
    return std::erase_if(marks_, [at](const Bookmark& b) { return b.at == at; }) > 0;
  }
  const std::vector<Bookmark>& all() const { return marks_; }

 private:
  std::vector<Bookmark> marks_;  // sorted by step
};

}  // namespace dw::sim
