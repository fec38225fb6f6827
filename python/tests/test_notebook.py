"""A Session in a notebook (python/src/session_binding.cpp): Jupyter shows its current view."""

import struct

import dwatch


def test_a_session_shows_its_view_as_png(source):
    s = dwatch.Session(source / "scenarios" / "leader_election.toml")
    s.step(2)
    png = s._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", png[16:24]) == (640, 360)  # IHDR: width, height
