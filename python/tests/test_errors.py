"""Errors as Python users know them (python/src/errors.cpp): FileNotFoundError for a missing file,
ValueError for a bad argument, and every dwatch error with file, line and column."""

import pathlib

import pytest

import dwatch
from conftest import LEADERS


def test_a_missing_file_is_file_not_found(tmp_path):
    for call in (lambda p: dwatch.Session(p), lambda p: dwatch.replay(p, LEADERS)):
        with pytest.raises(FileNotFoundError) as raised:
            call(tmp_path / "missing.file")
        assert raised.value.filename == str(tmp_path / "missing.file")


def test_paths_are_accepted_everywhere(source, tmp_path):
    s = dwatch.Session(pathlib.Path(source) / "scenarios" / "leader_election.toml")
    s.step(2)
    s.record(tmp_path / "run.jsonl")
    s.save(tmp_path / "saved.toml")
    assert len(dwatch.replay(tmp_path / "run.jsonl", "modules(a); a.isLeader = 1")["w1"]) > 0
    assert dwatch.Session(tmp_path / "saved.toml").modules == s.modules


def test_a_bad_argument_is_a_value_error(source):
    leaders = source / "scenarios" / "leader_election.toml"
    with pytest.raises(ValueError, match="threads must be an integer from 1 to 256") as raised:
        dwatch.Session(leaders, threads=0)
    assert isinstance(raised.value, dwatch.Error)
    with pytest.raises(ValueError, match="algorithm must be"):
        dwatch.replay({"t": [0], "m": [0], "nbrs": [[]]}, LEADERS, algorithm="magic")
    with pytest.raises(ValueError, match="width and height"):
        dwatch.Session(leaders).render(2, 2)


def test_every_error_says_where(tmp_path, source):
    with pytest.raises(dwatch.WatchError) as watch:
        dwatch.check("modules(a b);(a.x = 1) and (b.y = ")
    assert (watch.value.file, watch.value.line, watch.value.column) == ("<watch w1>", 1, 35)
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"t":0,"m":1,"vars":{},"nbrs":[]}\n{"t":0,"m":1,"vars":{},"nbrs":[]}\n')
    with pytest.raises(dwatch.TraceError) as trace:
        dwatch.replay(bad, LEADERS)
    assert (trace.value.file, trace.value.line, trace.value.column) == (str(bad), 2, 1)
    scenario = tmp_path / "bad.toml"
    scenario.write_text("steps = -3\n")
    with pytest.raises(dwatch.ScenarioError) as loaded:
        dwatch.Session(scenario)
    assert loaded.value.file == str(scenario) and loaded.value.line == 1 and loaded.value.column >= 1
    s = dwatch.Session(source / "scenarios" / "leader_election.toml")
    with pytest.raises(dwatch.CommandError) as command:
        s.command("step x")
    assert command.value.file == "<command>" and command.value.line == 1 and command.value.column == 6
    with pytest.raises(dwatch.CommandError) as unknown:
        s.matches("nope")
    assert unknown.value.file is None and unknown.value.line is None
