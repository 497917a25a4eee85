"""The training domain of a model, and whether a new window lies inside it.

A classifier has no "unknown" class: a window unlike anything it was trained on (a
phone in a pocket for a model trained on hand-held phones, a foot-mounted IMU, a
recording in g read as m/s^2) still gets one of its modes, often confidently. The
domain check lets ``gaitml predict`` and ``gaitml pdr`` say so, window by window.

:class:`DomainCheck` is the estimator (``fit(X, y, groups)``, ``check_windows``,
``get_params``); its fitted :class:`DomainModel` is what a saved model stores
(``model.json`` key ``domain``; the arrays in ``arrays.npz`` under names starting
``domain__``, read with ``allow_pickle=False``). Three tests, each with a threshold at
the ``quantile`` (default :data:`DEFAULT_QUANTILE`) of distances of training windows
*held out* by folds over the training groups (:mod:`._fit`):

- **feature distance** (:mod:`._distance`): the features standardised with the
  training mean and standard deviation; one Gaussian per training class (class mean and
  a Ledoit-Wolf shrunk covariance, invertible with many correlated features); a
  window's distance is its smallest Mahalanobis distance to the classes: small when it
  looks like *some* trained mode.
- **gravity direction** (phone-frame models only, :mod:`._gravity`): the angle of the
  window's mean acceleration direction to the nearest of up to
  :data:`MAX_GRAVITY_DIRECTIONS` training directions (the distribution may have several
  modes: flat and tilted phones). A gravity-frame model's features do not depend on the
  phone's orientation, so its gravity direction is recorded but not checked.
- **orientation dynamics** (models with the gyroscope, :mod:`._descriptors`): 13
  descriptors of how the phone moves and turns, independent of how it is held
  (:func:`orientation_dynamics`); one Ledoit-Wolf Gaussian per (mode, position). A
  carrying position is a property of a stretch of recording, so the decision uses the
  median over the last :data:`DYNAMICS_SPAN` windows of the distances of every
  :data:`DYNAMICS_EVERY`-th window (causal, so a stream can do the same;
  :func:`span_medians`, :mod:`._running`); the threshold is fitted on the same grid.
  Records written before the grid (no ``every``) are checked on every window; older
  records have no dynamics part and check as before.

A window is **in domain** when it passes every test its record holds. By construction
about ``1 - quantile`` of new windows from the training distribution fall outside each
test; ``experiments/reports/model-domain.md`` measures the check on new simulated
subjects, left-out carrying positions and real recordings.

This is ours (the papers have no domain check); it detects *that* a window is unlike the
training data, not *why*.
"""

from gaitml.models.domain._descriptors import DYNAMICS_CHUNK_S, DYNAMICS_NAMES, DYNAMICS_RATE_HZ, dynamics_sample_step, orientation_dynamics
from gaitml.models.domain._distance import RIDGE_UNITS, _class_gaussians, _min_mahalanobis, _standardiser
from gaitml.models.domain._fit import DEFAULT_QUANTILE, HELDOUT_FOLDS, DomainCheck, fit_domain
from gaitml.models.domain._gravity import ACC_MEAN_FEATURES, MAX_GRAVITY_DIRECTIONS, feature_gravity, span_gravity, window_gravity
from gaitml.models.domain._record import (
    _BLOCKED_MIN_ROWS,
    ARRAY_PREFIX,
    DOMAIN_VERSION,
    RATE_TOLERANCE,
    ChunkContext,
    DomainModel,
    domain_from_model_info,
    domain_rate_reason,
    out_of_domain_fraction,
)
from gaitml.models.domain._running import DYNAMICS_EVERY, DYNAMICS_SPAN, dynamics_grid_step, running_median, span_medians
from gaitml.parallel import one_blas_thread

__all__ = [
    "ACC_MEAN_FEATURES",
    "ARRAY_PREFIX",
    "DEFAULT_QUANTILE",
    "DOMAIN_VERSION",
    "DYNAMICS_CHUNK_S",
    "DYNAMICS_EVERY",
    "DYNAMICS_NAMES",
    "DYNAMICS_RATE_HZ",
    "DYNAMICS_SPAN",
    "HELDOUT_FOLDS",
    "MAX_GRAVITY_DIRECTIONS",
    "RATE_TOLERANCE",
    "RIDGE_UNITS",
    "ChunkContext",
    "DomainCheck",
    "DomainModel",
    "domain_from_model_info",
    "domain_rate_reason",
    "dynamics_grid_step",
    "dynamics_sample_step",
    "feature_gravity",
    "fit_domain",
    "one_blas_thread",
    "orientation_dynamics",
    "out_of_domain_fraction",
    "running_median",
    "span_gravity",
    "span_medians",
    "window_gravity",
    # the private helpers below are imported by the lab (experiments/scripts/lopo_domain.py) and tests
    "_BLOCKED_MIN_ROWS",
    "_class_gaussians",
    "_min_mahalanobis",
    "_standardiser",
]
