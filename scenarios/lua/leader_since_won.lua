-- leader_since_won.lua: min-id flooding leader election for a `since` watchpoint
-- (scenarios/leader_since_won.toml). Each module floods the least id it has heard; at step `round`
-- the module that heard none less than its own wins: `won` is 1 that step only, and it is the
-- leader (`isLeader` 1) from then on.
-- The planted bug: module `impostor` claims leadership at step `impostor_at` without having won.
program = {
  vars = { "best", "won", "isLeader" },
  params = { round = 20, impostor = -1, impostor_at = -1 },
}

function init(m) m:set("best", m.id) end

function step(m)
  local best = m:get("best")  -- as of the previous step
  for _, msg in ipairs(m:inbox()) do
    if msg.data[1] < best then best = msg.data[1] end
  end
  m:set("best", best)
  local won = m.step == m:param("round") and best == m.id
  m:set("won", won and 1 or 0)
  if won or (m.id == m:param("impostor") and m.step >= m:param("impostor_at")) then m:set("isLeader", 1) end
  m:broadcast({ best })
end
