"""Host programs written in Python: python/src/python_program.cpp, named by a scenario's
`[[program]] python = NAME` (scenarios/scenario_programs.cpp) and run in module order
(sim::HostProgram::in_module_order, sim/runtime.cpp)."""

import pathlib

import pytest

import dwatch

LEADERS = "modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)"


class TokenRing:
    """scenarios/lua/token_ring.lua, line for line."""

    vars = ["token", "_since", "_keep"]
    params = {"timeout": 16, "duplicate_at": -1, "lose_at": -1}

    def step(self, m):
        holds = len(m.inbox()) > 0 or m.get("_keep") != 0
        if m.id == 0:
            since = 0 if holds else m.get("_since") + 1
            if since > m.param("timeout") or m.step == 0:
                holds = True  # lost, or not yet made: make one
            m.set("_since", 0 if holds else since)
        m.set("token", 1 if holds else 0)
        m.set("_keep", 0)
        if not holds or m.step == m.param("lose_at"):
            return
        neighbors = m.neighbors()
        if not neighbors:  # cut off from the ring: keep the token
            m.set("_keep", 1)
            return
        m.send(next((n for n in neighbors if n > m.id), neighbors[0]), [1])
        if m.step == m.param("duplicate_at"):
            m.set("_keep", 1)


class LeaderElection:
    """scenarios/lua/leader_election.lua, line for line (its random draw included)."""

    vars = ["isLeader", "_status", "_priority"]
    params = {"bug": 0}
    UNDECIDED, LEADER, FOLLOWER = 0, 1, 2

    def step(self, m):
        priority = m.get("_priority")
        if m.step == 0:
            priority = ((m.random(0) >> 25) << 24) | (m.id & 0xFFFFFF)
            m.set("_priority", priority)
        status = m.get("_status")
        leader_1hop = leader_2hop = False
        best_neighbor = best_2hop = -1
        for _, data in m.inbox():
            status_of, priority_of, best_of = data[0], data[1], data[2]
            if status_of == self.LEADER:
                leader_1hop = True
            elif status_of == self.UNDECIDED and priority_of > best_neighbor:
                best_neighbor = priority_of
            if data[3] != 0:
                leader_2hop = True
            best_2hop = max(best_2hop, best_of)
        bug = m.param("bug") != 0
        if status == self.UNDECIDED:
            rival = best_neighbor if bug else max(best_neighbor, best_2hop)
            if leader_1hop or (not bug and leader_2hop):
                status = self.FOLLOWER
            elif m.step >= (1 if bug else 2) and priority >= rival:
                status = self.LEADER
        m.set("_status", status)
        m.set("isLeader", 1 if status == self.LEADER else 0)
        best_1hop = max(priority if status == self.UNDECIDED else -1, best_neighbor)
        m.broadcast([status, priority, best_1hop, 1 if (leader_1hop or status == self.LEADER) else 0])


def python_twin(source: pathlib.Path, tmp_path: pathlib.Path, lua: str, name: str) -> str:
    """The Lua scenario scenarios/lua/<lua>.toml with its script replaced by the Python program `name`."""
    text = (source / "scenarios" / "lua" / f"{lua}.toml").read_text()
    assert f'script = "{lua}.lua"' in text
    path = tmp_path / f"{lua}_python.toml"
    path.write_text(text.replace(f'script = "{lua}.lua"', f'python = "{name}"'))
    return str(path)


def played(session: dwatch.Session) -> list:
    """Every answer of run() to the end (each pause a stop on the way), with the hash after each."""
    out = []
    while True:
        answer = session.run()
        out.append((answer, session.hash()))
        if not answer["paused"]:
            return out


@pytest.mark.parametrize("lua, cls", [("token_ring", TokenRing), ("leader_election", LeaderElection)])
def test_a_python_program_gives_its_lua_twins_matches_and_hashes_on_1_and_2_threads(source, tmp_path, lua, cls):
    scenario = python_twin(source, tmp_path, lua, "mine")
    lua_scenario = str(source / "scenarios" / "lua" / f"{lua}.toml")
    twin = dwatch.Session(lua_scenario, threads=1)
    expected = played(twin)
    assert len(expected) >= 2 and expected[0][0]["paused"]["matches"] > 0  # it does find something
    w = twin.watches[0]
    for threads in (1, 2):
        s = dwatch.Session(scenario, threads=threads, programs={"mine": cls})
        assert played(s) == expected
        assert s.matches(w).slots.tolist() == twin.matches(w).slots.tolist()
        assert s.matches(w).t.tolist() == twin.matches(w).t.tolist()


def test_the_scenario_parameters_reach_the_program(source, tmp_path):
    # token_ring.toml sets duplicate_at = 40; without it the token is never duplicated.
    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    s = dwatch.Session(scenario, programs={"mine": TokenRing})
    assert s.run()["paused"]["t"] == 41
    pathlib.Path(scenario).write_text(pathlib.Path(scenario).read_text().replace("duplicate_at = 40", ""))
    assert dwatch.Session(scenario, programs={"mine": TokenRing}).run()["paused"] is None


def test_calls_come_in_module_order_on_every_thread_count(source, tmp_path):
    class Recorder(TokenRing):
        def __init__(self):
            self.calls = []

        def step(self, m):
            self.calls.append((m.step, m.id))
            super().step(m)

    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    for threads in (1, 2, 4):
        recorder = Recorder()
        s = dwatch.Session(scenario, threads=threads, programs={"mine": recorder})
        s.step(5)
        assert recorder.calls == [(t, m) for t in range(5) for m in range(16)], threads


def test_an_exception_in_step_names_the_program_module_and_step(source, tmp_path):
    class Broken(TokenRing):
        def step(self, m):
            if m.id == 5 and m.step == 3:
                return 1 // 0
            super().step(m)

    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    for threads in (1, 2):
        s = dwatch.Session(scenario, threads=threads, programs={"mine": Broken})
        with pytest.raises(dwatch.CommandError) as raised:
            s.run()
        text = str(raised.value)
        assert "mine on module 5 at step 3: ZeroDivisionError: integer division or modulo by zero" in text, text
        assert f"{__file__}:" in text and "in step" in text
        assert s.current == 2  # the session stays at the last good step, usable
        assert s.values("token").count() == 16


def test_ctrl_c_inside_step_raises_keyboard_interrupt_and_keeps_the_last_whole_step(source, tmp_path):
    class Interrupted(TokenRing):
        def __init__(self):
            self.once = True

        def step(self, m):
            if m.id == 3 and m.step == 50 and self.once:
                self.once = False
                raise KeyboardInterrupt  # what Python's SIGINT handler raises in the code running
            super().step(m)

    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    expected = dwatch.Session(scenario, programs={"mine": TokenRing})
    played(expected)
    for threads in (1, 2):
        s = dwatch.Session(scenario, threads=threads, programs={"mine": Interrupted})
        assert s.run()["paused"]["t"] == 41
        with pytest.raises(KeyboardInterrupt):
            s.run()
        assert s.current == 49
        assert played(s)[-1][1] == expected.hash()  # it goes on from there as if never stopped


def test_mistakes_in_the_api_are_program_errors(source, tmp_path):
    class SendsFar(TokenRing):
        def step(self, m):
            m.send(m.id + 5, [1])

    class Undeclared(TokenRing):
        def step(self, m):
            m.set("tokn", 1)

    class Kept(TokenRing):
        kept = None

        def step(self, m):
            if Kept.kept is not None:
                Kept.kept.get("token")
            Kept.kept = m

    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    for cls, words in [
        (SendsFar, "mine on module 0 at step 0: ValueError: module 0 sent to 5, which is not its neighbour"),
        (Undeclared, "KeyError: \"'tokn' is not a variable of this program"),
        (Kept, "mine on module 1 at step 0: RuntimeError: this Module is step(m)'s for one call"),
    ]:
        with pytest.raises(dwatch.CommandError, match=None) as raised:
            dwatch.Session(scenario, programs={"mine": cls}).step()
        assert words in str(raised.value), str(raised.value)


def test_a_scenario_naming_a_python_program_not_given_is_refused(source, tmp_path):
    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    with pytest.raises(dwatch.ScenarioError) as raised:
        dwatch.Session(scenario)
    assert raised.value.file == scenario and raised.value.line is not None
    assert 'the Python program "mine" is not given' in str(raised.value)
    assert 'programs={"mine": ...}' in str(raised.value)
    with pytest.raises(dwatch.ScenarioError, match=r'no Python program "mine" is given \(given: other\)'):
        dwatch.Session(scenario, programs={"other": TokenRing})


def test_a_class_that_declares_itself_wrongly_is_refused_at_its_table(source, tmp_path):
    class NoVars:
        def step(self, m):
            pass

    class BadParam(TokenRing):
        params = {"timeout": 1.5}

    class FailsToMake(TokenRing):
        def __init__(self):
            raise RuntimeError("no robot today")

    scenario = python_twin(source, tmp_path, "token_ring", "mine")
    for cls, words in [
        (NoVars, '(NoVars) must declare vars'),
        (BadParam, "must map names (str) to integer defaults, not 'timeout': 1.5"),
        (FailsToMake, "could not be made: RuntimeError: no robot today"),
    ]:
        with pytest.raises(dwatch.ScenarioError) as raised:
            dwatch.Session(scenario, programs={"mine": cls})
        assert words in str(raised.value), str(raised.value)
    # A parameter the class does not declare is an unknown key of the table.
    with pytest.raises(dwatch.ScenarioError, match="duplicate_at"):
        dwatch.Session(scenario, programs={"mine": type("Plain", (), {"vars": ["token"], "step": lambda self, m: None})})
