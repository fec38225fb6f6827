"""dwatch.Session: python/src/session_binding.cpp over the session shell (shell/shell.h)."""

import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import dwatch
from conftest import dwatch as cli, session_answers


def test_answers_and_hashes_equal_dwatch_session(leaders):
    s = dwatch.Session(leaders, threads=2)
    assert (s.current, s.latest, s.end, s.modules) == (-1, -1, 200, 120)
    assert s.variables[0] == "isLeader" and s.watches == ["two_leaders"]
    answers = [s.run(), s.seek(0), s.set(7, "isLeader", 0), s.step(3), s.command("hash")]
    expected = session_answers(leaders, "run", "seek 0", "set 7 isLeader 0", "step 3", "hash")
    assert answers == expected
    assert s.hash() == expected[-1]["hash"]
    # The same on one thread: the hash does not depend on the threads.
    one = dwatch.Session(leaders, threads=1)
    one.run()
    one.seek(0)
    one.set(7, "isLeader", 0)
    one.step(3)
    assert one.hash() == s.hash()


def test_a_pause_stops_the_run_and_matches_are_arrays(leaders):
    s = dwatch.Session(leaders)
    answer = s.run()
    paused = answer["paused"]
    assert paused["watch"] == "two_leaders" and s.current == paused["t"]
    found = s.matches("two_leaders")
    assert found.t.dtype == found.detected.dtype == found.slots.dtype == np.int64
    assert found.slots.shape == (len(found), 3) and len(found) == paused["matches"]
    assert tuple(found.slots[0]) == tuple(paused["group"].values())
    assert np.all(found.detected - found.t == 2)  # the distributed detector's lag for three slots
    listed = s.command("matches two_leaders")["matches"]
    assert [(m["t"], tuple(m["slots"].values())) for m in listed] == [
        (int(t), tuple(int(i) for i in row)) for t, row in zip(found.t, found.slots)
    ]
    # The group's two ends are leaders at the match's step.
    leader = s.values("isLeader")
    assert leader.dtype == np.int64 and leader.shape == (120,)
    assert leader[found.slots[0, 0]] == 1 and leader[found.slots[0, 2]] == 1


def test_values_state_and_series_agree(leaders):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    s.run(39)
    assert s.current == 39
    priority = s.values("_priority")
    for m in (0, 5, 119):
        assert s.state(m)["vars"]["_priority"] == priority[m]
    series = s.series(5, "isLeader", 0, 39)
    assert series.dtype == np.int64 and series.shape == (40,)
    for t in (0, 17, 39):
        s.seek(t)
        assert s.values("isLeader")[5] == series[t]


def test_watchpoints_added_later_see_the_whole_history(leaders):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    s.run(30)
    answer = s.watch("lone", "modules(a); a.isLeader = 1", algorithm="centralized")
    assert answer["watch"] == "lone" and answer["algorithm"] == "centralized"
    lone = s.matches("lone")
    assert len(lone) == answer["matches"] > 0 and lone.slots.shape == (len(lone), 1)
    for t, (m,) in zip(lone.t[:20], lone.slots[:20]):
        s.seek(int(t))
        assert s.values("isLeader")[m] == 1
    assert lone.count == len(lone)
    counted = s.watch("lone_count", "modules(a); a.isLeader = 1", algorithm="centralized", action="count")
    only = s.matches("lone_count")
    assert len(only) == 0 and only.count == counted["matches"] == len(lone)
    s.unwatch("lone")
    s.unwatch("lone_count")
    assert s.watches == ["two_leaders"]


def test_errors_are_exceptions_in_the_command_lines_words(leaders, tmp_path):
    s = dwatch.Session(leaders)
    with pytest.raises(dwatch.CommandError) as raised:
        s.set(99999, "isLeader", 1)
    assert "M must be an integer between 0 and 119, not '99999'" in str(raised.value)
    with pytest.raises(dwatch.CommandError, match="no watchpoint is named 'nobody'"):
        s.matches("nobody")
    with pytest.raises(dwatch.CommandError, match="'nope' is no program's variable"):
        s.values("nope")
    with pytest.raises(dwatch.WatchError) as raised:
        s.watch("bad", "modules(a); a.nope = 1")
    assert raised.value.message == "'nope' is no program's variable"
    with pytest.raises(dwatch.CommandError, match="is not an integer"):
        s.watch("12", "modules(a); a.isLeader = 1")
    with pytest.raises(dwatch.CommandError, match="no control character"):
        s.watch("a\x01b", "modules(a); a.isLeader = 1")
    with pytest.raises(dwatch.CommandError, match="cannot also hold"):
        s.watch('a "b', "modules(a); a.isLeader = 1")
    with pytest.raises(dwatch.CommandError, match="one command, on one line"):
        s.command("step\nstep")
    assert s.command("# a comment") is None
    with pytest.raises(FileNotFoundError):
        dwatch.Session(str(tmp_path / "missing.toml"))
    bad = tmp_path / "bad.toml"
    bad.write_text("steps = -3\n")
    with pytest.raises(dwatch.ScenarioError) as raised:
        dwatch.Session(str(bad))
    assert str(raised.value) in cli("run", str(bad), check=False).stderr
    with pytest.raises(dwatch.Error, match="threads must be an integer from 1 to 256"):
        dwatch.Session(leaders, threads=0)


def test_render_draws_the_view_with_the_group_in_red(leaders):
    s = dwatch.Session(leaders)
    s.run()  # paused on a two-leader group
    image = s.render(320, 200)
    assert image.dtype == np.uint8 and image.shape == (200, 320, 3)
    r, g, b = (image[..., c].astype(int) for c in range(3))
    red = (r > 150) & (g < 90) & (b < 90)
    assert red.sum() > 50, "the matched group is drawn in the outline's red"
    s.seek(0)
    s.unwatch("two_leaders")
    plain = s.render(320, 200)
    pr, pg, pb = (plain[..., c].astype(int) for c in range(3))
    assert ((pr > 150) & (pg < 90) & (pb < 90)).sum() < red.sum() / 4
    eye = s.render(320, 200, camera=((0, -40, 30), (5, 5, 0)))
    assert eye.shape == (200, 320, 3) and not np.array_equal(eye, plain)


def test_render_refuses_what_the_session_and_the_command_line_refuse(leaders):
    s = dwatch.Session(leaders)
    s.run(3)
    with pytest.raises(dwatch.Error, match="from 16 to 8192"):
        s.render(1, 1)
    for camera, said in [(((float("nan"), 0, 0), (0, 0, 0)), "finite"), (((1, 1, 1), (1, 1, 1)), "on its target"),
                         ((1, 2), "two points"), (((0, 0), (1, 1, 1)), "two points")]:
        with pytest.raises(dwatch.Error, match=said):
            s.render(64, 64, camera=camera)


def test_save_writes_a_scenario_the_session_loads_again(leaders, tmp_path):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    s.run(5)
    s.set(3, "isLeader", 1)
    saved = tmp_path / "my branch #2.toml"  # a space and a '#': sent quoted
    assert s.save(str(saved))["save"] == str(saved)
    with pytest.raises(dwatch.CommandError, match="overwrite"):
        s.save(str(saved))
    s.run(12)
    again = dwatch.Session(str(saved))
    again.run(12)
    assert again.hash() == s.hash()


def test_stepping_releases_the_gil(leaders):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    started = time.monotonic()
    s.run(20000)
    took = time.monotonic() - started
    done.set()
    counter.join()
    assert took > 0.2, "the run must be long enough to measure"
    assert ticks > took * 100, f"{ticks} ticks in {took:.2f} s: the other thread was starved"


def test_two_threads_each_with_a_session_make_their_first_arrays_at_once(leaders):
    # In a fresh interpreter, so that no array was made before: the first arrays made by two
    # threads at once deadlocked (pybind11's numpy lookup, a static, waited on under the GIL).
    program = f"""
import threading, dwatch
def work():
    s = dwatch.Session({leaders!r})
    s.run(5)
    for _ in range(20):
        s.values("isLeader"); s.series(0, "isLeader", 0, 3)
threads = [threading.Thread(target=work) for _ in range(2)]
[t.start() for t in threads]
[t.join() for t in threads]
print("both done")
"""
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=60)
    assert done.stdout == "both done\n", done.stderr


def test_ctrl_c_stops_a_long_run_and_the_session_goes_on(leaders):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    timer = threading.Timer(0.3, signal.raise_signal, args=(signal.SIGINT,))
    timer.start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        s.run(10_000_000)
    assert time.monotonic() - started < 5
    stopped_at = s.current
    assert 0 < stopped_at < 10_000_000 - 1
    # Where it stopped is a step like any other: the same state as a run that went there directly.
    direct = dwatch.Session(leaders)
    direct.action("two_leaders", "log")
    direct.run(stopped_at)
    assert direct.hash() == s.hash()
    s.step()
    assert s.current == stopped_at + 1


def test_interventions_continue_and_record_match_the_command_line(leaders, source, tmp_path):
    s = dwatch.Session(leaders)
    first = s.run()
    assert first["paused"] is not None
    went_on = s.continue_()
    assert went_on["current"] > first["current"]
    s.seek(2)
    removed = s.remove(4)
    # Step 2 is decided again on the branch (lag 2): the session simulated on to step 4.
    assert removed["intervention"]["module"] == 4 and s.latest == 4
    s.step(2)
    assert s.state(4)["present"] is False
    with pytest.raises(dwatch.CommandError, match="push needs bodies: the scenario has no physics"):
        s.push(3, 0, 0, 1)
    trace = tmp_path / "branch.jsonl"
    assert s.record(str(trace))["record"] == str(trace)
    # The recorded branch replays to the session's own matches.
    replayed = dwatch.replay(trace)["two_leaders"]
    kept = s.matches("two_leaders")
    decided = kept.t <= s.latest - 2
    np.testing.assert_array_equal(replayed.t[replayed.t <= s.latest - 2], kept.t[decided])
    expected = session_answers(leaders, "run", "continue", "seek 2", "remove 4", "step 2", "hash")
    assert s.hash() == expected[-1]["hash"]


def test_push_answers_and_hashes_as_the_command_line(source):
    scenario = str(source / "scenarios" / "push_wall.toml")
    s = dwatch.Session(scenario)
    answers = [s.step(2), s.push(59, 0.0, -500.0, 0.25), s.step(5), s.command("hash")]
    assert answers[1]["intervention"] == {"at": 2, "module": 59, "push": [0.0, -500.0, 0.25]}
    assert answers == session_answers(scenario, "step 2", "push 59 0 -500 0.25", "step 5", "hash")


def test_state_names_the_pose_the_neighbours_were_measured_from(source):
    # With physics, state() answers as `dwatch session` does (docs/session.md, "Which pose `state`
    # shows"): `pose` after the step, `nbrs_measured_from` the pose after the step before.
    scenario = str(source / "scenarios" / "slide.toml")
    s = dwatch.Session(scenario)
    s.run(8)
    now = s.state(15)
    assert now == session_answers(scenario, "run 8", "state 15")[-1]
    s.seek(7)
    before = s.state(15)
    assert now["nbrs_measured_from"] == {"t": 7, **before["pose"]}
    assert now["pose"] != before["pose"], "module 15 glides along its lattice move"


def test_a_watchpoint_named_with_a_space_is_said_quoted(leaders):
    # A scenario may name a watchpoint "two leaders #2"; so may Python, and every command naming it
    # quotes it (`unwatch "two leaders #2"`).
    s = dwatch.Session(leaders)
    s.unwatch("two_leaders")
    name = "two leaders #2"
    s.watch(name, "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)")
    assert name in s.watches
    assert s.run(to_match=name)["matched"]["watch"] == name and s.matches(name).count >= 1
    assert s.action(name, "pause")["action"] == "pause"
    assert s.run()["paused"]["watch"] == name
    s.unwatch(name)
    assert name not in s.watches



def test_a_second_thread_on_a_busy_session_gets_runtime_error_never_a_crash(leaders):
    # In a child process: before the fix this crashed the interpreter.
    program = f"""
import signal, threading, dwatch
s = dwatch.Session({leaders!r})
s.action("two_leaders", "log")
refused = []
def meanwhile():
    for call in (lambda: s.step(), lambda: s.values("isLeader"), lambda: s.current, lambda: s.run(3)):
        try:
            call()
        except RuntimeError as e:
            refused.append("in use" in str(e))
    signal.raise_signal(signal.SIGINT)
threading.Timer(0.3, meanwhile).start()
try:
    s.run(10_000_000)
except KeyboardInterrupt:
    pass
s.step()
print(refused, s.current > 0)
"""
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=60)
    assert done.stdout == "[True, True, True, True] True\n", done.stderr


def test_absent_modules_are_masked_in_values_and_series(leaders):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    s.run(5)
    assert s.present().all() and not s.values("isLeader").mask.any()
    s.remove(5)
    s.step()
    values, present = s.values("isLeader"), s.present()
    assert isinstance(values, np.ma.MaskedArray) and present.dtype == bool
    assert not present[5] and present.sum() == s.modules - 1
    assert values.mask[5] and not values.mask[np.arange(s.modules) != 5].any()
    assert values.sum() == values.data[present].sum()
    series = s.series(5, "isLeader", 0, s.current)
    assert isinstance(series, np.ma.MaskedArray) and len(series) == s.current + 1
    assert not series.mask[:5].any() and series.mask[-1]
