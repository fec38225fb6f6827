"""The examples of docs/python.md run as they are written."""

import re

import dwatch


def test_the_python_pages_example_runs(source, monkeypatch, capsys):
    page = (source / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert blocks
    monkeypatch.chdir(source)  # its paths are the repository's
    spaces: list[dict] = []
    for block in blocks:
        spaces.append({})
        exec(compile(block, "docs/python.md", "exec"), spaces[-1])
    assert len(spaces[0]["found"]["two_leaders"]) > 0
    assert spaces[1]["s"].current == 41  # Robot logic in Python: the duplicated token found
    assert "watchpoint w1 " in capsys.readouterr().out


def test_check_names_the_watchpoint_w1_as_the_command_line_does():
    assert dwatch.check("modules(a); a.x = 1").startswith("watchpoint w1 ")
