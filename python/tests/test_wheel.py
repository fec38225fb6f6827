"""The package as a user installs it (python/pyproject.toml, python/setup.py): a wheel built from the
build tree with no download, pip-installed into a fresh virtual environment, imported and run there,
outside the checkout; and the message an interpreter the package was not built for gets."""

import os
import pathlib
import re
import shutil
import subprocess
import sys
import textwrap

import pytest

import dwatch

from conftest import SOURCE

BUILD = pathlib.Path(os.environ.get("DWATCH_BUILD_DIR", SOURCE / "build")).resolve()
VERSION = re.search(r"project\(dwatch VERSION ([0-9.]+)", (SOURCE / "CMakeLists.txt").read_text()).group(1)

IN_THE_VENV = textwrap.dedent(
    """
    import importlib.metadata, pathlib, sys
    import numpy as np
    import dwatch
    assert pathlib.Path(dwatch.__file__).is_relative_to(sys.prefix), (dwatch.__file__, sys.prefix)
    print("version", importlib.metadata.version("dwatch"), dwatch.__version__)
    found = dwatch.replay(LINE, "modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)", algorithm="centralized")
    print("matches", found["w1"].t.tolist(), found["w1"].slots.tolist())
    with dwatch.Session(dwatch.scenario_path("leader_election.toml")) as s:
        print("paused", s.run()["paused"]["watch"])
    print("scenarios", len(dwatch.scenarios()))
    """
)


# A line of 4 modules over 2 steps, two leaders a hop apart at step 1 (docs/python.md's example).
LINE = """{"t": np.array([0, 0, 0, 0, 1, 1, 1, 1]), "m": np.array([0, 1, 2, 3, 0, 1, 2, 3]),
        "nbrs": [[1], [0, 2], [1, 3], [2]] * 2, "vars": {"isLeader": np.array([0, 0, 0, 1, 1, 0, 1, 0])}}"""
IN_THE_VENV = IN_THE_VENV.replace("LINE", LINE)


def run(*args, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=120, **kwargs)


@pytest.mark.skipif(shutil.which("cmake") is None, reason="needs cmake")
def test_a_wheel_from_the_build_tree_installs_into_a_fresh_venv_and_runs_there(tmp_path):
    if not (BUILD / "python" / "dwatch").is_dir():
        pytest.skip(f"no build tree at {BUILD} (DWATCH_BUILD_DIR)")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # the venv's dwatch, not build/python
    built = run(sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", tmp_path / "dist",
                SOURCE / "python", env={**env, "DWATCH_BUILD_DIR": str(BUILD)})
    assert built.returncode == 0, built.stdout + built.stderr
    wheels = list((tmp_path / "dist").glob("*.whl"))
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    assert [w.name for w in wheels] == [f"dwatch-{VERSION}-{tag}-{tag}-linux_{os.uname().machine}.whl"]

    venv = tmp_path / "venv"
    made = run(sys.executable, "-m", "venv", "--system-site-packages", venv)  # numpy from Debian's
    assert made.returncode == 0, made.stderr
    installed = run(venv / "bin" / "pip", "install", "--no-index", "--no-cache-dir", wheels[0], env=env)
    assert installed.returncode == 0, installed.stdout + installed.stderr
    answer = run(venv / "bin" / "python", "-c", IN_THE_VENV, cwd=tmp_path, env=env)  # away from the checkout
    assert answer.returncode == 0, answer.stderr
    assert answer.stdout.splitlines() == [
        f"version {VERSION} {VERSION}",
        "matches [1, 1] [[0, 1, 2], [2, 1, 0]]",
        "paused two_leaders",
        f"scenarios {len(dwatch.scenarios())}",
    ]


def test_another_interpreter_is_told_which_one_the_package_was_built_for():
    message = dwatch._interpreter_problem((3, 99), "/opt/python3.99/bin/python3")
    built_for = dwatch._build_info.PYTHON_VERSION
    assert message.startswith(f"dwatch {VERSION} was built for Python {built_for[0]}.{built_for[1]} (")
    assert "this is Python 3.99 (/opt/python3.99/bin/python3)" in message
    assert dwatch._interpreter_problem(sys.version_info, sys.executable) == ""
    assert "PyPy" in dwatch._interpreter_problem(sys.version_info, "/usr/bin/pypy3", "PyPy")


def test_another_python_importing_the_build_tree_gets_that_message():
    built_for = dwatch._build_info.PYTHON_VERSION
    others = [shutil.which(f"python3.{minor}") for minor in (built_for[1] + 1, built_for[1] - 1)]
    other = next((o for o in others if o and run(o, "-c", "pass").returncode == 0), None)
    if other is None:
        pytest.skip("no other Python 3 here")
    package_parent = pathlib.Path(dwatch.__file__).resolve().parents[1]
    answer = run(other, "-c", "import dwatch", env={**os.environ, "PYTHONPATH": str(package_parent)})
    assert answer.returncode != 0
    assert f"dwatch {VERSION} was built for Python {built_for[0]}.{built_for[1]} (" in answer.stderr


def test_the_version_answers_from_the_build_tree_too():
    import importlib.metadata

    assert importlib.metadata.version("dwatch") == dwatch.__version__ == VERSION


def test_a_shipped_scenario_is_found_by_its_name():
    path = dwatch.scenario_path("leader_election.toml")
    assert path.read_text() == (SOURCE / "scenarios" / "leader_election.toml").read_text()
    assert "lua/gradient.toml" in dwatch.scenarios() and "table1.toml" in dwatch.scenarios()
    with pytest.raises(FileNotFoundError, match="no shipped scenario is named 'nope.toml'; there are: "):
        dwatch.scenario_path("nope.toml")
    with pytest.raises(ValueError):
        dwatch.scenario_path("../CMakeLists.txt")
