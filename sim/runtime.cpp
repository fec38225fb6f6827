#include "sim/runtime.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "sim/read_file.h"
#include "watch/agent_step.h"
#include "watch/make_detector.h"

namespace dw::sim {

// A thread's PatternMatcher outbox: each copy goes into the lane of its receiver's block.
struct Runtime::Lanes final : watch::PatternMatcherOutbox {
  watch::RecordBuffer* row;  // this thread's lanes, one per receiving block
  uint32_t block_shift;
  void send(uint32_t, std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) override {
    // One record per run of receivers in the same block.
    for (size_t i = 0, j; i < to.size(); i = j) {
      const uint32_t block = to[i] >> block_shift;
      for (j = i + 1; j < to.size() && to[j] >> block_shift == block; ++j) {
      }
      row[block].append(to.subspan(i, j - i), pm, bytes);
    }
  }
};

watch::Frame make_frame(const Model& model, int64_t step, std::span<const int64_t> values,
                        std::span<const uint8_t> present, const std::shared_ptr<const NeighborGraph>& graph,
                        uint32_t first_module) {
  watch::Frame frame;
  frame.step = step;
  frame.present = present;
  frame.values = values;
  frame.first_module = first_module;
  frame.nbr_begin = graph->begin;
  frame.nbrs = graph->ids;
  frame.variable_count = model.variable_count();
  frame.topology = graph;
  return frame;
}

std::string why_not_over_ranks(const Model& model) {
  for (const HostedWatchpoint& w : model.watches)
    if (!w.runs_on_agents())
      return "watchpoint '" + w.watchpoint.name + "' is " +
             (w.algorithm == watch::Algorithm::Centralized ? "centralized" : "read over simultaneous states") +
             ": its detector observes the whole ensemble in one place, which no rank holds; over ranks a "
             "watchpoint runs on the modules' agents (algorithm = \"distributed\", states = \"consistent\"; "
             "or --algorithm distributed --states consistent)";
  return {};
}

Runtime::Runtime(const Model& model, World& world, unsigned threads, RankExchange* ranks, Partition partition)
    : model_(model),
      world_(world),
      pool_(std::max(1u, std::min(threads, std::max(1u, model.module_count())))),
      ranks_(ranks) {
  // Blocks of at most 4096 modules (a power of two). A neighbour list that crosses a block boundary
  // is sent as one record per block, so blocks are as large as the threads allow: one thread takes
  // the ensemble as one block (up to 4096), and several (over all ranks) take at least one block
  // each, never so large that one is left without.
  const uint32_t m = model.module_count();
  const uint32_t rank_count = ranks_ ? static_cast<uint32_t>(ranks_->ranks()) : 1;
  const uint32_t workers = pool_.size() * rank_count;
  const uint32_t per_thread = std::max(1u, m / workers);
  if (workers == 1)
    while (owners_.block_shift < 12 && (1u << owners_.block_shift) < per_thread) ++owners_.block_shift;
  else
    while (owners_.block_shift < 12 && (2u << owners_.block_shift) <= per_thread) ++owners_.block_shift;
  blocks_ = (m >> owners_.block_shift) + ((m & ((1u << owners_.block_shift) - 1)) != 0);
  place_blocks(partition);
  world_.share_over(ranks_, owners_);
  scratch_.resize(pool_.size());
  border_messages_.resize(pool_.size());
  arriving_.resize(pool_.size());
  for (const auto& program : model.programs) programs_.push_back(program.get());
  for (ThreadScratch& s : scratch_) {
    s.outbox.byte_limit = model.message_bytes_per_step;
    for (const auto& program : model.programs) s.programs.push_back(program->make_scratch());
    for (const HostedWatchpoint& w : model.watches) {
      // Each thread may use the whole budget; whether the step went over it is decided on the
      // threads' sum afterwards (finish_distributed), so the stop never depends on the thread count.
      s.agents.emplace_back(w.watchpoint.program, w.options.optimizations, w.options.live_budget);
    }
  }
  next_values_.resize(size_t{window_} * model.variable_count());
  const size_t lanes = size_t{pool_.size()} * blocks_;
  for (const HostedWatchpoint& w : model.watches) {
    columns_.push_back(watch::variable_columns(w.watchpoint.program, model.universe));
    sending_.emplace_back(w.runs_on_agents() ? lanes : 0);
  }
}

void Runtime::use_program(uint32_t p, const HostProgram& program) {
  if (programs_[p] == &program) return;
  programs_[p] = &program;
  for (ThreadScratch& s : scratch_) s.programs[p] = program.make_scratch();
}

// Which rank steps each block. By blocks: each rank a run of consecutive blocks holding about as
// many present modules as the others (on a lattice, whose ids run x, y, z: a slab). By graph: the
// blocks' neighbour graph at step 0 (the lattice's), weighted by present modules and by links
// between blocks, cut k-way by the exchange's partitioner.
void Runtime::place_blocks(Partition partition) {
  const uint32_t rank_count = ranks_ ? static_cast<uint32_t>(ranks_->ranks()) : 1;
  const uint32_t me = ranks_ ? static_cast<uint32_t>(ranks_->rank()) : 0;
  const std::vector<uint8_t>& occupied = model_.lattice.occupied;
  std::vector<uint32_t> weight(blocks_, 0);
  for (uint32_t m = 0; m < model_.module_count(); ++m)
    weight[m >> owners_.block_shift] += m < occupied.size() ? occupied[m] : 1;
  if (partition == Partition::Auto) partition = world_.moves() ? Partition::Graph : Partition::Blocks;
  partition_ = partition;
  if (partition == Partition::Graph && rank_count > 1) {
    // The links between blocks, as sorted (block, block) pairs: equal pairs make one edge's weight.
    // A physical world's lattice keeps no graph: its cells give the links (no graph of a million
    // is made on every rank only to be read once).
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    const auto link = [&](ModuleId m, ModuleId n) {
      const uint32_t a = m >> owners_.block_shift, b = n >> owners_.block_shift;
      if (a != b) pairs.push_back({a, b}), pairs.push_back({b, a});
    };
    if (const NeighborGraph* g = model_.lattice.graph.get()) {
      for (ModuleId m = 0; m < g->module_count(); ++m)
        for (ModuleId n : g->neighbors(m))
          if (m < n) link(m, n);
    } else {
      for_lattice_pairs(model_.lattice.spec, model_.lattice.occupied, link);
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<uint32_t> first(blocks_ + 1, 0), adjacent, link_weight;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (i > 0 && pairs[i] == pairs[i - 1]) {
        ++link_weight.back();
        continue;
      }
      adjacent.push_back(pairs[i].second);
      link_weight.push_back(1);
      ++first[pairs[i].first + 1];
    }
    for (uint32_t b = 0; b < blocks_; ++b) first[b + 1] += first[b];
    owners_.block_rank = ranks_->partition_graph(first, adjacent, weight, link_weight);
    if (owners_.block_rank.size() != blocks_) throw std::logic_error("the rank exchange has no graph partitioner");
  } else {
    uint64_t total = 0, seen = 0;
    for (uint32_t w : weight) total += w;
    owners_.block_rank.assign(blocks_, 0);
    for (uint32_t b = 0; b < blocks_; ++b) {
      // The block goes to the rank whose share its middle module falls in.
      const uint64_t middle = 2 * seen + weight[b];
      owners_.block_rank[b] =
          total == 0 ? 0 : static_cast<uint32_t>(std::min<uint64_t>(rank_count - 1, middle * rank_count / (2 * total)));
      seen += weight[b];
    }
  }
  own_blocks_.clear();
  for (uint32_t b = 0; b < blocks_; ++b)
    if (owners_.block_rank[b] == me) own_blocks_.push_back(b);
  first_ = own_blocks_.empty() ? 0 : block_begin(own_blocks_.front());
  window_ = own_blocks_.empty() ? 0 : block_begin(own_blocks_.back() + 1) - first_;
}

uint32_t Runtime::block_begin(uint32_t block) const {
  return static_cast<uint32_t>(std::min<uint64_t>(uint64_t{block} << owners_.block_shift, model_.module_count()));
}

State Runtime::initial_state() {
  State s;
  const uint32_t v = model_.variable_count();
  s.values.resize(size_t{window_} * v);
  for (uint32_t i = 0; i < window_; ++i)
    std::copy(model_.initial_values.begin(), model_.initial_values.end(), s.values.begin() + size_t{i} * v);
  world_.initialize(model_, s, pool_);
  for (uint32_t w = 0; w < model_.watches.size(); ++w) s.watches.push_back(initial_watch_state(w));
  return s;
}

WatchState Runtime::initial_watch_state(uint32_t w) const {
  const HostedWatchpoint& h = model_.watches[w];
  WatchState ws;
  if (!h.runs_on_agents()) {
    ws.detector = watch::make_detector(h.algorithm, h.watchpoint, model_.universe, h.options, nullptr);
    ws.detector->stats().max_steps = 0;  // the run keeps its own series
  } else {
    // An aggregate reads neighbours, which may be another rank's: its agents keep every module's
    // history, the others' filled as the step ends (share_neighbor_values).
    const bool whole = ranks_ && !h.watchpoint.program.aggregates.empty();
    ws.agents.emplace(h.watchpoint.program, h.options.optimizations.temporal_spans, whole ? 0 : first_,
                      whole ? model_.module_count() : window_);
    ws.in_flight.resize(size_t{pool_.size()} * blocks_);
  }
  return ws;
}

void Runtime::run_programs(unsigned thread, uint32_t begin, uint32_t end, const State& state) {
  const uint32_t v = model_.variable_count(), programs = model_.program_count();
  ThreadScratch& scratch = scratch_[thread];
  for (uint32_t m = begin; m < end; ++m) {
    const int64_t* before = state.values.data() + size_t{m - first_} * v;
    int64_t* after = next_values_.data() + size_t{m - first_} * v;
    // A variable nobody assigns keeps its value. (A model without variables has no rows: their
    // pointers may be null, which memcpy may not be given even for no bytes.)
    if (v > 0) std::memcpy(after, before, sizeof(int64_t) * v);
    if (!state.present[m]) continue;
    const auto neighbors = state.graph->neighbors(m);
    for (uint32_t p = 0; p < programs; ++p) {
      // Once a module has failed, the step fails with the lowest failing module's message: the
      // calls of higher modules on this thread cannot change it and are not made (a script looping
      // to its budget on every module took minutes to report module 0's failure).
      if (!scratch.outbox.error.empty() && scratch.outbox.error_module <= m) break;
      const uint32_t base = model_.program_base[p];
      const HostProgram& program = *programs_[p];
      ModuleContext ctx(m, state.step, model_.seed, static_cast<uint16_t>(p), neighbors,
                        state.inbox.of(m - first_, p, programs), before + base, after + base, scratch.outbox,
                        program.name(), state.bodies, scratch.programs[p].get());
      program.step(ctx);
    }
  }
}

// One block of agents for one watchpoint, in the order that keeps the block's agents in cache:
// each records its module's state at t and decides its own leaves, then the PatternMatchers sent
// to the block arrive, then every agent starts its own (watch/agent_step.h).
void Runtime::run_agents(unsigned thread, uint32_t block, uint32_t w, State& state) {
  const watch::Program& program = model_.watches[w].watchpoint.program;
  WatchState& ws = state.watches[w];
  const uint32_t begin = block_begin(block), end = block_begin(block + 1);
  const watch::Frame frame = make_frame(model_, state.step, next_values_, state.present, state.graph, first_);
  ws.agents->record(frame, begin, end, program, columns_[w]);
  const int64_t f = state.step - program.agent_delay();
  if (f >= 0) step_block_agents(thread, block, w, ws, f);
}

// Detector step f of one block's agents: the PatternMatchers sent to the block arrive, then each
// present agent starts its own; what they send goes into this thread's lanes.
void Runtime::step_block_agents(unsigned thread, uint32_t block, uint32_t w, WatchState& ws, int64_t f) {
  Lanes out;
  out.row = sending_[w].data() + size_t{thread} * blocks_;
  out.block_shift = owners_.block_shift;
  arriving_[thread].clear();
  for (unsigned from = 0; from < pool_.size(); ++from)
    arriving_[thread].push_back(&ws.in_flight[size_t{from} * blocks_ + block]);
  watch::step_agents(*ws.agents, block_begin(block), block_begin(block + 1), f, arriving_[thread],
                     scratch_[thread].agents[w], out);
}

void Runtime::start_thread(unsigned thread, const State& state) {
  ThreadScratch& s = scratch_[thread];
  s.outbox.messages.clear();
  s.outbox.actuations.clear();
  s.outbox.error.clear();  // a failed step may be tried again (a script reloaded, a seek back)
  s.outbox.over = false;
  for (uint32_t w : agent_watches_)
    watch::start_agent_step(s.agents[w], state.step - model_.watches[w].watchpoint.program.agent_delay());
}

// The thread's share of `blocks`: the t-th of equal runs.
void Runtime::run_blocks(unsigned thread, std::span<const uint32_t> blocks, State& state) {
  const size_t n = blocks.size();
  for (size_t i = thread * n / pool_.size(); i < (thread + 1) * n / pool_.size(); ++i) {
    if (exchanging_ && thread == 0) ranks_->progress();  // thread 0 is the caller's, the one that calls MPI
    run_programs(thread, block_begin(blocks[i]), block_begin(blocks[i] + 1), state);
    for (uint32_t w : agent_watches_) run_agents(thread, blocks[i], w, state);
  }
}

// Over ranks, the blocks that may send to another rank run first; their batches then travel while
// the interior blocks run, and what the other ranks sent is taken in at the end (docs/design.md §12).
void Runtime::run_over_ranks(State& state) {
  split_own_blocks(state);
  pool_.run([&](unsigned thread) {
    start_thread(thread, state);
    run_blocks(thread, border_blocks_, state);
    border_messages_[thread] = scratch_[thread].outbox.messages.size();
  });
  ranks_->start_exchange(batches_for_ranks());
  exchanging_ = true;
  pool_.run([&](unsigned thread) { run_blocks(thread, interior_blocks_, state); });
  exchanging_ = false;
  arrived_ = ranks_->finish_exchange();
  open_batches();
}

// A block may send to another rank when one of its modules has a neighbour there: in N(m, t),
// along which the programs send, or in N(m, t - E+) of a watch whose agents run, along which they
// send (DistributedAgents::fill_and_spread). Worked out once per graph: a static lattice's once
// for the run.
void Runtime::split_own_blocks(const State& state) {
  std::vector<std::pair<std::shared_ptr<const void>, watch::AgentHistory::StepGraph>> graphs{
      {state.graph, {state.graph->begin.data(), state.graph->ids.data()}}};
  for (uint32_t w : agent_watches_) {
    const watch::AgentHistory& history = state.watches[w].agents->history();
    const int64_t f = state.step - model_.watches[w].watchpoint.program.agent_delay();
    if (auto owner = history.graph_owner(f)) graphs.emplace_back(std::move(owner), history.graph(f));
  }
  const uint32_t me = static_cast<uint32_t>(ranks_->rank());
  std::vector<Border> kept;
  for (const auto& graph : graphs) {
    const auto& [owner, g] = graph;
    auto same = [&](const Border& b) { return b.graph == graph.first; };  // clang 14 captures no bindings
    if (std::ranges::any_of(kept, same)) continue;
    if (auto known = std::ranges::find_if(borders_, same); known != borders_.end()) {
      kept.push_back(std::move(*known));
      continue;
    }
    Border& b = kept.emplace_back(Border{owner, std::vector<uint8_t>(own_blocks_.size(), 0)});
    for (size_t i = 0; i < own_blocks_.size(); ++i)
      for (uint32_t m = block_begin(own_blocks_[i]); m < block_begin(own_blocks_[i] + 1) && !b.crosses[i]; ++m)
        for (uint32_t e = g.begin[m]; e < g.begin[m + 1]; ++e)
          if (owners_.rank_of(g.ids[e]) != me) {
            b.crosses[i] = 1;
            break;
          }
  }
  borders_ = std::move(kept);
  border_blocks_.clear();
  interior_blocks_.clear();
  for (size_t i = 0; i < own_blocks_.size(); ++i) {
    const bool border = std::ranges::any_of(borders_, [&](const Border& b) { return b.crosses[i] != 0; });
    (border ? border_blocks_ : interior_blocks_).push_back(own_blocks_[i]);
  }
}

// What the border blocks sent to other ranks' modules, one batch per rank: the program messages
// (their count, then the records), then for each watch whose agents run, its lanes to that rank's
// blocks (their bytes, then each as block, bytes, records). The lanes are emptied: their
// PatternMatchers are in flight in the batch. A rank with nothing for another sends it nothing.
std::vector<std::vector<std::byte>> Runtime::batches_for_ranks() {
  const uint32_t me = static_cast<uint32_t>(ranks_->rank());
  std::vector<std::vector<std::byte>> out(static_cast<size_t>(ranks_->ranks()));
  auto put = [](std::vector<std::byte>& to, uint64_t value) {
    append_records(to, std::span<const uint64_t>(&value, 1));
  };
  auto patch = [](std::vector<std::byte>& to, size_t at, uint64_t value) {
    std::memcpy(to.data() + at, &value, sizeof value);
  };
  // The messages: their count, their headers (each header's `first` counting in this batch's
  // words), the count of the words and the words.
  std::vector<MessageList> going(out.size());
  for (const ThreadScratch& s : scratch_)
    for (const Message m : s.outbox.messages)
      if (const uint32_t r = owners_.rank_of(m.to); r != me) going[r].add(m);
  for (size_t r = 0; r < out.size(); ++r) {
    put(out[r], going[r].size());
    append_records(out[r], std::as_const(going[r]).headers());
    put(out[r], going[r].words().size());
    append_records(out[r], std::span<const int64_t>(going[r].words()));
  }
  for (uint32_t w : agent_watches_) {
    std::vector<size_t> head(out.size());
    for (size_t r = 0; r < out.size(); ++r) head[r] = out[r].size(), put(out[r], 0);
    for (uint32_t thread = 0; thread < pool_.size(); ++thread)
      for (uint32_t block = 0; block < blocks_; ++block) {
        watch::RecordBuffer& lane = sending_[w][size_t{thread} * blocks_ + block];
        if (lane.empty() || owners_.block_rank[block] == me) continue;
        std::vector<std::byte>& to = out[owners_.block_rank[block]];
        put(to, block);
        put(to, lane.size());
        to.insert(to.end(), lane.data(), lane.data() + lane.size());
        lane.clear();
      }
    for (size_t r = 0; r < out.size(); ++r) patch(out[r], head[r], out[r].size() - head[r] - sizeof(uint64_t));
  }
  const size_t headers = sizeof(uint64_t) * (2 + agent_watches_.size());  // all a batch of nothing holds
  for (std::vector<std::byte>& to : out) {
    if (to.size() == headers) to.clear();
    bytes_to_ranks_ += to.size();
  }
  return out;
}

// The batches that arrived (batches_for_ranks), opened in place: the messages, and each watch's
// lanes, by rank.
void Runtime::open_batches() {
  arrived_messages_.assign(arrived_.size(), {});
  arrived_lanes_.assign(model_.watches.size(), {});
  for (size_t r = 0; r < arrived_.size(); ++r) {
    const std::span<const std::byte> part = arrived_[r];
    if (part.empty()) continue;
    size_t at = 0;
    auto take = [&] {
      uint64_t value;
      std::memcpy(&value, part.data() + at, sizeof value);
      at += sizeof value;
      return value;
    };
    const uint64_t count = take();
    const std::span<const MessageHeader> headers =
        records_of<MessageHeader>(part.subspan(at, count * sizeof(MessageHeader)));
    at += count * sizeof(MessageHeader);
    const uint64_t words = take();
    arrived_messages_[r] = Messages(headers, records_of<int64_t>(part.subspan(at, words * sizeof(int64_t))).data());
    at += words * sizeof(int64_t);
    for (uint32_t w : agent_watches_) {
      const uint64_t bytes = take();
      arrived_lanes_[w].push_back(part.subspan(at, bytes));
      at += bytes;
    }
  }
}

// Gathers the threads' matches and statistics; the PatternMatchers sent become those in flight.
void Runtime::drain_agents(State& state, uint32_t w, int64_t f, WatchStepOutput& out) {
  const watch::Program& program = model_.watches[w].watchpoint.program;
  WatchState& ws = state.watches[w];
  if (ws.stopped) return;
  out = WatchStepOutput{};
  for (watch::RecordBuffer& lane : sending_[w]) lane.clear();
  agent_watches_ = {w};  // what a batch between ranks carries: this watch's PatternMatchers alone
  for (ThreadScratch& s : scratch_) s.outbox.messages.clear();
  pool_.run([&](unsigned thread) {
    watch::AgentContext& ctx = scratch_[thread].agents[w];
    watch::start_agent_step(ctx, f);
    const size_t n = own_blocks_.size();
    for (size_t i = thread * n / pool_.size(); i < (thread + 1) * n / pool_.size(); ++i) {
      const uint32_t block = own_blocks_[i];
      ws.agents->prepare(program, f, block_begin(block), block_begin(block + 1));
      step_block_agents(thread, block, w, ws, f);
    }
  });
  if (ranks_) {
    ranks_->start_exchange(batches_for_ranks());
    arrived_ = ranks_->finish_exchange();
    open_batches();
  }
  finish_distributed(w, state, out, f);
  ws.matches += out.matches;
  sort_matches(w, out);
}

void Runtime::finish_distributed(uint32_t w, State& state, WatchStepOutput& out, int64_t f) {
  const HostedWatchpoint& hosted = model_.watches[w];
  const watch::Program& program = hosted.watchpoint.program;
  WatchState& ws = state.watches[w];
  const uint32_t k = program.slot_count();
  for (size_t lane = 0; lane < ws.in_flight.size(); ++lane) {
    std::swap(ws.in_flight[lane], sending_[w][lane]);
    sending_[w][lane].clear();
  }
  if (ranks_) take_arrived_lanes(w, ws);
  if (f < 0) return;
  std::vector<watch::AgentContext*> contexts;
  for (ThreadScratch& s : scratch_) contexts.push_back(&s.agents[w]);
  watch::AgentStepOutcome outcome = watch::sum_agent_step(contexts, f);
  if (ranks_) add_up_over_ranks(outcome);
  watch::decide_agent_budget(outcome, f, hosted.options.live_budget);
  if (outcome.over_budget) {
    // The step that went over the budget was cut short wherever each thread was: none of it is
    // reported, and the stopped watch lets go of its agents and PatternMatchers.
    ws.stopped = true;
    ws.stop_reason = std::move(outcome.stop_reason);
    ws.agents.reset();
    ws.in_flight = {};
    for (watch::RecordBuffer& lane : sending_[w]) lane = {};
    return;
  }
  out.observed = true;
  out.stats = std::move(outcome.stats);
  // Everything that matched now was started at t0 = f - (k - 1).
  const int64_t t0 = f - (k - 1);
  if (t0 >= 0) {
    out.t = t0;
    for (ThreadScratch& s : scratch_) out.matches += s.agents[w].match_values / k;
    if (ranks_) ranks_->sum({&out.matches, 1});
    if ((hosted.action != MatchAction::Count || !program.actions.empty()) && out.matches) {
      for (ThreadScratch& s : scratch_) {
        const watch::AgentContext& ctx = s.agents[w];
        out.slots.insert(out.slots.end(), ctx.matches.begin(),
                         ctx.matches.begin() + static_cast<ptrdiff_t>(ctx.match_values));
        out.actions.insert(out.actions.end(), ctx.action_values.begin(), ctx.action_values.end());
      }
      if (ranks_) {  // every rank's, on every rank: each decides alike where to pause, and acts alike
        std::vector<ModuleId> all;
        for (const auto& part : ranks_->all_gather(std::as_bytes(std::span(out.slots))))
          all.insert(all.end(), records_of<ModuleId>(part).begin(), records_of<ModuleId>(part).end());
        out.slots = std::move(all);
        if (!program.actions.empty()) {
          std::vector<watch::Value> values;
          for (const auto& part : ranks_->all_gather(std::as_bytes(std::span(out.actions))))
            values.insert(values.end(), records_of<watch::Value>(part).begin(), records_of<watch::Value>(part).end());
          out.actions = std::move(values);
        }
      }
    }
  }
}

void Runtime::observe_detector(uint32_t w, State& state, WatchStepOutput& out) {
  WatchState& ws = state.watches[w];
  const watch::Program& program = model_.watches[w].watchpoint.program;
  const bool keep = model_.watches[w].action != MatchAction::Count || !program.actions.empty();
  const uint32_t k = program.slot_count();
  ws.detector->set_sink(
      [&out, keep, k](int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value> actions) {
        out.t = t;
        out.matches += ids.size() / k;
        if (!keep) return;
        out.slots.assign(ids.begin(), ids.end());
        out.actions.assign(actions.begin(), actions.end());
      });
  const watch::Frame frame = make_frame(model_, state.step, state.values, state.present, state.graph);
  const uint64_t before = ws.detector->stats().observed_steps;
  ws.detector->observe(frame);
  if (ws.detector->stats().observed_steps > before) {  // a step cut short by the budget counts not
    out.observed = true;
    out.stats = ws.detector->stats().last;
  }
  if (ws.detector->stopped()) {
    ws.stopped = true;
    ws.stop_reason = ws.detector->stats().stop_reason;
  }
}

void Runtime::deliver_program_messages(State& state) {
  const uint32_t programs = model_.program_count();
  const size_t groups = size_t{window_} * programs;
  const uint32_t me = ranks_ ? static_cast<uint32_t>(ranks_->rank()) : 0;
  uint64_t total = 0;  // to this rank's modules
  if (ranks_) {
    // Those to another rank's modules went in the border blocks' batches; those sent here came in.
    for (unsigned thread = 0; thread < pool_.size(); ++thread) {
      const MessageList& sent = scratch_[thread].outbox.messages;
      for (size_t i = 0; i < sent.size(); ++i)
        if (owners_.rank_of(sent[i].to) == me) ++total;
        else if (i >= border_messages_[thread])
          throw std::logic_error("a block taken for interior sent to another rank: its message would be lost");
    }
    for (const Messages part : arrived_messages_) total += part.size();
  } else {
    for (const ThreadScratch& s : scratch_) total += s.outbox.messages.size();
  }
  // The messages to this rank's modules: its own (in thread order, which is module order), then
  // those of every other rank (each in module order); over ranks, each inbox is put in sender
  // order below.
  auto each = [&](auto&& fn) {
    for (const ThreadScratch& s : scratch_)
      for (const Message m : s.outbox.messages)
        if (!ranks_ || owners_.rank_of(m.to) == me) fn(m);
    for (const Messages part : arrived_messages_)
      for (const Message m : part) fn(m);
  };
  Mailbox& box = state.inbox;
  box.begin.assign(groups + 1, 0);
  std::vector<MessageHeader>& headers = box.messages.headers();
  std::vector<int64_t>& words = box.messages.words();
  headers.resize(total);
  words.clear();
  uint64_t sent = total;  // every message is received by exactly one rank
  if (ranks_) ranks_->sum({&sent, 1});
  state.program_messages += sent;
  if (total == 0) return;
  // A stable counting sort of the headers by (receiver, program): senders stay in id order within
  // a group. The words go in the order the messages come.
  size_t word_count = 0;
  each([&](const Message& m) {
    ++box.begin[size_t{m.to - first_} * programs + m.program + 1];
    word_count += m.size;
  });
  if (word_count > UINT32_MAX) throw std::length_error("more message words in one step than a mailbox indexes");
  words.reserve(word_count);
  for (size_t g = 0; g < groups; ++g) box.begin[g + 1] += box.begin[g];
  counts_.assign(box.begin.begin(), box.begin.end() - 1);
  each([&](const Message& m) {
    headers[counts_[size_t{m.to - first_} * programs + m.program]++] = {m.from, m.to, m.program, m.size,
                                                                        static_cast<uint32_t>(words.size())};
    words.insert(words.end(), m.words, m.words + m.size);
  });
  if (ranks_)  // a sender's messages stay in the order sent; a group holds a few
    for (size_t g = 0; g < groups; ++g)
      if (box.begin[g + 1] - box.begin[g] > 1)
        std::stable_sort(headers.begin() + box.begin[g], headers.begin() + box.begin[g + 1],
                         [](const MessageHeader& a, const MessageHeader& b) { return a.from < b.from; });
}

// The step's statistics are those of all ranks, and so is a stop: with the reason of the first
// rank that gave one.
void Runtime::add_up_over_ranks(watch::AgentStepOutcome& outcome) {
  watch::StepStats& st = outcome.stats;
  std::vector<uint64_t> sums = st.live_by_filled;
  sums.insert(sums.end(),
              {st.live, st.created, st.messages, st.bytes, st.matches, outcome.over_budget, st.value_messages});
  ranks_->sum(sums);
  const size_t n = st.live_by_filled.size();
  std::copy(sums.begin(), sums.begin() + static_cast<ptrdiff_t>(n), st.live_by_filled.begin());
  st.live = sums[n], st.created = sums[n + 1], st.messages = sums[n + 2], st.bytes = sums[n + 3];
  st.matches = sums[n + 4];
  st.value_messages = sums[n + 6];
  if (sums[n + 5] == 0) return;
  outcome.over_budget = true;
  for (const std::span<const std::byte> why : ranks_->all_gather(std::as_bytes(std::span(outcome.stop_reason))))
    if (!why.empty()) {
      outcome.stop_reason.assign(reinterpret_cast<const char*>(why.data()), why.size());
      break;
    }
}

// The PatternMatchers other ranks sent to this rank's blocks (batches_for_ranks), appended to each
// block's first lane. Their order in the lanes matters to nothing (docs/design.md §4: a multiset), as with
// threads.
void Runtime::take_arrived_lanes(uint32_t w, WatchState& ws) {
  const uint32_t me = static_cast<uint32_t>(ranks_->rank());
  for (size_t lane = 0; lane < ws.in_flight.size(); ++lane)
    if (!ws.in_flight[lane].empty() && owners_.block_rank[lane % blocks_] != me)
      throw std::logic_error("a block taken for interior sent to another rank: its PatternMatchers would be lost");
  for (const std::span<const std::byte> lanes : arrived_lanes_[w])
    for (size_t at = 0; at < lanes.size();) {
      uint64_t head[2];
      std::memcpy(head, lanes.data() + at, sizeof head);
      ws.in_flight[head[0]].append_records(lanes.data() + at + sizeof head, head[1]);
      at += sizeof head + head[1];
    }
}

// A program's misuse on any rank stops every rank, with the first one in module order, as one
// process reports it (each thread's outbox keeps its lowest module's). Otherwise the actuation
// requests go to the world in module order, as one process has them (in thread order): the world
// is stepped whole on every rank, so every rank needs all of them. One sum over the ranks says
// whether either has to be gathered. Without a misuse, messages past Model::message_bytes_per_step
// in a process stop every rank: a thread past it alone means the process's are, so whether the
// step stops does not depend on the threads.
void Runtime::agree_on_failure_and_gather_actuations(int64_t step) {
  const Outbox* failed = nullptr;
  const size_t before = actuations_.size();  // the interventions' pushes come first
  uint64_t message_bytes = 0;
  bool over = false;
  for (const ThreadScratch& s : scratch_) {
    if (!s.outbox.error.empty() && (!failed || s.outbox.error_module < failed->error_module)) failed = &s.outbox;
    actuations_.insert(actuations_.end(), s.outbox.actuations.begin(), s.outbox.actuations.end());
    message_bytes += s.outbox.messages.used_bytes();
    over = over || s.outbox.over;
  }
  const uint64_t limit = model_.message_bytes_per_step;
  over = over || (limit > 0 && message_bytes > limit);
  uint64_t counts[3] = {failed != nullptr, actuations_.size() - before, over};
  if (ranks_) ranks_->sum(counts);
  if (ranks_ && counts[0] != 0) {
    std::vector<std::byte> said;
    if (failed) {
      const int64_t where[2] = {failed->error_step, failed->error_module};
      append_records(said, std::span<const int64_t>(where));
      append_records(said, std::span(failed->error.data(), failed->error.size()));
    }
    // Each failing rank said (step, module, message); the lowest module's is the one.
    const Gathered all = ranks_->all_gather(said);
    int64_t where[2] = {0, INT64_MAX};
    std::string message;
    for (const std::span<const std::byte> part : all) {
      if (part.empty()) continue;
      int64_t at[2];
      std::memcpy(at, part.data(), sizeof at);
      if (at[1] >= where[1]) continue;
      std::memcpy(where, at, sizeof where);
      message.assign(reinterpret_cast<const char*>(part.data()) + sizeof at, part.size() - sizeof at);
    }
    throw ProgramError(message, static_cast<ModuleId>(where[1]), where[0]);
  }
  if (failed) throw ProgramError(failed->error, failed->error_module, failed->error_step);
  if (counts[2] != 0)
    throw ProgramError("at step " + std::to_string(step) + " the modules' messages took more than " + size_text(limit) +
                       (ranks_ ? " in one process" : "") +
                       ", what a step's messages may take on this machine beyond the scenario's memory estimate (a "
                       "program sending without end?)");
  if (!ranks_ || counts[1] == 0) return;
  std::vector<std::byte> mine;
  append_records(mine, std::span<const Actuation>(actuations_).subspan(before));
  actuations_.resize(before);
  for (const auto& part : ranks_->all_gather(mine))
    actuations_.insert(actuations_.end(), records_of<Actuation>(part).begin(), records_of<Actuation>(part).end());
  std::stable_sort(actuations_.begin() + static_cast<ptrdiff_t>(before), actuations_.end(),
                   [](const Actuation& a, const Actuation& b) { return a.module < b.module; });
}

// Each rank gives its blocks' rows in block order, and every rank knows whose each block is: the
// rows of every block, in block order, lie in the gathered parts.
std::vector<std::span<const int64_t>> Runtime::gather_values(const State& state, Gathered& parts) {
  const size_t v = model_.variable_count();
  std::vector<int64_t> copied;  // unless the blocks are one run (--partition blocks), read in place
  std::span<const int64_t> own = state.values;
  if (!own_blocks_.empty() && own_blocks_.back() - own_blocks_.front() + 1 != own_blocks_.size()) {
    for (uint32_t b : own_blocks_)
      copied.insert(copied.end(), state.values.begin() + static_cast<ptrdiff_t>((block_begin(b) - first_) * v),
                    state.values.begin() + static_cast<ptrdiff_t>((block_begin(b + 1) - first_) * v));
    own = copied;
  }
  parts = ranks_->all_gather(std::as_bytes(own));
  std::vector<std::span<const int64_t>> rows;
  std::vector<size_t> read(parts.size(), 0);
  for (uint32_t b = 0; b < blocks_; ++b) {
    const size_t n = (block_begin(b + 1) - block_begin(b)) * v;
    rows.push_back(records_of<int64_t>(parts[owners_.block_rank[b]]).subspan(read[owners_.block_rank[b]], n));
    read[owners_.block_rank[b]] += n;
  }
  return rows;
}

std::vector<int64_t> Runtime::whole_values(const State& state) {
  if (!ranks_) return state.values;
  Gathered parts;
  std::vector<int64_t> values;
  values.reserve(size_t{model_.module_count()} * model_.variable_count());
  for (const std::span<const int64_t> rows : gather_values(state, parts))
    values.insert(values.end(), rows.begin(), rows.end());
  return values;
}

// Each rank gives its blocks' lists in block order, each as its length and its ids.
std::shared_ptr<const NeighborGraph> Runtime::whole_graph(const std::shared_ptr<const NeighborGraph>& graph) {
  if (!ranks_ || !graph->held) return graph;
  std::vector<uint32_t> own;
  for (uint32_t b : own_blocks_)
    for (ModuleId m = block_begin(b); m < block_begin(b + 1); ++m) {
      const std::span<const ModuleId> list = graph->neighbors(m);
      own.push_back(static_cast<uint32_t>(list.size()));
      own.insert(own.end(), list.begin(), list.end());
    }
  const Gathered parts = ranks_->all_gather(std::as_bytes(std::span<const uint32_t>(own)));
  auto whole = std::make_shared<NeighborGraph>();
  whole->begin.reserve(size_t{model_.module_count()} + 1);
  std::vector<size_t> read(parts.size(), 0);
  for (uint32_t b = 0; b < blocks_; ++b) {
    const uint32_t rank = owners_.block_rank[b];
    const std::span<const uint32_t> words = records_of<uint32_t>(parts[rank]);
    for (ModuleId m = block_begin(b); m < block_begin(b + 1); ++m) {
      const uint32_t count = words[read[rank]++];
      whole->ids.insert(whole->ids.end(), words.begin() + ptrdiff_t(read[rank]),
                        words.begin() + ptrdiff_t(read[rank] + count));
      read[rank] += count;
      whole->begin.push_back(static_cast<uint32_t>(whole->ids.size()));
    }
  }
  return whole;
}

// Passes the hash along the blocks in module order: the rank holding a run of blocks continues it
// over that run (`run(h, first, end)`, modules of this rank's window), then gives it to all.
uint64_t Runtime::pass_hash(uint64_t h, const std::function<uint64_t(uint64_t, uint32_t, uint32_t)>& run) {
  const auto me = static_cast<uint32_t>(ranks_->rank());
  for (uint32_t b = 0, e = 0; b < blocks_; b = e) {
    for (e = b + 1; e < blocks_ && owners_.block_rank[e] == owners_.block_rank[b];) ++e;
    const bool mine = owners_.block_rank[b] == me;
    if (mine) h = run(h, block_begin(b) - first_, block_begin(e) - first_);
    const Gathered told = ranks_->all_gather(mine ? std::as_bytes(std::span(&h, 1)) : std::span<const std::byte>{});
    h = records_of<uint64_t>(told[owners_.block_rank[b]])[0];
  }
  return h;
}

StateHash Runtime::hash(const State& state) {
  if (!ranks_) return hash_state(state);
  // The whole state as one process would hold it. The rest every rank holds; each rank's modules'
  // variables and messages are hashed where they are, the hash passed from rank to rank in module
  // order, never put together in one place (a million modules' inbox is hundreds of MB); the
  // in-flight multisets are added up.
  std::vector<InFlightDigest> digests;
  for (const WatchState& w : state.watches) digests.push_back(in_flight_digest(w));
  std::vector<uint64_t> sums;
  for (const InFlightDigest& d : digests) sums.insert(sums.end(), {d.sum, d.count});
  uint64_t messages = state.inbox.messages.size();
  sums.push_back(messages);
  ranks_->sum(sums);
  for (size_t w = 0; w < digests.size(); ++w) digests[w] = {sums[2 * w], sums[2 * w + 1]};
  messages = sums.back();
  const size_t v = model_.variable_count(), programs = model_.program_count();
  const auto values = [&](uint64_t h) {
    return pass_hash(h, [&](uint64_t h, uint32_t first, uint32_t end) {
      return continue_hash(h, std::span(state.values).subspan(first * v, (end - first) * v));
    });
  };
  // Every rank holds the graph and the bodies whole as yet; each hashes its own modules' all the
  // same, as it will once a rank holds only its own modules' and their neighbours'.
  const auto by_module = [&](const auto* whole) {
    return [&, whole](uint64_t h) {
      return pass_hash(h, [&](uint64_t h, uint32_t first, uint32_t end) {
        return continue_hash(h, *whole, first_ + first, first_ + end);
      });
    };
  };
  const auto inbox = [&](uint64_t h) {
    return pass_hash(h, [&](uint64_t h, uint32_t first, uint32_t end) {
      const std::vector<uint32_t>& begin = state.inbox.begin;  // empty before the first delivery
      if (begin.empty()) return h;
      const uint32_t from = begin[first * programs], to = begin[end * programs];
      return continue_hash(h, state.inbox.messages.all().subspan(from, to - from));
    });
  };
  const uint64_t n = model_.module_count();
  return hash_state(state, digests,
                    {n * v, values, state.graph ? n : 0, by_module(state.graph.get()), state.bodies.empty() ? 0 : n,
                     by_module(&state.bodies), messages, inbox});
}

void Runtime::intervene(State& state, std::span<const Intervention> interventions) {
  const uint32_t v = model_.variable_count();
  for (const Intervention& i : interventions) {
    if (i.module >= model_.module_count() ||
        (i.kind == Intervention::Kind::Set && (i.column < 0 || uint32_t(i.column) >= v)))
      throw ProgramError(std::string("a ") + intervention_name(i.kind) + " intervention at step " +
                         std::to_string(i.at) + " names no module or variable of the model");
    switch (i.kind) {
      case Intervention::Kind::Set:  // the module's rank's alone: no other holds its variables
        if (!ranks_ || owners_.rank_of(i.module) == static_cast<uint32_t>(ranks_->rank()))
          state.values[size_t{i.module - first_} * v + size_t(i.column)] = i.value;
        break;
      case Intervention::Kind::Remove: world_.remove_module(model_, state, i.module); break;
      case Intervention::Kind::Push:
        if (state.bodies.empty())
          throw ProgramError("a push on module " + std::to_string(i.module) + " at step " + std::to_string(i.at) +
                             " needs bodies: the scenario has no physics");
        actuations_.push_back({Actuation::Kind::Push, i.module, 0, i.impulse});
        break;
    }
  }
}

// The actions due at the start of this step (queue_actions), in the order queued. An action whose
// value is unknown, whose module is absent by now or lacks the variable does nothing, and counts
// as skipped (docs/design.md §4b).
void Runtime::act(State& state) {
  const uint32_t v = model_.variable_count();
  for (const PendingAction& a : state.actions) {
    WatchState& ws = state.watches[a.watch];
    const bool can =
        a.module < model_.module_count() && state.present[a.module] && (a.remove || (a.known && a.column >= 0));
    if (!can) {
      ++ws.actions_skipped;
      continue;
    }
    ++ws.actions_done;
    if (a.remove) world_.remove_module(model_, state, a.module);
    else if (!ranks_ || owners_.rank_of(a.module) == static_cast<uint32_t>(ranks_->rank()))  // its rank's alone
      state.values[size_t{a.module - first_} * v + size_t(a.column)] = a.value;
  }
  state.actions.clear();
}

// The actions of the matches decided this step, due at the start of the next (t + λ + 1): in
// watchpoint order, then match order (by slot ids; one step's matches share t), then action order.
void Runtime::queue_actions(State& state, const StepOutput& out) {
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    const watch::Program& p = model_.watches[w].watchpoint.program;
    const WatchStepOutput& o = out.watches[w];
    if (p.actions.empty() || o.slots.empty()) continue;
    const size_t k = static_cast<size_t>(p.slot_count()), a = p.actions.size();
    for (size_t i = 0; i * k < o.slots.size(); ++i)
      for (size_t j = 0; j < a; ++j) {
        const watch::ActionCode& code = p.actions[j];
        const watch::Value value = o.actions[i * a + j];
        PendingAction act;
        act.watch = w;
        act.module = o.slots[i * k + static_cast<size_t>(code.slot)];
        act.remove = code.kind == watch::Action::Kind::Remove;
        act.column = act.remove ? -1 : model_.column(code.variable);
        act.known = value.known;
        act.value = value.value;
        state.actions.push_back(act);
      }
  }
}

// Matches in a fixed order whatever the thread count: by slot ids, their actions' values along.
void Runtime::sort_matches(uint32_t w, WatchStepOutput& o) const {
  if (o.slots.empty()) return;
  const uint32_t k = model_.watches[w].watchpoint.program.slot_count();
  std::vector<uint32_t> order(o.slots.size() / k);
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return std::lexicographical_compare(o.slots.begin() + a * k, o.slots.begin() + a * k + k, o.slots.begin() + b * k,
                                        o.slots.begin() + b * k + k);
  });
  std::vector<ModuleId> sorted;
  sorted.reserve(o.slots.size());
  for (uint32_t i : order) sorted.insert(sorted.end(), o.slots.begin() + i * k, o.slots.begin() + i * k + k);
  o.slots = std::move(sorted);
  if (const size_t a = model_.watches[w].watchpoint.program.actions.size(); a > 0) {
    std::vector<watch::Value> values;
    values.reserve(o.actions.size());
    for (uint32_t i : order) values.insert(values.end(), o.actions.begin() + i * a, o.actions.begin() + i * a + a);
    o.actions = std::move(values);
  }
}

// Over ranks, the agents of a watchpoint with an aggregate read their neighbours' values, which
// may be another rank's modules': every rank's values of the step are gathered and written into
// those agents' history, where the hop (watch::Program::agent_delay) reads them from the next step
// on. A whole gather, not only the border's: simple, and right whatever moves.
void Runtime::share_neighbor_values(State& state) {
  std::vector<uint32_t> acting;
  for (uint32_t w : agent_watches_)
    if (!model_.watches[w].watchpoint.program.aggregates.empty() && state.watches[w].agents) acting.push_back(w);
  if (!any_rank(ranks_, !acting.empty())) return;
  Gathered parts;
  const std::vector<std::span<const int64_t>> rows = gather_values(state, parts);
  const uint32_t v = model_.variable_count(), me = static_cast<uint32_t>(ranks_->rank());
  for (uint32_t w : acting) {
    watch::AgentHistory& history = state.watches[w].agents->history();
    for (uint32_t b = 0; b < blocks_; ++b) {
      if (owners_.block_rank[b] == me) continue;
      for (uint32_t m = block_begin(b); m < block_begin(b + 1); ++m)
        for (size_t c = 0; c < columns_[w].size(); ++c) {
          if (columns_[w][c] < 0) continue;
          const int64_t value = rows[b][size_t{m - block_begin(b)} * v + static_cast<size_t>(columns_[w][c])];
          history.set_value(m, static_cast<int>(c), state.step, value, state.present[m] != 0);
        }
    }
  }
}

bool Runtime::observes(uint32_t w, std::span<const uint8_t> watching) const {
  return watching.empty() || watching[w] || !model_.watches[w].watchpoint.program.actions.empty();
}

void Runtime::step(State& state, StepOutput& out, std::span<const Intervention> interventions,
                   std::span<const uint8_t> watching) {
  out.step = state.step;
  out.watches.assign(model_.watches.size(), WatchStepOutput{});
  // Pushes made from outside go to the world first, then the programs' own requests.
  actuations_.clear();
  act(state);
  intervene(state, interventions);
  // The watchpoints whose agents run this step make room for it before the threads record it.
  agent_watches_.clear();
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    if (!model_.watches[w].runs_on_agents() || state.watches[w].stopped) continue;
    if (!observes(w, watching)) continue;
    agent_watches_.push_back(w);
    for (watch::RecordBuffer& lane : sending_[w]) lane.clear();  // a step that failed may have filled some
    state.watches[w].agents->begin_record(
        make_frame(model_, state.step, next_values_, state.present, state.graph, first_));
  }
  if (ranks_) {
    run_over_ranks(state);
  } else {
    pool_.run([&](unsigned thread) {
      start_thread(thread, state);
      run_blocks(thread, own_blocks_, state);
    });
  }
  agree_on_failure_and_gather_actuations(state.step);

  std::swap(state.values, next_values_);  // assign: the variables now hold step t's values
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    if (state.watches[w].stopped || !observes(w, watching)) continue;
    if (model_.watches[w].runs_on_agents())
      finish_distributed(w, state, out.watches[w], state.step - model_.watches[w].watchpoint.program.agent_delay());
    else observe_detector(w, state, out.watches[w]);
    WatchStepOutput& o = out.watches[w];
    state.watches[w].matches += o.matches;
    sort_matches(w, o);
  }
  queue_actions(state, out);
  if (ranks_) share_neighbor_values(state);
  out.present = state.present;
  out.graph = state.graph;
  const uint64_t sent_before = state.program_messages;
  deliver_program_messages(state);
  out.program_messages = state.program_messages - sent_before;
  ++state.step;
  const auto moving_on = std::chrono::steady_clock::now();
  world_.advance(model_, state, actuations_, pool_);
  world_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - moving_on).count();
}

}  // namespace dw::sim
