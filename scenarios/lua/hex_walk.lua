-- Walkers on a hexagonal lattice going round the ensemble they belong to, a pivot every `every`
-- steps: 2-D catoms climbing a pile against gravity (hex2d_vertical, rows climbing z) or
-- Hexanodes walking round a patch on the ground (hex2d, rows along y). The walkers are modules
-- `a` and `b`; `a_turn` and `b_turn` say which way each goes round the ensemble: -1
-- anticlockwise (the ensemble on its left, as seen with x right and the rows' axis up), 1
-- clockwise. A walker pivots about the first neighbour of the arc of cells it touches
-- into the free cell before it, as a hand kept on a wall does; the cell after that (the one both
-- cells touch besides the neighbour) must be free too, since a disc bulges over it as it rolls,
-- and so must the cell across from the neighbour for a Hexanode, whose far edge sweeps over it
-- (and over one cell beyond the cell it goes to, which a walker cannot see: there, nothing is).
-- It stops where the next cell is off the lattice, and, in a vertical plane, where it could not
-- see the cell it goes to supported by a module below it (docs/physics.md: the world refuses a
-- pivot that would leave a catom hanging, and a refused pivot ends the run).
--
-- A walker pivots every `every` steps from step `a_delay` (or `b_delay`) + `every` on. Only the
-- walkers move: every other module is still in its own cell, so module c + nx * r is the one in
-- column c of row r. The other walker is the one module whose id does not say where it is; a
-- walker touching it stops (docs/physics.md: two walkers meeting head on block each other).
program = {
  vars = { "rolls", "row" },
  params = {
    nx = 9, ny = 5, vertical = 1, every = 12, a = 0, b = 8, a_turn = 1, b_turn = -1, a_delay = 0, b_delay = 0,
  },
}

local h = math.sqrt(3) / 2
-- The six ways to a neighbour, anticlockwise from +x: x, and the step along the rows' axis.
local ways = { { 1, 0 }, { 0.5, h }, { -0.5, h }, { -1, 0 }, { -0.5, -h }, { 0.5, -h } }

-- The cell next to (c, r) the way k (1..6) goes: odd rows sit half a module right.
local function next_cell(c, r, k)
  local odd = r % 2 == 1
  if k == 1 then return c + 1, r end
  if k == 4 then return c - 1, r end
  local dr = (k == 2 or k == 3) and 1 or -1
  if k == 2 or k == 6 then return c + (odd and 1 or 0), r + dr end
  return c - (odd and 0 or 1), r + dr
end

local function wrap(k) return (k - 1) % 6 + 1 end

function step(m)
  local x, y, z = m:position()
  local across = m:param("vertical") == 1 and z or y
  local r = math.floor(across / h + 0.5)
  m:set("row", r)
  local turn = (m.id == m:param("a")) and m:param("a_turn") or ((m.id == m:param("b")) and m:param("b_turn") or 0)
  if turn == 0 or m:moving() then return end
  local delay = (m.id == m:param("a")) and m:param("a_delay") or m:param("b_delay")
  local since = m.step - delay
  if since <= 0 or since % m:param("every") ~= 0 then return end
  local nx, ny = m:param("nx"), m:param("ny")
  local c = math.floor(x - ((r % 2 == 1) and 0.5 or 0) + 0.5)
  -- The other walker is not in the cell its id names: one that touches it stops where it is,
  -- since it cannot tell which cell the other holds (two walkers meeting head on both stop).
  local other = (m.id == m:param("a")) and m:param("b") or m:param("a")
  local taken = {}
  for _, n in ipairs(m:neighbors()) do
    if n == other then return end
    taken[n] = true
  end
  local function held(cc, rr) return cc >= 0 and rr >= 0 and cc < nx and rr < ny and taken[cc + nx * rr] end
  local function inside(cc, rr) return cc >= 0 and rr >= 0 and cc < nx and rr < ny end
  for k = 1, 6 do
    local pc, pr = next_cell(c, r, k)
    local tc, tr = next_cell(c, r, wrap(k + turn))
    local ec, er = next_cell(c, r, wrap(k + 2 * turn))
    local fc, fr = next_cell(c, r, wrap(k + 3))
    if held(pc, pr) and not held(tc, tr) then
      if not inside(tc, tr) or held(ec, er) then return end
      if m:param("vertical") == 0 and held(fc, fr) then return end
      -- In a vertical plane the cell must rest on the ground or on the neighbour pivoted about.
      if m:param("vertical") == 1 and tr > 0 and pr >= tr then return end
      local w = ways[wrap(k + turn)]
      if m:param("vertical") == 1 then
        m:pivot(pc + nx * pr, w[1], 0, w[2])
      else
        m:pivot(pc + nx * pr, w[1], w[2], 0)
      end
      m:set("rolls", m:get("rolls") + 1)
      return
    end
  end
end
