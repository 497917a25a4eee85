"""Where parallel work runs: joblib processes locally, or a Dask cluster.

Cross-validation folds and sweep points are independent jobs dispatched through
``joblib.Parallel``. :func:`parallel_backend` chooses where they run:

- ``"joblib"`` (default): local worker processes (``n_jobs``).
- ``"dask"``: the jobs go to a Dask cluster through joblib's Dask backend
  (needs the optional extra: ``pip install 'gaitml[dask]'``). With
  ``scheduler=None`` an in-process local cluster is started; with an address
  (``tcp://host:8786``) the existing cluster is used. Results are identical to
  the local run because every job is seeded by its own parameters.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

from gaitml.errors import ConfigError, InputError

__all__ = ["parallel_backend", "BACKENDS", "one_blas_thread"]

BACKENDS = ("joblib", "dask")


@contextlib.contextmanager
def parallel_backend(backend: str = "joblib", scheduler: str | None = None, *, n_workers: int = 2) -> Iterator[dict]:
    """Context in which ``joblib.Parallel`` runs on the chosen backend.

    Yields a dict describing the backend (``{"backend": ..., "scheduler": ...}``)
    for run reports.
    """
    import joblib

    if backend not in BACKENDS:
        raise ConfigError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}.")
    if backend == "joblib":
        if scheduler:
            raise InputError("--scheduler needs --backend dask; drop --scheduler or add --backend dask.")
        yield {"backend": "joblib"}
        return
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:
        raise ConfigError("--backend dask needs the optional extra: pip install 'gaitml[dask]'.") from exc
    cluster = None
    try:
        if scheduler:
            try:
                client = Client(scheduler, timeout="10s")
            except OSError as exc:
                raise InputError(f"cannot reach the Dask scheduler at {scheduler} ({exc}); check the address.") from exc
        else:
            cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=False, dashboard_address=None)
            client = Client(cluster)
        with client, joblib.parallel_config(backend="dask"):
            yield {"backend": "dask", "scheduler": client.scheduler.address if client.scheduler else scheduler}
    finally:
        if cluster is not None:
            cluster.close()


#: The BLAS libraries whose thread count :func:`one_blas_thread` limits (threadpoolctl controllers), found at its first call.
_BLAS_LIBS: list | None = None
_BLAS_LOCK = threading.Lock()
_BLAS_STATE = {"depth": 0, "saved": []}


@contextlib.contextmanager
def one_blas_thread():
    """Run the block with one BLAS thread (restored after; nested and concurrent uses restore once, at the last exit).

    For small matrix products such as the domain check's (:mod:`gaitml.models.domain`):
    a second BLAS thread saves little on an idle machine, and on a loaded one the
    product waits for a busy core while OpenBLAS's threads spin (the measurement is in
    ``experiments/reports/model-domain.md``, "The cost, third follow-up"). The first
    call finds the BLAS libraries through threadpoolctl (a dependency of
    scikit-learn); without threadpoolctl the block runs unchanged.
    """
    global _BLAS_LIBS
    if _BLAS_LIBS is None:
        try:
            from threadpoolctl import ThreadpoolController

            _BLAS_LIBS = [lib for lib in ThreadpoolController().lib_controllers if lib.user_api == "blas"]
        except ImportError:  # no threadpoolctl: leave the threads alone
            _BLAS_LIBS = []
    with _BLAS_LOCK:
        if _BLAS_STATE["depth"] == 0:
            _BLAS_STATE["saved"] = [lib.get_num_threads() for lib in _BLAS_LIBS]
            for lib in _BLAS_LIBS:
                lib.set_num_threads(1)
        _BLAS_STATE["depth"] += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _BLAS_STATE["depth"] -= 1
            if _BLAS_STATE["depth"] == 0:
                for lib, k in zip(_BLAS_LIBS, _BLAS_STATE["saved"], strict=True):
                    lib.set_num_threads(k)
