"""numpy out (python/src/session_binding.cpp, matches.cpp): the neighbour graph as compressed rows,
matches as a structured array and a pandas DataFrame."""

import numpy as np
import pytest

import dwatch


def test_neighbours_are_compressed_rows_equal_to_state(source):
    s = dwatch.Session(source / "scenarios" / "leader_election.toml")
    s.step(3)
    indptr, indices = s.neighbours()
    assert indptr.dtype == indices.dtype == np.int64 and indptr.shape == (s.modules + 1,)
    assert indptr[0] == 0 and indptr[-1] == len(indices) and not indptr.flags.writeable
    for m in (0, 5, 119):
        assert list(indices[indptr[m] : indptr[m + 1]]) == s.state(m)["nbrs"]


def test_matches_as_records_and_pandas(source):
    s = dwatch.Session(source / "scenarios" / "leader_election.toml")
    s.run()
    found = s.matches("two_leaders")
    records = found.records()
    assert records.dtype.names == ("t", "detected", "a", "b", "c") and len(records) == len(found) > 0
    np.testing.assert_array_equal(records["t"], found.t)
    np.testing.assert_array_equal(records["c"], found.slots[:, 2])
    odd = dwatch.replay({"t": [0], "m": [0], "nbrs": [[]], "vars": {"x": [1]}}, "modules(t); t.x = 1")["w1"]
    assert odd.records().dtype.names == ("t", "detected", "slot_t")
    pandas = pytest.importorskip("pandas")
    frame = found.to_pandas()
    assert isinstance(frame, pandas.DataFrame) and list(frame.columns) == ["t", "detected", "a", "b", "c"]
