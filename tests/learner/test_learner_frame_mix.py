"""The frames' step in generation (learner/_frame_mix.py): its statistics.

The views' weights and the slopes do not depend on where a frame without an
orientation moved to, so they are computed once at the templates' mean pose
and kept for every new pose: checked against computing them at each new pose
(the direct reference, equal up to rounding), and the path for a pose does
not depend on which poses came before it (a warm cache or a fresh model).
"""

import numpy as np
import pytest

import ndlfd.learner._frame_mix as frame_mix
from hands_data import object_pose, planar_arm, planar_target, two_hands
from ndlfd import KeypointHMM


def _values(path):
    return np.column_stack([path.get(g) for g in path.group_names])


def _two_hands():
    demos, _ = two_hands(12, seed=4)
    rng = np.random.default_rng(7)
    return demos, [{"object": object_pose(rng)[0]} for _ in range(3)]


def _arm():
    demos, _ = planar_arm(20, seed=3)
    rng = np.random.default_rng(8)
    return demos, [{"target": planar_target(rng)} for _ in range(3)]


CASES = {"two hands": _two_hands, "joint space": _arm}


@pytest.mark.parametrize("case", CASES)
def test_the_statistics_are_those_at_the_new_pose(case, monkeypatch):
    """Computed at the templates' mean pose, or at each new pose: one path."""
    demos, poses = CASES[case]()
    t = demos[0].t
    kept = KeypointHMM(random_state=0).fit(demos)
    paths = [_values(kept.generate(t, dense=True, frames=f)) for f in poses]
    # the reference: a fresh model per pose, its statistics at that pose
    monkeypatch.setattr(frame_mix, "_canonical", lambda est, demos, frames: frames)
    for f, got in zip(poses, paths, strict=True):
        direct = KeypointHMM(random_state=0).fit(demos)
        want = _values(direct.generate(t, dense=True, frames=f))
        span = np.ptp(want, axis=0).max()
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * span)


@pytest.mark.parametrize("case", CASES)
def test_a_path_does_not_depend_on_the_poses_before_it(case):
    demos, poses = CASES[case]()
    t = demos[0].t
    warm = KeypointHMM(random_state=0).fit(demos)
    for f in poses:
        last = _values(warm.generate(t, dense=True, frames=f))
    fresh = KeypointHMM(random_state=0).fit(demos)
    np.testing.assert_array_equal(
        last, _values(fresh.generate(t, dense=True, frames=poses[-1]))
    )
