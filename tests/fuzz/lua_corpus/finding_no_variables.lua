-- Finding: a program with no variables: the runtime copied its zero variables with memcpy from
-- and to null pointers (undefined behaviour, sim/runtime.cpp run_programs).
program = { vars = {} }
function step(m) end
