"""A written path keeps the input's names, order and time column (io/_output.py)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.demonstration import Demonstration, with_velocity
from ndlfd.io import (
    ColumnMapping,
    csv_columns,
    read_demos,
    read_table,
    write_csv,
    write_table,
)

#: Column names the naming convention maps, with the motor names of LeRobot.
_NAMES = ["x", "y", "z", "vx", "vy", "fx", "gripper", "grip.w", "a.pos", "b.pos",
          "a.vel", "b.effort"]  # fmt: skip
_TIMES = ["t", "time", "timestamp", "Time"]


@settings(max_examples=40, deadline=None)
@given(
    names=st.lists(st.sampled_from(_NAMES), min_size=1, max_size=8, unique=True),
    time=st.sampled_from(_TIMES),
    where=st.integers(0, 8),
    seed=st.integers(0, 2**16),
)
def test_csv_in_csv_out_keeps_names_order_and_time(tmp_path_factory, names, time,
                                                   where, seed):  # fmt: skip
    tmp = tmp_path_factory.mktemp("io")
    rng = np.random.default_rng(seed)
    n = 6
    header = list(names)
    header.insert(min(where, len(header)), time)  # the time column anywhere
    data = rng.normal(size=(n, len(header)))
    data[:, header.index(time)] = np.arange(n) * 0.25
    write_table(tmp / "in.csv", header, data)
    (demo,), (m,) = read_demos(tmp / "in.csv", return_mappings=True)
    out = write_csv(demo, tmp / "out.csv", mapping=m)
    got_header, got = read_table(out)
    # the reference: the input's value columns in the input's order, time first
    want = [time] + [h for h in header if h != time]
    assert got_header == want
    for j, h in enumerate(want):
        np.testing.assert_array_equal(got[:, j], data[:, header.index(h)])
    assert m.order == tuple(h for h in header if h != time)


def test_columns_the_input_lacks_follow_in_the_model_order(tmp_path):
    rows = np.column_stack([[0, 0, 1.0], [0, 1, 2.0], [1, 2, 3.0], [3, 2, 1.0]])
    write_table(tmp_path / "a.csv", ["gripper", "t", "y", "x"], rows)
    (demo,), (m,) = read_demos(tmp_path / "a.csv", return_mappings=True)
    d = with_velocity(demo)  # x, y, gripper, vx, vy: vx, vy not in the file
    header, index = csv_columns(d, "t", m)
    assert header == ["t", "gripper", "y", "x", "vx", "vy"]
    assert [d.columns[j] for j in index] == ["gripper", "y", "x", "vx", "vy"]
    # no mapping: the model's names and order
    header, index = csv_columns(d)
    assert header == ["t", *d.columns] and index.tolist() == list(range(d.n_dims))


@pytest.mark.parametrize("layout", ["arrays", "ndlfd"])
def test_mappings_without_file_names_keep_the_model_names(tmp_path, layout):

    d = Demonstration.from_arrays([0.0, 1.0], position=[[0, 1], [2, 3]])
    m = ColumnMapping("a.npz", "t", (("position", ("pos",)),), layout=layout,
                      order=("pos",))  # fmt: skip
    assert csv_columns(d, "t", m)[0] == ["t", "x", "y"]
