"""A Session's life (python/src/session_binding.cpp): `with`, close()."""

import pytest

import dwatch


def test_with_closes_the_session_and_later_calls_raise(source):
    with dwatch.Session(source / "scenarios" / "leader_election.toml") as s:
        s.step(2)
        assert s.current == 1
    for call in (lambda: s.step(), lambda: s.current, lambda: s.values("isLeader"), lambda: s.matches("two_leaders")):
        with pytest.raises(dwatch.Error, match="this Session is closed"):
            call()
    s.close()  # twice: nothing


def test_close_frees_and_an_exception_in_the_block_passes_through(source):
    with pytest.raises(KeyError):
        with dwatch.Session(source / "scenarios" / "leader_election.toml") as s:
            raise KeyError("mine")
    with pytest.raises(dwatch.Error, match="closed"):
        s.step()
