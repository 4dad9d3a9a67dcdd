"""--split-still: one demonstration per stretch between rests, /tf publishing on."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("rosbags")

from bag_samples import session, tf_bag
from ndlfd import NdlfdWarning
from ndlfd._errors import ValidationError
from ndlfd.io import read_bag, read_demos
from ndlfd.io._motion import rest_pieces


def test_five_demonstrations_between_rests_while_tf_publishes(tmp_path):
    t, P, spans = session()
    assert t[-1] > 119.9  # a 2-minute recording
    bag = tf_bag(tmp_path / "session", t, P)
    (whole,) = read_bag(bag, frame="tool0")  # without: one demonstration
    assert whole.n_samples == t.size
    demos, maps = read_demos(bag, frame="tool0", split_still=2.5,
                             return_mappings=True)  # fmt: skip
    assert len(demos) == 5
    step = 0.02
    for d, m, (a, b) in zip(demos, maps, spans, strict=True):
        # where the piece starts in the session: its first pose, read exactly
        (i0,) = np.flatnonzero((P == d.get("position")[0]).all(axis=1))
        start = t[i0]
        stop = start + d.t[-1]
        # ... as its mapping says (stamps in whole nanoseconds)
        np.testing.assert_allclose(m.span, (start, stop), rtol=0, atol=2e-9)
        # the piece holds its motion (but for the slow first and last 10 %
        # of a minimum-jerk move) and none of the next one
        assert a - 3.0 <= start <= a + 0.1 * (b - a)
        assert b - 0.1 * (b - a) <= stop <= b + 3.0
        assert np.all(np.diff(d.t) > 0) and abs(np.median(np.diff(d.t)) - step) < 1e-9
    # rests (3 s, and about 1 s of the slow ends of each move) shorter than asked
    with pytest.warns(NdlfdWarning, match=r"session: no rest of at least 8 s found"):
        (one,) = read_bag(bag, frame="tool0", split_still=8.0)
    assert one.n_samples == t.size


def test_split_still_warns_for_very_many_pieces_and_checks_its_value(tmp_path):
    t, P, _ = session(n_demos=60, move=1.0, rest=1.0, hz=20)
    bag = tf_bag(tmp_path / "many", t, P)
    with pytest.warns(NdlfdWarning, match=r"many: 60 pieces between rests of at"):
        demos = read_bag(bag, frame="tool0", split_still=0.8)
    assert len(demos) == 60
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(read_bag(bag, frame="tool0", split_gap=0.5)) == 1
    with pytest.raises(ValidationError, match=r"split_still must be a number of"
                       r" seconds > 0; got -1"):  # fmt: skip
        read_bag(bag, frame="tool0", split_still=-1)


@settings(max_examples=60, deadline=None)
@given(
    seconds=st.floats(0.5, 3.0),
    moves=st.lists(st.tuples(st.floats(2.0, 5.0), st.floats(1.2, 2.0)), min_size=1,
                   max_size=6),
    noise=st.sampled_from([0.0, 1e-6]),
)  # fmt: skip
def test_rest_pieces_find_each_move_between_long_rests(seconds, moves, noise):
    """Moves at one speed (back and forth) between rests longer than asked."""
    hz = 50.0
    knots_t, knots_x, spans = [0.0], [0.0], []
    now, x = 1.3 * seconds, 0.0
    for k, (move, rest) in enumerate(moves):
        knots_t.append(now)
        knots_x.append(x)
        x += (1 if k % 2 == 0 else -1) * move * seconds  # speed 1 per second
        spans.append((now, now + move * seconds))
        now += move * seconds
        knots_t.append(now)
        knots_x.append(x)
        now += rest * seconds
    t = np.arange(0.0, now, 1 / hz)
    X = np.interp(t, knots_t, knots_x)[:, None]
    X += np.random.default_rng(0).normal(0, noise, X.shape)
    pieces = rest_pieces(t, X, seconds)
    assert len(pieces) == len(moves)
    # a resting sample's window (2h) may hold up to 5 % of motion: a rest's
    # edge is within h of the move's, or 0.1 h (and a sample) inside it
    h, dt = seconds / 4, 1 / hz
    for (a, b), (m0, m1) in zip(pieces, spans, strict=True):
        assert m0 - h - 2 * dt <= t[a] <= m0 + 0.1 * h + 2 * dt
        assert m1 - 0.1 * h - 2 * dt <= t[b - 1] <= m1 + h + 2 * dt
