"""A Session's copies: fork() (two branches side by side) and snapshot() / restore() (MuJoCo's
mj_getState / mj_setState), over sim::Session's copy (sim/session.h) and shell/fresh_world.h."""

import subprocess
import sys

import pytest

import dwatch


def straight(path, steps, threads=1, set_at=None):
    """The hashes of steps 0..steps - 1 of a run that never went back (one intervention, optionally)."""
    s = dwatch.Session(path, threads=threads)
    s.action(s.watches[0], "log")
    hashes = []
    for t in range(steps):
        s.step()
        if set_at and t == set_at[0]:
            s.set(*set_at[1:])
        hashes.append(s.hash())
    return hashes, s.matches(s.watches[0])


def same_matches(a, b):
    return (a.t.tolist(), a.detected.tolist(), a.slots.tolist()) == (b.t.tolist(), b.detected.tolist(), b.slots.tolist())


def test_a_fork_goes_on_as_the_session_would_and_each_leaves_the_other_alone(leaders):
    # The branch (an intervention at step 6) and the history are the fork's too.
    want, want_matches = straight(leaders, 40, set_at=(6, 7, "isLeader", 1))
    s = dwatch.Session(leaders, threads=2)
    s.action("two_leaders", "log")
    s.run(6)
    s.set(7, "isLeader", 1)
    s.run(15)
    f = s.fork()
    assert (f.current, f.latest, f.watches, f.hash()) == (s.current, s.latest, s.watches, s.hash())
    assert s.command("interventions") == f.command("interventions")
    for t in range(16, 40):  # in turns
        f.step()
        s.step()
        assert f.hash() == s.hash() == want[t]
    assert same_matches(f.matches("two_leaders"), want_matches)
    # What the fork does is its own: another branch, another watchpoint, another step.
    f.seek(20)
    f.set(3, "isLeader", 1)
    f.watch("solo", "modules(a); a.isLeader = 1")
    f.run(30)
    assert s.watches == ["two_leaders"] and s.current == 39 and s.hash() == want[39]
    s.seek(29)
    assert s.hash() == want[29] != f.hash()
    assert same_matches(s.matches("two_leaders"), want_matches)


def test_a_fork_of_a_physical_scenario_steps_a_world_of_its_own(source):
    path = source / "scenarios" / "token_ring_physics.toml"
    want, _ = straight(path, 60)
    s = dwatch.Session(path)
    s.action("token_from_nowhere", "log")
    s.run(20)
    snap = s.snapshot()
    f = s.fork()
    f.seek(10)  # back into the history: the fork's world is told a keyframe's state
    f.run(20)
    for t in range(21, 60):  # in turns
        f.step()
        s.step()
        assert f.hash() == s.hash() == want[t]
    s.restore(snap)  # the world is told the snapshot's state before it steps again
    for t in range(21, 40):
        s.step()
        assert s.hash() == want[t]


def test_restore_then_run_equals_the_run_that_never_went_back(leaders):
    want, want_matches = straight(leaders, 51)
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    s.run(12)
    snap = s.snapshot()
    assert (snap.current, snap.latest) == (12, s.latest) and "step 12" in repr(snap)
    # Everything that changes, changed: a branch, a watchpoint, the cursor, the history's length.
    s.set(4, "isLeader", 1)
    s.watch("solo", "modules(a); a.isLeader = 1")
    s.action("two_leaders", "count")
    s.run(45)
    assert s.hash() != want[45]
    for _ in range(2):  # a snapshot restores as often as wanted
        s.restore(snap)
        assert (s.current, s.watches, s.hash()) == (12, ["two_leaders"], want[12])
        assert s.command("interventions")["interventions"] == []
        s.run(50)
        assert s.hash() == want[50]
        assert same_matches(s.matches("two_leaders"), want_matches)
        s.seek(30)
        assert s.hash() == want[30]


def test_a_snapshot_restores_into_a_fork_but_not_into_another_load(leaders):
    s = dwatch.Session(leaders)
    s.action("two_leaders", "log")
    s.step(10)
    snap = s.snapshot()
    f = s.fork()
    f.step(20)
    f.restore(snap)
    assert (f.current, f.hash()) == (9, s.hash())
    other = dwatch.Session(leaders)
    with pytest.raises(dwatch.ArgumentError, match="the session it was taken of, or a fork of it"):
        other.restore(snap)
    s.close()
    assert f.snapshot().current == 9  # the fork lives on without the first
    f.restore(snap)  # and so does the snapshot
    with pytest.raises(dwatch.Error, match="closed"):
        s.fork()


THREADS_ON_A_FORK = """
import sys, threading
import dwatch
path = sys.argv[1]
ref = dwatch.Session(path)
want = []
for t in range(150):
    ref.step()
    want.append(ref.hash())
s = dwatch.Session(path)
s.run(50)
f = s.fork()
got = {}
def go(name, session):
    got[name] = []
    for t in range(51, 150):
        session.step()
        got[name].append(session.hash())
threads = [threading.Thread(target=go, args=item) for item in (("s", s), ("f", f))]
for thread in threads:
    thread.start()
for thread in threads:
    thread.join()
print(got["s"] == want[51:], got["f"] == want[51:])
"""


def test_a_fork_and_its_session_step_at_once_in_two_threads(source):
    # Each steps a world of its own: two sessions on one world raced here (hung or crashed).
    path = source / "scenarios" / "push_wall.toml"  # bodies moving, bonds breaking
    answer = subprocess.run([sys.executable, "-c", THREADS_ON_A_FORK, str(path)], capture_output=True, text=True,
                            timeout=120)
    assert answer.returncode == 0, answer.stderr
    assert answer.stdout.split() == ["True", "True"]
