"""Input checks shared by the estimators: scikit-learn's ``validate_data`` with gaitml's errors.

scikit-learn's checks (``validate_data``, ``check_classification_targets``) raise
``ValueError``; here they are re-raised as :class:`~gaitml.errors.InputError`
(a ``ValueError`` subclass, so scikit-learn's own estimator checks still see a
``ValueError``) on one line, with the original message kept (the estimator
checks match parts of it, e.g. ``"Reshape your data"``) and the fix appended.
The classes and the standardisation every classifier fits first live here too.
"""

from __future__ import annotations

import numpy as np
from sklearn.utils.multiclass import check_classification_targets
from sklearn.utils.random import check_random_state
from sklearn.utils.validation import validate_data

from gaitml.errors import GaitmlError, InputError

__all__ = ["validate_fit", "validate_predict", "set_classes", "standardisation", "seed_from", "FIX"]

#: The fix appended to a scikit-learn input error.
FIX = "pass a finite numeric array of shape (windows, features) (raw windows: (windows, samples, channels))"


def _one_line(exc: Exception, fix: str = FIX) -> InputError:
    msg = " ".join(str(exc).split()).rstrip(".")
    return InputError(f"{msg}; {fix}.")


def validate_fit(estimator, X, y, *, allow_nd: bool = False, ensure_min_features: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Check ``X`` and ``y`` for ``fit`` and set ``n_features_in_`` (and ``feature_names_in_``).

    ``X`` becomes a float64 array (2-D, or n-D with ``allow_nd``), finite; ``y`` a
    1-D array of class labels of their own type (never cast to str), one per row.

    Raises
    ------
    InputError
        Bad shape, NaN/inf, non-numeric values, mismatched lengths, a continuous
        or multi-output target (scikit-learn's message kept, the fix appended).
    """
    try:
        X, y = validate_data(estimator, X, y, dtype=np.float64, allow_nd=allow_nd, ensure_min_features=ensure_min_features)
        check_classification_targets(y)
    except GaitmlError:
        raise
    except ValueError as exc:
        raise _one_line(exc, f"{FIX}, and one class label per row") from exc
    return X, y


def validate_predict(estimator, X, *, allow_nd: bool = False) -> np.ndarray:
    """Check ``X`` for ``predict`` against what ``fit`` saw (number of features, names).

    A C-ordered float64 ndarray of the fitted width, all finite, fitted without
    feature names, is returned as is without calling ``validate_data``: the result
    is the same and the one-window streaming path skips its cost (``gaitml bench``,
    ``models / stream-predict-per-window``). Anything else goes through
    ``validate_data(reset=False)``.
    """
    n = getattr(estimator, "n_features_in_", None)
    if (
        type(X) is np.ndarray
        and X.dtype == np.float64
        and X.ndim == 2
        and X.shape[1] == n
        and X.shape[0] > 0
        and not hasattr(estimator, "feature_names_in_")
        and np.isfinite(X).all()
    ):
        return X
    try:
        return validate_data(estimator, X, reset=False, dtype=np.float64, allow_nd=allow_nd)
    except GaitmlError:
        raise
    except ValueError as exc:
        raise _one_line(exc, f"{FIX}; use the feature set and window the model was trained on") from exc


def set_classes(estimator, y: np.ndarray) -> np.ndarray:
    """Set ``classes_`` (the sorted labels of validated ``y``) and return each row's index into it.

    Raises
    ------
    InputError
        Fewer than 2 classes (``classes_`` is set all the same).
    """
    estimator.classes_, codes = np.unique(y, return_inverse=True)
    classes = estimator.classes_
    if len(classes) < 2:
        raise InputError(
            f"need at least 2 classes to train a classifier, got {len(classes)} class ({', '.join(map(str, classes)) or 'none'}); check the labels of the training data."
        )
    return codes


def standardisation(X: np.ndarray, axis=0) -> tuple[np.ndarray, np.ndarray]:
    """Mean and scale of ``X`` over ``axis``: the std, with 1 for a constant column (left at 0 after centring)."""
    mean = X.mean(axis=axis)
    scale = X.std(axis=axis)
    scale[scale == 0] = 1.0
    return mean, scale


def seed_from(random_state) -> int:
    """An int seed from ``random_state`` (int, RandomState or None), scikit-learn style.

    An int is used as is (so int seeds give the same results as before); ``None``
    and a ``RandomState`` draw one seed from :func:`sklearn.utils.check_random_state`.
    """
    if isinstance(random_state, int | np.integer) and not isinstance(random_state, bool):
        return int(random_state)
    try:
        rng = check_random_state(random_state)
    except ValueError as exc:
        raise InputError(f"`random_state` must be an int, a numpy RandomState or None, got {random_state!r}.") from exc
    return int(rng.randint(np.iinfo(np.int32).max))
