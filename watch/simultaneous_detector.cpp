#include "watch/simultaneous_detector.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "watch/connected_groups.h"

namespace dw::watch {
namespace {

constexpr uint32_t kNoParent = ~uint32_t{0};
constexpr uint32_t kHeaderBytes = 16;  // t0, target and the walk's state, as a message carries them

}  // namespace

SimultaneousDetector::SimultaneousDetector(const Watchpoint& w, const Universe& u, DetectorOptions options,
                                           MatchSink sink)
    : Detector(u, std::move(sink)),
      program_(std::make_shared<const Program>(w.program)),
      options_(options),
      shape_(group_shape(Algorithm::Distributed, options)),
      k_(static_cast<uint32_t>(w.program.slot_count())),
      latency_(hop_latency(shape_, w.program.slot_count())),
      leaf_words_(static_cast<uint32_t>((w.program.leaves.size() + 3) / 4)),
      fixed_words_(2 * k_ + leaf_words_),
      history_(*program_, u, options.optimizations.temporal_spans, latency_ + w.program.aggregate_hops),
      starts_(static_cast<size_t>(latency_) + 1, StartStep{StepView(*program_, u.module_count()), {}, {}, true}),
      search_(*program_, options.optimizations, 0, u.module_count()),
      mark_(u.module_count(), 0),
      stack_(static_cast<size_t>(w.program.max_stack)),
      trial_(w.program.leaves.size()) {}

std::unique_ptr<Detector> SimultaneousDetector::clone() const {
  auto copy = std::make_unique<SimultaneousDetector>(*this);
  // The views point into this detector's history: read the copy's own.
  for (int64_t t0 = std::max<int64_t>(0, next_f_ - 1 - latency_); t0 < next_f_; ++t0)
    copy->view(t0).resolve(copy->history_, t0, shape_ == GroupShape::Any);
  return copy;
}

size_t SimultaneousDetector::bytes() const {
  size_t n = sizeof(*this) + history_.bytes();
  for (const StartStep& s : starts_) n += s.view.bytes() + s.found.ids.capacity() * sizeof(uint32_t) + s.groups.bytes();
  n += (arriving_.capacity() + sent_.capacity()) * sizeof(Walker);
  return n + (arriving_words_.capacity() + sent_words_.capacity()) * sizeof(uint32_t);
}

void SimultaneousDetector::observe(const Frame& frame) {
  if (stats_.stopped) return;
  history_.record(frame);
  newest_ = frame.step;
  const int64_t f = frame.step - program_->agent_delay();
  if (f >= 0) step(f, true);
}

// The input has ended: PatternMatchers in flight go on over the last step's links until every
// start step that the frames decide is reported.
void SimultaneousDetector::finish() {
  // Start steps an aggregate's hop held back start now; then every PatternMatcher drains.
  const int64_t last_t0 = newest_ - program_->extent_plus;
  while (!stats_.stopped && next_f_ <= last_t0) step(next_f_, true);
  while (!stats_.stopped && next_f_ > 0 && next_f_ - latency_ <= last_t0) step(next_f_, false);
}

void SimultaneousDetector::step(int64_t f, bool start_new) {
  const auto started = std::chrono::steady_clock::now();
  step_ = StepStats{};
  step_.step = f;
  step_.live_by_filled.assign(k_ + 1, 0);
  if (start_new) {
    StartStep& s = at(f);
    s.view.resolve(history_, f, shape_ == GroupShape::Any);
    s.found.values = 0;
    if (program_->aggregate_hops > 0 && s.view.now() != nullptr)  // neighbours' values, one message each
      for (uint32_t m = 0; m < universe_.module_count(); ++m)
        if (s.view.present(m)) step_.value_messages += s.view.now()->neighbors(m).size();
    if (shape_ == GroupShape::Any && s.view.now() != nullptr)
      s.symmetric = s.groups.build(*s.view.now(), s.view.now()->present);
  }
  std::swap(arriving_, sent_);
  std::swap(arriving_words_, sent_words_);
  sent_.clear();
  sent_words_.clear();
  links_ = links(f);
  for (const Walker& w : arriving_) {
    if (!stop_reason_.empty()) break;
    arrive(w, arriving_words_.data() + w.data);  // each record is read once: filled in place
  }
  if (start_new && view(f).now() != nullptr)
    for (uint32_t m = 0; m < universe_.module_count() && stop_reason_.empty(); ++m)
      if (view(f).present(m)) start(f, m);
  next_f_ = f + 1;
  if (!stop_reason_.empty()) {
    stats_.stopped = true;
    stats_.stop_reason = stop_reason_ + " at detector step " + std::to_string(f);
    arriving_ = sent_ = {};
    arriving_words_ = sent_words_ = {};
    return;
  }
  step_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  stats_.add(step_);
  stats_.history_values = history_.held_values();
  if (f - latency_ >= 0) report(f - latency_);
}

void SimultaneousDetector::report(int64_t t0) {
  const MatchBuffer& m = at(t0).found;
  action_values(at(t0).view, *program_, {m.ids.data(), m.values}, actions_);
  emit(t0, {m.ids.data(), m.values}, actions_);
}

void SimultaneousDetector::arrive(const Walker& w, uint32_t* words) {
  if (links_ == nullptr || !links_->present[w.at]) {  // the module it hopped to has left
    ++step_.lost;
    return;
  }
  if (w.walking) return hop(w, words, fixed_words_ + 2u * w.ext);
  if (shape_ == GroupShape::Any) join_group(w, words);
  else fill_chain(w, words);
}

void SimultaneousDetector::start(int64_t t0, uint32_t module) {
  ++step_.created;
  Walker w;
  w.t0 = t0;
  w.at = w.target = module;
  if (start_words_.empty()) {  // no member, no parent, every leaf unknown
    start_words_.assign(fixed_words_, 0);
    start_words_[k_] = kNoParent;
    std::memset(start_words_.data() + 2 * k_, kUnknown, leaf_words_ * 4);
  }
  scratch_ = start_words_;
  uint32_t* words = scratch_.data();
  if (shape_ == GroupShape::Any) join_group(w, words);
  else fill_chain(w, words);
}

// Chain and ordered: the module at target fills the next slot with its state at t0, decides the
// leaves that slot completes, and sends the PatternMatcher on to each candidate for the slot after.
void SimultaneousDetector::fill_chain(Walker w, uint32_t* words) {
  const StepView& v = view(w.t0);
  const uint32_t slot = w.filled;
  uint32_t* members = words;
  uint32_t* parents = words + k_;
  Truth* leaves = reinterpret_cast<Truth*>(words + 2 * k_);
  members[slot] = w.target;
  ++step_.live_by_filled[slot + 1];
  ++step_.live;
  const SlotProgram& sp = program_->slots[slot];
  for (uint16_t l : sp.own_leaves) leaves[l] = v.own(l, w.target);
  for (uint16_t l : sp.carried_leaves) leaves[l] = v.decide(l, members);
  Truth* st = stack_.data();
  const Truth result = program_->evaluate(leaves, st);
  w.filled = static_cast<uint8_t>(slot + 1);
  if (w.filled == k_) {
    if (result == kTrue) {
      ++step_.matches;
      // MatchBuffer::add copies in chunks that may read past k ids: from a copy with room.
      uint32_t ids[kMaxSlots + kCopyChunk];
      std::memcpy(ids, members, 4 * size_t{k_});
      at(w.t0).found.add(ids, k_, ids[k_ - 1]);
    }
    return;
  }
  if (result == kFalse && options_.optimizations.early_termination) return;

  // Each candidate once, from the latest slot it neighbours at t0 (chain: the slot just filled).
  if (++generation_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0);
    generation_ = 1;
  }
  for (uint32_t j = 0; j <= slot; ++j) mark_[members[j]] = generation_;
  const SlotProgram& next = program_->slots[slot + 1];
  const bool cull = options_.optimizations.neighbor_culling && !next.cull_leaves.empty();
  std::vector<Truth>& trial = trial_;
  const uint32_t lowest = shape_ == GroupShape::Chain ? slot : 0;
  for (uint32_t j = slot + 1; j-- > lowest;) {
    for (uint32_t u : v.now()->neighbors(members[j])) {
      if (mark_[u] == generation_ || !v.present(u)) continue;
      mark_[u] = generation_;
      if (cull) {
        trial.assign(leaves, leaves + program_->leaves.size());
        for (uint16_t l : next.cull_leaves) {
          const Leaf& leaf = program_->leaves[l];
          trial[l] = v.neighbor(members[static_cast<size_t>(leaf.x)], leaf.offset, u);
        }
        if (program_->evaluate(trial.data(), st) == kFalse) continue;
      }
      Walker child = w;
      child.target = u;
      child.via = static_cast<uint8_t>(j);
      child.position = static_cast<uint8_t>(slot);
      parents[slot + 1] = j;
      ++step_.created;
      hop(child, words, fixed_words_);
      if (!stop_reason_.empty()) return;
    }
  }
}

// Any: the module at target joins the group (ESU); a complete group assigns the slots, an
// incomplete one extends by each module of its extension set in turn.
void SimultaneousDetector::join_group(Walker w, uint32_t* words) {
  StartStep& s = at(w.t0);
  const StepView& v = s.view;
  const uint32_t i = w.filled;
  uint32_t* members = words;
  uint32_t* parents = words + k_;
  const uint32_t* ext = words + fixed_words_;
  members[i] = w.target;
  ++step_.live_by_filled[i + 1];
  ++step_.live;
  // Early termination: a module that can fill no slot is in no match, nor is any group through it.
  if (options_.optimizations.early_termination && v.fillable(w.target) == 0) return;
  w.filled = static_cast<uint8_t>(i + 1);
  if (w.filled == k_) {
    const std::span<const uint32_t> group(members, k_);
    if (s.symmetric || rooted(*v.now(), group)) search_.assign(v, group, step_, s.found);
    return;
  }
  // The extension set: what is left of the one it came with, then the exclusive neighbours of
  // the new member (beside no earlier member), greater than the group's first module. Over a
  // graph with one-way links ESU grows over both ways; a hop against a one-way link is lost.
  if (++generation_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0);
    generation_ = 1;
  }
  for (uint32_t j = 0; j <= i; ++j) mark_[members[j]] = generation_;
  for (uint32_t j = 0; j < i; ++j)
    for (uint32_t u : s.groups.neighbors(members[j])) mark_[u] = generation_;
  std::vector<uint32_t>& all = ext_;
  all.assign(ext, ext + 2u * w.ext);
  for (uint32_t u : s.groups.neighbors(w.target)) {
    if (mark_[u] == generation_ || u <= members[0]) continue;
    mark_[u] = generation_;
    all.push_back(u);
    all.push_back(i);
  }
  const uint32_t entries = static_cast<uint32_t>(all.size() / 2);
  for (uint32_t e = 0; e < entries; ++e) {
    Walker child = w;
    child.target = all[2 * e];
    child.via = static_cast<uint8_t>(all[2 * e + 1]);
    child.position = static_cast<uint8_t>(i);
    child.ext = static_cast<uint16_t>(entries - e - 1);
    parents[i + 1] = all[2 * e + 1];
    // The child's words: the fixed part, then the entries after this one.
    std::vector<uint32_t>& copy = child_words_;
    copy.assign(words, words + fixed_words_);
    copy.insert(copy.end(), all.begin() + 2 * (e + 1), all.end());
    ++step_.created;
    hop(child, copy.data(), static_cast<uint32_t>(copy.size()));
    if (!stop_reason_.empty()) return;
  }
}

// The member after `from` on the tree path to member `to` (parents: the member each was reached from).
uint8_t SimultaneousDetector::toward(const uint32_t* parents, uint8_t from, uint8_t to) const {
  for (uint32_t a = to; parents[a] != kNoParent; a = parents[a])
    if (parents[a] == from) return static_cast<uint8_t>(a);  // from is an ancestor of to: go down
  return static_cast<uint8_t>(parents[from]);                // else up
}

// One hop of `w` from where it is: toward the member `via` over the group's tree, or from `via`
// to `target`. It needs the link now (detector step f); a link that is gone loses it.
void SimultaneousDetector::hop(Walker w, const uint32_t* words, uint32_t word_count) {
  uint32_t next;
  if (w.position == w.via) {
    next = w.target;
    w.walking = false;
  } else {
    w.position = toward(words + k_, w.position, w.via);
    next = words[w.position];
    w.walking = true;
  }
  const StepHistory::Graph* g = links_;
  const bool linked = g != nullptr && g->present[w.at] && [&] {
    const auto n = g->neighbors(w.at);
    return std::find(n.begin(), n.end(), next) != n.end();
  }();
  if (!linked) {
    ++step_.lost;
    return;
  }
  ++step_.messages;
  step_.bytes += kHeaderBytes + 4u * word_count;
  if (options_.live_budget != 0 && step_.live + step_.messages > options_.live_budget) {
    stop_reason_ = "more than " + std::to_string(options_.live_budget) + " live PatternMatchers";
    return;
  }
  w.at = next;
  w.data = static_cast<uint32_t>(sent_words_.size());
  sent_words_.insert(sent_words_.end(), words, words + word_count);
  sent_.push_back(w);
}

}  // namespace dw::watch
