-- 2-hop leader election (the paper's Fig. 2 setting), the Lua twin of
-- scenarios/programs/leader_election.cpp: the same variables, messages and random draw, so the same state
-- hashes and matches. Leaders end up at least three hops apart.
--
-- Each module draws a unique priority at step 0. Every step it broadcasts its status, its
-- priority, the best priority among the undecided modules it knows within one hop (itself
-- included), and whether a leader is within one hop; from its neighbours' messages it sees its
-- 2-hop neighbourhood one step late. An undecided module that hears of a leader within two hops
-- becomes a follower; one whose priority beats every undecided module within two hops (from step
-- 2 on) becomes a leader.
--
-- bug = 1 compares only 1-hop neighbours and only listens to 1-hop leaders: the classic mistake
-- that makes the paper's Fig. 2 violation, two leaders two hops apart.
program = {
  vars = { "isLeader", "_status", "_priority" },
  params = { bug = 0 },
}

-- Statuses (<const>: compiled in, so step keeps nothing outside the module's variables).
local UNDECIDED <const> = 0
local LEADER <const> = 1
local FOLLOWER <const> = 2

function step(m)
  local priority = m:get("_priority")
  if m.step == 0 then
    -- Unique: random high bits (m:random(0) draws 64 bits), the module id in the low 24.
    priority = ((m:random(0) >> 25) << 24) | (m.id & 0xFFFFFF)
    m:set("_priority", priority)
  end
  local status = m:get("_status")

  -- The neighbourhood as the inbox tells it (the neighbours' state at t - 1): each message is
  -- { status, priority, best priority within one hop, leader within one hop }.
  local leader_1hop, leader_2hop = false, false
  local best_neighbor, best_2hop = -1, -1  -- of the undecided neighbours; what they know of
  local inbox = m:inbox()
  for i = 1, #inbox do
    local data = inbox[i].data
    local status_of, priority_of, best_of = data[1], data[2], data[3]
    if status_of == LEADER then
      leader_1hop = true
    elseif status_of == UNDECIDED and priority_of > best_neighbor then
      best_neighbor = priority_of
    end
    if data[4] ~= 0 then leader_2hop = true end
    if best_of > best_2hop then best_2hop = best_of end
  end

  local bug = m:param("bug") ~= 0
  if status == UNDECIDED then
    local covered = leader_1hop or (not bug and leader_2hop)
    local rival = best_neighbor
    if not bug and best_2hop > rival then rival = best_2hop end
    local ready = bug and 1 or 2  -- the step from which the compared priorities have arrived
    if covered then
      status = FOLLOWER
    elseif m.step >= ready and priority >= rival then  -- rival may be us, relayed back
      status = LEADER
    end
  end
  m:set("_status", status)
  m:set("isLeader", status == LEADER and 1 or 0)
  -- What the neighbours learn: the new status, the best undecided priority within one hop, and
  -- whether a leader is within one hop.
  local best_1hop = status == UNDECIDED and priority or -1
  if best_neighbor > best_1hop then best_1hop = best_neighbor end
  m:broadcast({ status, priority, best_1hop, (leader_1hop or status == LEADER) and 1 or 0 })
end
