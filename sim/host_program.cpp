#include "sim/host_program.h"

#include <algorithm>
#include <cstring>

#include "sim/random.h"

namespace dw::sim {

bool same_variables(const HostProgram& a, const HostProgram& b) {
  const std::vector<VariableSpec> x = a.variables(), y = b.variables();
  return std::equal(x.begin(), x.end(), y.begin(), y.end(),
                    [](const VariableSpec& u, const VariableSpec& v) { return u.name == v.name; });
}

bool ModuleContext::is_neighbor(ModuleId m) const {
  return std::binary_search(neighbors_.begin(), neighbors_.end(), m);
}

uint64_t ModuleContext::random(uint32_t stream) const {
  // Program 0's streams are the bare stream numbers, so that a lone random_vars program draws
  // exactly the numbers of the synthetic Table I trace.
  return counter_random(seed_, id_, static_cast<uint64_t>(step_), (uint64_t{program_} << 32) | stream);
}

void ModuleContext::fail(const std::string& what) {
  // The lowest module's first misuse wins: the one module order meets first, whatever order a
  // thread ran its blocks in (over ranks, border blocks go first).
  if (!outbox_.error.empty() && outbox_.error_module <= id_) return;
  outbox_.error = std::string(program_name_) + " on module " + std::to_string(id_) + " " + what;
  outbox_.error_module = id_;
  outbox_.error_step = step_;
}

bool ModuleContext::check_size(size_t words) {
  if (words <= Message::kMaxWords) return true;
  fail("sent a message of " + std::to_string(words) + " words; the most is " + std::to_string(Message::kMaxWords));
  return false;
}

void ModuleContext::actuate(const Actuation& a) {
  if (!has_body()) {
    fail("asked its body to move or latch at step " + std::to_string(step_) +
         ", but the world has no bodies (the scenario's physics is off)");
    return;
  }
  outbox_.actuations.push_back(a);
}

void ModuleContext::pivot(ModuleId about, Vec3 offset) {
  if (!is_neighbor(about)) {
    fail("asked to pivot about module " + std::to_string(about) + " at step " + std::to_string(step_) +
         ", which is not its neighbour");
    return;
  }
  actuate({Actuation::Kind::Pivot, id_, about, offset});
}

void ModuleContext::bond(ModuleId other) {
  if (!is_neighbor(other)) {
    fail("asked to bond with module " + std::to_string(other) + " at step " + std::to_string(step_) +
         ", which is not its neighbour");
    return;
  }
  actuate({Actuation::Kind::Bond, id_, other, {}});
}

void ModuleContext::send(ModuleId to, std::span<const int64_t> payload) {
  if (!check_size(payload.size())) return;
  if (!is_neighbor(to)) {
    fail("sent to module " + std::to_string(to) + " at step " + std::to_string(step_) + ", which is not its neighbour");
    return;
  }
  post(to, payload);
}

void ModuleContext::broadcast(std::span<const int64_t> payload) {
  if (!check_size(payload.size())) return;
  for (ModuleId n : neighbors_) post(n, payload);
}

void ModuleContext::post(ModuleId to, std::span<const int64_t> payload) {
  // Past the step's limit on this thread, the step's messages in all are past it too: the step
  // will fail whatever follows, and what is sent is not kept.
  if (outbox_.over) return;
  if (outbox_.byte_limit > 0 &&
      outbox_.messages.used_bytes() + sizeof(MessageHeader) + payload.size_bytes() > outbox_.byte_limit) {
    outbox_.over = true;
    return;
  }
  outbox_.messages.add(id_, to, program_, payload);
}

}  // namespace dw::sim
