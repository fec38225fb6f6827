"""Session.why and Session.why_match: the session's `why` (docs/session.md) as dicts, equal to what
`dwatch session` answers; the leader election's 1-hop bug shown by the narrow cone."""

import json

import pytest

import dwatch
from conftest import dwatch as run_dwatch
from conftest import session_answers


def test_why_is_the_sessions_answer_and_shows_the_one_hop_bug(leaders):
    s = dwatch.Session(leaders)
    s.run()
    narrow = s.why(7, "isLeader", 1, narrow=True)
    wide = s.why(7, "isLeader", depth=2)  # t: the current step (1)
    expected = session_answers(leaders, "run", "why 7 isLeader 1 --narrow", "why 7 isLeader 1 --depth 2")
    assert narrow == expected[1] and wide == expected[2]
    assert narrow["values"][0]["origin"] == {"step": 1, "writer": "program", "event": len(narrow["events"]) - 1}
    # 7 heard only its one-hop neighbours: no two-hop module sent it anything.
    assert sorted(m["from"] for m in narrow["messages"]) == [6, 8, 18, 19]
    assert {m["to"] for m in narrow["messages"]} == {7}
    assert wide["depth"] == 2 and not wide["narrow"]
    assert s.current == 1  # the cursor stays


def test_why_match_is_the_sessions_answer(leaders):
    s = dwatch.Session(leaders)
    s.run()
    answer = s.why_match("two_leaders", 0, narrow=True)
    assert answer == session_answers(leaders, "run", "why match two_leaders 0 --narrow")[1]
    assert answer["match"] == {"watch": "two_leaders", "t": 1, "slots": {"a": 7, "b": 6, "c": 17}}
    assert {e["module"] for e in answer["events"] if e.get("group")} == {6, 7, 17}
    with pytest.raises(dwatch.CommandError, match="no row 5000"):
        s.why_match("two_leaders", 5000)


def test_a_trace_recorded_with_messages_answers_as_why(leaders, tmp_path):
    s = dwatch.Session(leaders)
    s.run()
    path = tmp_path / "leaders.jsonl"
    assert s.record(path, messages=True)["messages"] is True
    assert s.current == 1  # the cursor stays
    lines = path.read_text().splitlines()
    assert '"recv":[{"from":' in lines[1 + 120 + 7]  # module 7 at step 1 read its neighbours
    from_trace = json.loads(run_dwatch("why", str(path), "7", "isLeader", "1", "--narrow").stdout)
    assert from_trace == {k: v for k, v in s.why(7, "isLeader", 1, narrow=True).items() if k not in ("cmd", "current", "latest")}
    s.record(path)
    assert '"recv"' not in path.read_text()
