"""Fixtures of the learner tests."""

import pytest

from ndlfd import (
    synth,
)


@pytest.fixture(scope="module")
def square():
    return synth.make_dataset("square", n_demos=30, random_state=3)


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=2,
            processes=False,
            threads_per_worker=1,
            dashboard_address=":0",
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client
