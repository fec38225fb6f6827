-- Catoms 3D rolling over the surface of an fcc block: each catom of the top layer rolls one site
-- along +x over a catom of the layer below every `every` steps, until it reaches site `stop`.
-- A catom pivots about a neighbour it touches (m:pivot), into a site that touches that neighbour
-- too; the world checks the site and the sweep, and finds the arc (over the neighbour, or along
-- the groove between it and the next catom down).
--
-- Positions on the fcc lattice: layer k lies at height k * sqrt(2)/2, odd layers shifted by half
-- a site along x and y; site (i, j) of layer k is module i + nx * (j + ny * k).
program = {
  vars = { "rolls" },
  params = { nx = 6, ny = 6, top = 3, every = 12, stop = 5 },
}

local layer_height = math.sqrt(2) / 2

function step(m)
  if m.step == 0 or m.step % m:param("every") ~= 0 or m:moving() then return end
  local x, y, z = m:position()
  local k = math.floor(z / layer_height + 0.5)
  if k ~= m:param("top") then return end
  local shift = (k % 2 == 1) and 0.5 or 0
  local i, j = math.floor(x - shift + 0.5), math.floor(y - shift + 0.5)
  if i >= m:param("stop") then return end
  -- The catom of the layer below that touches this site and the next one along +x.
  local below_shift = ((k - 1) % 2 == 1) and 0.5 or 0
  local bi, bj = math.floor(x + 0.5 - below_shift + 0.5), math.floor(y - 0.5 - below_shift + 0.5)
  local about = bi + m:param("nx") * (bj + m:param("ny") * (k - 1))
  for _, n in ipairs(m:neighbors()) do
    if n == about then
      m:pivot(about, 1, 0, 0)
      m:set("rolls", m:get("rolls") + 1)
      return
    end
  end
end
