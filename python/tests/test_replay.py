"""dwatch.replay: python/src/replay_binding.cpp over sim/replay.h."""

import signal
import threading
import time

import numpy as np
import pytest

import dwatch
from conftest import LEADERS, dwatch as cli, json_lines, read_columns

CASES = ["02_leader_two_hop_hex", "01_fig6_2222_grid", "03_token_ring_last"]


def case(source, name):
    folder = source / "tests" / "conformance" / name
    return folder / "trace.jsonl", (folder / "watch.txt").read_text().strip()


def as_rows(matches: dwatch.Matches) -> list[tuple]:
    return [(int(t), tuple(int(i) for i in slots)) for t, slots in zip(matches.t, matches.slots)]


def cli_rows(trace, text, algorithm):
    out = cli("replay", str(trace), "--watch", "w1=" + text, "--algorithm", algorithm, "--matches", "-").stdout
    return [(row["t"], tuple(row["slots"].values())) for row in json_lines(out) if row["watch"] == "w1"]


@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("algorithm", ["distributed", "centralized"])
def test_replay_of_a_file_finds_what_dwatch_replay_finds(source, name, algorithm):
    trace, text = case(source, name)
    found = dwatch.replay(str(trace), text, algorithm=algorithm)
    assert list(found) == ["w1"]
    rows = as_rows(found["w1"])
    assert rows == cli_rows(trace, text, algorithm)
    assert len(rows) > 0


@pytest.mark.parametrize("name", CASES)
def test_columns_give_the_matches_of_the_file(source, name):
    trace, text = case(source, name)
    from_file = dwatch.replay(trace, {"x": text})["x"]
    columns = read_columns(trace)
    from_columns = dwatch.replay(columns, {"x": text})["x"]
    assert as_rows(from_columns) == as_rows(from_file)
    np.testing.assert_array_equal(from_columns.detected, from_file.detected)

    # The same lines in another order, and the neighbours as one list per line.
    order = np.random.default_rng(3).permutation(len(columns["t"]))
    begin, flat = columns["nbr_begin"], columns["nbrs"]
    shuffled = {
        "t": columns["t"][order],
        "m": columns["m"][order].astype(np.int32),  # converted to int64
        "nbrs": [list(flat[begin[i] : begin[i + 1]]) for i in order],
        "vars": {name: values[order] for name, values in columns["vars"].items()},
    }
    assert as_rows(dwatch.replay(shuffled, {"x": text})["x"]) == as_rows(from_file)


def test_matches_are_int64_arrays_of_the_documented_shapes(source):
    trace, text = case(source, "02_leader_two_hop_hex")
    m = dwatch.replay(trace, [text, "modules(a); a.isLeader = 1"])
    assert list(m) == ["w1", "w2"]
    leaders, single = m["w1"], m["w2"]
    assert leaders.slot_names == ["a", "b", "c"] and single.slot_names == ["a"]
    for found, k in ((leaders, 3), (single, 1)):
        n = len(found)
        assert n > 0
        assert found.t.dtype == found.detected.dtype == found.slots.dtype == np.int64
        assert found.t.shape == found.detected.shape == (n,)
        assert found.slots.shape == (n, k)
        assert np.all(found.detected >= found.t)
        assert np.all(np.diff(found.t) >= 0)
        assert not found.t.flags.writeable
    # Every module a single-slot match names is a leader there: read back from the trace's lines.
    columns = read_columns(trace)
    leader = {(t, m) for t, m, v in zip(columns["t"], columns["m"], columns["vars"]["isLeader"]) if v == 1}
    assert {(int(t), int(s[0])) for t, s in zip(single.t, single.slots)} == leader


def test_the_header_watchpoints_are_replayed_by_default(source, tmp_path):
    trace = tmp_path / "run.jsonl"
    cli("run", str(source / "scenarios" / "leader_election.toml"), "--record", str(trace), "--steps", "6")
    found = dwatch.replay(trace)
    assert list(found) == ["two_leaders"]
    expected = cli("replay", str(trace), "--matches", "-").stdout
    rows = [(r["t"], tuple(r["slots"].values())) for r in json_lines(expected) if r.get("watch") == "two_leaders"]
    assert as_rows(found["two_leaders"]) == rows and rows


def test_a_run_a_pause_stopped_replays_to_its_own_matches(source, tmp_path):
    # leader_election.toml pauses on two_leaders: the trace ends with {"paused":...}, and the
    # header's watchpoints leave the last steps undecided as the run did; given, they decide them.
    trace, live = tmp_path / "run.jsonl", tmp_path / "live.jsonl"
    cli("run", str(source / "scenarios" / "leader_election.toml"), "--record", str(trace), "--matches", str(live))
    assert '"paused"' in trace.read_text().splitlines()[-1]
    rows = [(r["t"], tuple(r["slots"].values())) for r in json_lines(live.read_text())]
    assert as_rows(dwatch.replay(trace)["two_leaders"]) == rows and rows
    text = "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)"
    assert len(dwatch.replay(trace, {"two_leaders": text})["two_leaders"]) >= len(rows)


def test_count_only_counts_every_match_and_keeps_none(source):
    trace, text = case(source, "01_fig6_2222_grid")
    kept = dwatch.replay(trace, text)["w1"]
    counted = dwatch.replay(trace, text, count_only=True)["w1"]
    assert kept.count == len(kept) > 0
    assert counted.count == kept.count and len(counted) == 0
    assert counted.slots.shape == (0, len(kept.slot_names)) and counted.t.dtype == np.int64
    assert "counted only" in repr(counted)


def test_bad_traces_raise_trace_error_in_the_readers_words(source, tmp_path):
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"t":0,"m":1,"vars":{},"nbrs":[]}\n{"t":0,"m":1,"vars":{},"nbrs":[]}\n')
    with pytest.raises(dwatch.TraceError) as raised:
        dwatch.replay(bad, LEADERS)
    assert str(raised.value) == f"{bad}:2:1: error: duplicate line for module 1 at step 0 (first at line 1)"
    assert str(raised.value) in cli("replay", str(bad), "--watch", LEADERS, check=False).stderr

    columns = {"t": [0, 0], "m": [1, 1], "nbrs": [[], []], "vars": {"isLeader": [0, 1]}}
    with pytest.raises(dwatch.TraceError, match=r"line 1 \(t=0, m=1\): duplicate line for module 1 at step 0"):
        dwatch.replay(columns, LEADERS)
    with pytest.raises(dwatch.TraceError, match="lists itself as a neighbour"):
        dwatch.replay({"t": [0], "m": [2], "nbrs": [[2]]}, LEADERS)
    with pytest.raises(dwatch.TraceError, match='lack "m"'):
        dwatch.replay({"t": [0], "nbrs": [[]]}, LEADERS)
    with pytest.raises(FileNotFoundError):
        dwatch.replay(tmp_path / "missing.jsonl", LEADERS)


def test_bad_readings_and_watchpoints_raise(source):
    trace, text = case(source, "02_leader_two_hop_hex")
    with pytest.raises(dwatch.Error, match="algorithm must be 'centralized' or 'distributed', not 'magic'"):
        dwatch.replay(trace, text, algorithm="magic")
    with pytest.raises(dwatch.Error, match="shape must be"):
        dwatch.replay(trace, text, shape="blob")
    with pytest.raises(dwatch.WatchError) as raised:
        dwatch.replay(trace, {"bad": "modules(a); a.x ="})
    assert raised.value.text.startswith("<watch bad>:1:")
    with pytest.warns(UserWarning, match="reads 'nothere', which no line of .* has: it can never match"):
        assert len(dwatch.replay(trace, "modules(a); a.nothere = 1")["w1"]) == 0


def test_the_budget_stops_a_replay_with_an_error(source):
    trace, text = case(source, "01_fig6_2222_grid")
    with pytest.raises(dwatch.Error, match="stopped: .*max_live= sets the budget"):
        dwatch.replay(trace, text, max_live=1)


def test_the_budget_keeps_what_every_watchpoint_found_as_the_command_line_does(source):
    trace, text = case(source, "01_fig6_2222_grid")
    single = "modules(a); a.x1 = 1"
    with pytest.raises(dwatch.BudgetError) as raised:
        dwatch.replay(trace, {"heavy": text, "single": single}, max_live=100)
    e = raised.value
    assert isinstance(e, dwatch.Error)
    assert list(e.matches) == ["heavy", "single"] and list(e.stopped) == ["heavy"]
    out = cli("replay", str(trace), "-w", "heavy=" + text, "-w", "single=" + single, "--max-live", "100",
              "--matches", "-", check=False)
    assert out.returncode == 1
    rows = json_lines(out.stdout)
    for name in ("heavy", "single"):
        expected = [(r["t"], tuple(r["slots"].values())) for r in rows if r.get("watch") == name]
        assert as_rows(e.matches[name]) == expected
    assert len(e.matches["single"]) > 0


def test_ctrl_c_stops_a_long_replay():
    # Two lines 10^7 steps apart, modules 0 and 99: 10^9 module-steps, mostly empty, seconds of work.
    columns = {"t": [0, 9_999_999], "m": [0, 99], "nbrs": [[], []], "vars": {"x": [1, 1]}}
    timer = threading.Timer(0.3, signal.raise_signal, args=(signal.SIGINT,))
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            dwatch.replay(columns, "modules(a); a.x = 2")
    finally:
        timer.cancel()
    assert time.monotonic() - started < 2


@pytest.mark.parametrize("algorithm", ["distributed", "centralized"])
def test_a_zero_slot_watchpoint_has_a_row_a_step_with_no_module(source, algorithm):
    # 'modules(); φ' decides the whole ensemble once a step (docs/language.md): each match is a row
    # with no module, as dwatch replay prints it; python counted ids / slots and found none.
    trace, _ = case(source, "03_token_ring_last")
    text = "modules(); count(n in all: n.token = 1) >= 1"
    found = dwatch.replay(str(trace), text, algorithm=algorithm)["w1"]
    rows = as_rows(found)
    assert rows == cli_rows(trace, text, algorithm)
    assert len(rows) > 0 and found.count == len(rows)
    assert found.slots.shape == (len(rows), 0)
