"""The fit's two passes: serial, threads, processes, Dask; files and re-iterables."""

import numpy as np
import pytest

from learner_helpers import (
    Reiterable,
    assert_same_model,
    run_in,
    two_routes,
    waves,
)
from ndlfd import (
    ValidationError,
)
from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.metrics import dtw_distance


@pytest.mark.parametrize("where", ["threads", "processes", "dask"])
@pytest.mark.parametrize("max_templates", [200, 9])
def test_serial_and_parallel_fits_give_the_same_model(
    where, max_templates, request, monkeypatch
):
    demos = [Demonstration.from_arrays(t, position=P) for t, P in waves(40)]
    kw = dict(epsilon=0.02, n_time_bins=20, max_templates=max_templates,
              random_state=7)  # fmt: skip
    serial = KeypointHMM(**kw, n_jobs=1).fit(demos)
    params, fit, seen = run_in(where, request, monkeypatch)
    timing = np.linspace(0.0, 2.0, 150)
    assert_same_model(serial, KeypointHMM(**kw, **params).fit(demos, **fit), timing)
    lazy = Reiterable(waves(40))
    assert_same_model(serial, KeypointHMM(**kw, **params).fit(lazy, **fit), timing)
    # each pass ran where asked
    assert seen == ([] if where == "dask" else [f"_run_{where}"] * 4)
    assert serial.n_demos_ == 40
    if max_templates < 40:
        from ndlfd.learner._templates import template_mask

        want = np.flatnonzero(template_mask(40, max_templates, 7))
        np.testing.assert_array_equal(serial.template_indices_, want)
        assert len(serial.train_values_) == max_templates
    else:  # all are templates, in order: as before the statistics
        np.testing.assert_array_equal(serial.template_indices_, np.arange(40))


def test_more_demonstrations_than_templates(tmp_path):
    # two routes; few templates: the counts, centroids and conditioning use all
    # demonstrations, the blend only the templates; random_state picks them
    demos = two_routes(per_route=10)
    kw = dict(groups=("position",), epsilon=0.01, n_time_bins=30)
    full = KeypointHMM(**kw).fit(demos)
    few = KeypointHMM(**kw, max_templates=6, random_state=1).fit(demos)
    other = KeypointHMM(**kw, max_templates=6, random_state=2).fit(demos)
    assert few.template_indices_.size == 6
    assert not np.array_equal(few.template_indices_, other.template_indices_)
    for m in (few, other):
        for k in ("key_states", "key_bins", "keypoints", "first", "last",
                  "centroid_limbs", "centroid_counts"):  # fmt: skip
            np.testing.assert_array_equal(
                getattr(m.fit_stats_, k), getattr(full.fit_stats_, k), err_msg=k
            )
        np.testing.assert_array_equal(m.centroids_, full.centroids_)
        for j, u in zip(m.template_indices_, m.train_values_, strict=True):
            np.testing.assert_array_equal(u, full.train_values_[j])
    # conditioned on either start, the path follows that route (as with all)
    t = np.linspace(0.0, 2.0, 200)
    for sign in (1.0, -1.0):
        route = np.mean(
            [d.get("position") for d in demos if d.get("position")[0, 1] * sign > 0],
            axis=0,
        )
        P = few.generate(t, dense=True, start={"position": [0.0, sign]})
        assert dtw_distance(P.get("position"), route, normalize=True) < 0.03
    # saved and loaded: the same model, the same paths
    few.save(tmp_path / "few.ndlfd")
    again = KeypointHMM.load(tmp_path / "few.ndlfd")
    assert_same_model(few, again, t)
    assert again.get_params() == few.get_params()


def test_a_reiterable_is_read_twice_and_never_held_whole():
    lazy = Reiterable(waves(150))
    model = KeypointHMM(
        epsilon=0.02, n_time_bins=20, n_jobs=1, max_templates=10, random_state=3
    )
    model.fit(lazy)
    assert lazy.passes == 2
    assert lazy.most_alive < 80  # a chunk at a time (64), not all 150
    assert model.n_demos_ == 150 and len(model.train_values_) == 10
    listed = [Demonstration.from_arrays(t, position=P) for t, P in waves(150)]
    assert_same_model(model, KeypointHMM(**model.get_params()).fit(listed),
                       np.linspace(0, 2, 50))  # fmt: skip


def test_a_generator_is_refused_with_what_to_pass_instead():
    demos = (Demonstration.from_arrays(t, position=P) for t, P in waves(3))
    with pytest.raises(ValidationError, match=r"one-shot iterator.*re-iterable"):
        KeypointHMM().fit(demos)
    with pytest.raises(ValidationError, match=r"one-shot iterator"):
        KeypointHMM().fit(iter([]))
    with pytest.raises(ValidationError, match=r"single path.*\[path\]"):
        KeypointHMM().fit("demos.csv")
    with pytest.raises(ValidationError, match=r"Demonstration or a file path; got int"):
        t, P = waves(1)[0]
        KeypointHMM().fit([Demonstration.from_arrays(t, position=P), 3])


@pytest.mark.parametrize("where", ["serial", "threads", "processes", "dask"])
def test_a_corrupt_demonstration_is_named(where, request, monkeypatch):
    run, fit, _ = run_in(where, request, monkeypatch)
    lazy = Reiterable(waves(30), bad=17)
    model = KeypointHMM(epsilon=0.02, n_time_bins=20, **run)
    want = (
        r"^demos\[17\]: a demonstration lacks group\(s\) position, velocity;"
        r" it has force$"
    )
    with pytest.raises(ValidationError, match=want):
        model.fit(lazy, **fit)
    assert not hasattr(model, "model_")


@pytest.mark.parametrize("where", ["threads", "processes", "dask"])
def test_files_are_read_in_each_pass_and_a_bad_one_is_named(
    where, request, monkeypatch, tmp_path
):
    from ndlfd import DataFileError
    from ndlfd.io import write_csv

    demos = [Demonstration.from_arrays(t, position=P) for t, P in waves(12)]
    paths = []
    for i, d in enumerate(demos):
        write_csv(d, tmp_path / f"d{i:02d}.csv")
        paths.append(tmp_path / f"d{i:02d}.csv")
    params, fit, _ = run_in(where, request, monkeypatch)
    kw = dict(epsilon=0.02, n_time_bins=20, **params)
    from_files = KeypointHMM(**kw).fit(paths, **fit)
    from_demos = KeypointHMM(epsilon=0.02, n_time_bins=20, n_jobs=1).fit(demos)
    assert_same_model(from_files, from_demos, np.linspace(0, 2, 50))
    (tmp_path / "d07.csv").write_text("t,x,y\n0,1,2\n1,oops,3\n")
    with pytest.raises(DataFileError, match=r"^demos\[7\]: .*d07\.csv"):
        KeypointHMM(**kw).fit([str(p) for p in paths], **fit)


def test_batched_counting_and_the_prepared_cache_change_nothing(monkeypatch):
    import ndlfd.learner._passes as _passes
    import ndlfd.learner._segments as _segments

    demos = [Demonstration.from_arrays(t, position=P) for t, P in waves(40)]
    kw = dict(epsilon=0.02, n_time_bins=20, n_jobs=1)
    ref = KeypointHMM(**kw).fit(demos)
    monkeypatch.setattr(_segments, "_ESTIMATE_BATCH", 3)  # hmm.merge of 14 parts
    monkeypatch.setattr(_passes, "_CACHE_BYTES", 0)  # prepare again in pass 2
    assert_same_model(ref, KeypointHMM(**kw).fit(demos), np.linspace(0, 2, 50))


def test_a_long_first_demonstration_then_short_ones_on_two_workers():
    # pass 1 picks threads (by the first), pass 2 processes (by the mean): the
    # prepared cache of pass 1 stays local, and the model is the same
    long_t = np.linspace(0.0, 2.0, 6000)
    long_P = np.column_stack([np.sin(long_t), np.cos(long_t)])
    demos = [Demonstration.from_arrays(long_t, position=long_P)]
    demos += [Demonstration.from_arrays(t, position=P) for t, P in waves(12)]
    kw = dict(epsilon=0.02, n_time_bins=20)
    serial = KeypointHMM(**kw, n_jobs=1).fit(demos)
    assert_same_model(serial, KeypointHMM(**kw, n_jobs=2).fit(demos),
                       np.linspace(0.0, 2.0, 80))  # fmt: skip
