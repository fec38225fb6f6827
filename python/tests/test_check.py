"""dwatch.check: python/src/errors.cpp."""

import pytest

import dwatch
from conftest import LEADERS, dwatch as cli


def test_check_explains_as_the_command_line_does():
    explained = dwatch.check(LEADERS, name="leaders")
    assert "slots          3: a b c" in explained
    printed = cli("check", "leaders=" + LEADERS).stdout
    # The same explanation; only the source's name differs ("<watch leaders>" / "<watch 1>").
    assert explained.replace("<watch leaders>", "<watch 1>") == printed


def test_a_mistake_raises_watch_error_with_its_place_and_caret():
    text = "modules(a b);(a.x = 1) and (b.y = "
    with pytest.raises(dwatch.WatchError) as raised:
        dwatch.check(text)
    e = raised.value
    assert isinstance(e, ValueError) and isinstance(e, dwatch.Error)
    assert (e.line, e.column) == (1, 35)
    assert e.message.startswith("expected a number, a state variable or an expression after '='")
    # The caret sits under column 35 of the source line, as the command line prints it.
    lines = e.text.splitlines()
    assert lines[1] == text and lines[2].index("^") == 34
    printed = cli("check", text, check=False)
    assert printed.returncode == 2
    assert e.message in printed.stderr


def test_an_empty_watchpoint_is_a_watch_error_not_a_crash():
    with pytest.raises(dwatch.WatchError):
        dwatch.check("")
