-- The paper's medium-intensity workload (§V-B), the Lua twin of scenarios/programs/aggregation_routing.cpp
-- with three landmarks: the same variables, messages and order, so the same state hashes and
-- matches after every step. (The C++ program starts its distances at -1 and a script's variables
-- start at 0; both set every variable at every step, so only the state before step 0 differs.)
--
-- Every step each module broadcasts its hop distance to the root, its parent, its subtree's sum
-- and its hop distance to each landmark, and recomputes them from its neighbours' messages:
--   dist    0 at the root, else 1 + the smallest neighbour dist (the spanning tree's depth)
--   parent  the neighbour with that smallest dist (ties: the smallest id)
--   sum     1 + the sums of the neighbours whose parent it is (the subtree's module count)
--   lm<i>   0 at landmark i, else 1 + the smallest neighbour lm<i> (a routing gradient)
-- Unknown distances are -1. The default landmarks are the C++ twin's on 1,000 modules: module
-- (2i + 1) * N / 6 for N modules.
program = {
  vars = { "dist", "parent", "sum", "lm0", "lm1", "lm2" },
  params = { root = 0, landmark0 = 166, landmark1 = 500, landmark2 = 833 },
}

-- 1 + the smallest known (>= 0) word w of the messages, or -1 when none knows it.
local function closest(inbox, w)
  local best = -1
  for i = 1, #inbox do
    local v = inbox[i].data[w]
    if v >= 0 and (best < 0 or v < best) then best = v end
  end
  return best < 0 and -1 or best + 1
end

function step(m)
  local inbox, id = m:inbox(), m.id  -- message words: dist, parent, sum, lm0, lm1, lm2
  local is_root = id == m:param("root")
  local dist = is_root and 0 or closest(inbox, 1)
  local parent = -1
  if not is_root and dist >= 0 then
    for i = 1, #inbox do  -- in arrival order, by sender id: the first is the smallest id
      if inbox[i].data[1] == dist - 1 then
        parent = inbox[i].from
        break
      end
    end
  end
  local sum = 1
  for i = 1, #inbox do
    local data = inbox[i].data
    if data[2] == id then sum = sum + data[3] end
  end
  local lm0 = id == m:param("landmark0") and 0 or closest(inbox, 4)
  local lm1 = id == m:param("landmark1") and 0 or closest(inbox, 5)
  local lm2 = id == m:param("landmark2") and 0 or closest(inbox, 6)
  m:set("dist", dist)
  m:set("parent", parent)
  m:set("sum", sum)
  m:set("lm0", lm0)
  m:set("lm1", lm1)
  m:set("lm2", lm2)
  m:broadcast({ dist, parent, sum, lm0, lm1, lm2 })
end
