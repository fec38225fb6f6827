// The host-program API (docs/design.md §2): what a module's program sees and may do in one step.
// A program is a const object fixed for the run (its parameters live in it); everything that
// changes lives in the module's variables, so a snapshot of the variables is a snapshot of the
// program. Names starting with '_' are hidden variables: state, not meant for display.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sim/actuation.h"
#include "sim/bodies.h"
#include "sim/message.h"
#include "sim/neighbor_graph.h"

namespace dw::sim {

// A host program misused the API; the run cannot go on.
struct ProgramError : std::runtime_error {
  using std::runtime_error::runtime_error;
  ProgramError(const std::string& what, ModuleId module, int64_t step)
      : std::runtime_error(what), module(module), step(step) {}
  // The module whose program failed and the step it was running; none for a bad intervention.
  std::optional<ModuleId> module;
  int64_t step = -1;
};

struct VariableSpec {
  std::string name;
  int64_t initial = 0;  // the value before step 0
};

class ModuleContext;

// Working memory a program keeps per stepping thread (an interpreter, buffers), never a module's
// state, which lives in its variables only. Every runtime thread has its own, so no lock is taken.
class ProgramScratch {
 public:
  virtual ~ProgramScratch() = default;
};

class HostProgram {
 public:
  virtual ~HostProgram() = default;
  virtual std::string_view name() const = 0;
  // The variables this program keeps; the program addresses them by their index in this list.
  virtual std::vector<VariableSpec> variables() const = 0;
  // Runs once per present module and step: reads the inbox, the neighbours and the variables,
  // assigns variables and sends messages.
  virtual void step(ModuleContext& module) const = 0;
  // A stepping thread's scratch, made when the runtime starts (ModuleContext::scratch hands it
  // back); nullptr, the default, when the program needs none.
  virtual std::unique_ptr<ProgramScratch> make_scratch() const { return nullptr; }
  // Whether its calls must come one at a time, in module id order, from one thread (a program in
  // an interpreter with one lock, whose user code may keep state outside the variables: Python).
  // Then the runtime runs every thread's share of a step in turn on the caller's thread, thread 0's
  // first, which is module order: the same calls in the same order on every thread count.
  virtual bool in_module_order() const { return false; }
};

// Whether two programs keep the same variables (names, in order): one may replace the other in a run.
bool same_variables(const HostProgram& a, const HostProgram& b);

// Where a step's sends go, per thread; the runtime checks and delivers them.
struct Outbox {
  MessageList messages;
  std::vector<Actuation> actuations;
  // Model::message_bytes_per_step, set when the runtime starts (0: none), and whether this
  // thread's messages went past it this step (what was sent after that is not kept; the step
  // fails once every module has run).
  uint64_t byte_limit = 0;
  bool over = false;
  std::string error;          // the lowest module's first misuse of the API (sending to a non-neighbour, ...)
  ModuleId error_module = 0;  // whose it was, at which step
  int64_t error_step = -1;
};

class ModuleContext {
 public:
  ModuleContext(ModuleId id, int64_t step, uint64_t seed, uint16_t program, std::span<const ModuleId> neighbors,
                Messages inbox, const int64_t* before, int64_t* after, Outbox& outbox, std::string_view program_name,
                const Bodies& bodies, ProgramScratch* scratch = nullptr)
      : id_(id),
        step_(step),
        seed_(seed),
        program_(program),
        neighbors_(neighbors),
        inbox_(inbox),
        before_(before),
        after_(after),
        outbox_(outbox),
        program_name_(program_name),
        bodies_(bodies),
        scratch_(scratch) {}

  ModuleId id() const { return id_; }
  int64_t step() const { return step_; }
  // N(self, t), sorted by id.
  std::span<const ModuleId> neighbors() const { return neighbors_; }
  bool is_neighbor(ModuleId m) const;
  // This program's messages sent to this module at t - 1: by sender id, then in sending order.
  Messages inbox() const { return inbox_; }

  // The variable's value at t - 1 (its initial value at step 0); assignments in this step do
  // not show until the next one.
  int64_t get(uint32_t variable) const { return before_[variable]; }
  // Assigns the value the variable has at step t.
  void set(uint32_t variable, int64_t value) { after_[variable] = value; }
  // The value assigned so far in this step (the value at t - 1 when none was).
  int64_t assigned(uint32_t variable) const { return after_[variable]; }

  // This module's random numbers: a pure function of (seed, module, step, program, stream).
  uint64_t random(uint32_t stream) const;
  // Uniform in 0 .. n - 1 (n > 0).
  int64_t uniform(int64_t n, uint32_t stream) const { return static_cast<int64_t>(random(stream) % uint64_t(n)); }

  // What the step has sent and asked of the body so far, to take back (a call run again).
  struct Sent {
    size_t messages, actuations;
    bool over;
  };
  Sent sent() const { return {outbox_.messages.size(), outbox_.actuations.size(), outbox_.over}; }
  void take_back(Sent s) {
    outbox_.messages.keep_first(s.messages);
    outbox_.actuations.resize(s.actuations);
    outbox_.over = s.over;
  }

  // This thread's scratch of the program (HostProgram::make_scratch).
  ProgramScratch* scratch() const { return scratch_; }

  // Sends to a neighbour (delivered at t + 1). Sending to a module that is not a neighbour, or
  // more than Message::kMaxWords words, is a program error that stops the run.
  void send(ModuleId to, std::span<const int64_t> payload);
  void send(ModuleId to, std::initializer_list<int64_t> payload) {
    send(to, std::span(payload.begin(), payload.size()));
  }
  // Sends the same message to every neighbour.
  void broadcast(std::span<const int64_t> payload);
  void broadcast(std::initializer_list<int64_t> payload) { broadcast(std::span(payload.begin(), payload.size())); }

  // The module's body, as the step began (sensing). Only in a physical world: has_body() says.
  bool has_body() const { return !bodies_.empty(); }
  Pose pose() const { return bodies_.poses[id_]; }
  Velocity velocity() const { return bodies_.velocities[id_]; }
  // Making a lattice move (it then belongs to no cluster and has no bonds).
  bool moving() const { return bodies_.moving(id_); }

  // Actuation, carried out when the world moves on to the next step (see sim/actuation.h). In a
  // world without bodies, asking is a program error.
  void push(Vec3 impulse) { actuate({Actuation::Kind::Push, id_, 0, impulse}); }
  // A lattice move by `offset`, one module size long, into a free cell: the module releases its
  // bonds, glides there, and latches to what it touches on arrival. Refused (nothing happens)
  // when the cell is taken or the module is already moving.
  void move(Vec3 offset) { actuate({Actuation::Kind::Move, id_, 0, offset}); }
  // A pivot about the neighbour `about` into the free cell at `offset` from this one: a cube
  // turns about the edge it shares with `about`, by 90 degrees to the next cell along the face
  // it rests on (offset perpendicular to the way to `about`) or by 180 over that edge onto the
  // next face of `about`; a sphere rolls over `about` into a cell touching both. Like a move it
  // takes move_steps steps and releases the bonds. A cell that is taken, a sweep that would pass
  // through another module, or an offset no pivot about `about` reaches is a program error.
  void pivot(ModuleId about, Vec3 offset);
  void release(ModuleId other) { actuate({Actuation::Kind::Release, id_, other, {}}); }
  void release_all() { actuate({Actuation::Kind::ReleaseAll, id_, 0, {}}); }
  // Latches to a neighbour (it must be one now).
  void bond(ModuleId other);

  // A program error that stops the run: "<program> on module <id> <what>" (the lowest module's first one wins).
  void fail(const std::string& what);

 private:
  bool check_size(size_t words);
  void post(ModuleId to, std::span<const int64_t> payload);
  void actuate(const Actuation& a);

  ModuleId id_;
  int64_t step_;
  uint64_t seed_;
  uint16_t program_;
  std::span<const ModuleId> neighbors_;
  Messages inbox_;
  const int64_t* before_;
  int64_t* after_;
  Outbox& outbox_;
  std::string_view program_name_;
  const Bodies& bodies_;
  ProgramScratch* scratch_;
};

}  // namespace dw::sim
