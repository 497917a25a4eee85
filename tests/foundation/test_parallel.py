"""The Dask backend runs joblib jobs on an in-process local cluster with the same results."""

from __future__ import annotations

import pytest
from joblib import Parallel, delayed

from gaitml.errors import ConfigError, InputError
from gaitml.parallel import parallel_backend


def _square(x):
    return x * x


def test_joblib_backend():
    with parallel_backend("joblib") as info:
        assert info["backend"] == "joblib"
        assert Parallel(n_jobs=2)(delayed(_square)(i) for i in range(5)) == [0, 1, 4, 9, 16]


def test_dask_backend_local_cluster():
    pytest.importorskip("distributed")
    with parallel_backend("dask") as info:
        assert info["backend"] == "dask" and info["scheduler"]
        assert Parallel(n_jobs=2)(delayed(_square)(i) for i in range(5)) == [0, 1, 4, 9, 16]


def test_backend_errors():
    with pytest.raises(ConfigError, match="unknown backend"):
        with parallel_backend("spark"):
            pass
    with pytest.raises(InputError, match="--scheduler needs --backend dask"):
        with parallel_backend("joblib", "tcp://x:1"):
            pass
