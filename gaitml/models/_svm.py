"""Linear one-vs-one SVM on standardised features (paper 003, sec. 3.1 and 3.3).

The paper classifies the five motion modes with a linear-kernel SVM, trained one
pair of classes at a time (OVO: m (m - 1) / 2 binary machines, majority vote),
on its time-domain features, with a penalty factor (called M in eq. 5, C here).

Implementation choice (measured, see ``benchmarks/models.py``): each pairwise
machine is a :class:`sklearn.svm.LinearSVC` (liblinear) solved in the primal
(``dual=False``), which is linear in the number of windows; libsvm's
``SVC(kernel='linear')`` (also one-vs-one) grows faster than linearly (on
simulated 52-feature windows, 2-core machine: 1.6 s vs 0.55 s at 20,000
windows, 35 s vs 5.6 s at 100,000). ``solver='libsvm'`` keeps
that path selectable as the reference. liblinear's primal solver needs the
squared hinge loss; the paper's eq. (5) is the plain hinge. Both give a maximum
margin linear separator with penalty C; ``loss='hinge'`` (dual solver) is
available for a literal reading.

After fitting, the standardisation is folded into the pairwise weights so that
prediction is one matrix product plus a vote: about 30 microseconds for one
window (input checks included), which is what the streaming path needs.
"""

from __future__ import annotations

import warnings
from itertools import combinations

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils.validation import check_is_fitted

from gaitml.errors import InputError

__all__ = ["LinearOVOSVM", "ovo_vote"]

#: Penalty factor default (paper 003 eq. 5 calls it M; its value is not given).
DEFAULT_C = 1.0


def ovo_vote(decision: np.ndarray, pairs: np.ndarray, n_classes: int) -> np.ndarray:
    """Turn pairwise decision values into class indices by one-vs-one voting.

    Parameters
    ----------
    decision : ndarray, shape (n, n_pairs)
        Decision value of machine k (positive means ``pairs[k, 0]`` wins).
    pairs : ndarray of int, shape (n_pairs, 2)
        Class indices (i, j) of every machine, i < j.
    n_classes : int

    Returns
    -------
    ndarray of int, shape (n,)
        The class with the most votes; ties go to the class with the larger sum
        of squashed confidences (the rule of :class:`sklearn.multiclass.OneVsOneClassifier`),
        then to the lower index.
    """
    first, second = _vote_matrices(pairs, n_classes)
    return _vote(decision, first, second)


def _vote_matrices(pairs, n_classes: int) -> tuple[np.ndarray, np.ndarray]:
    """One-hot (n_pairs, n_classes) matrices of the first and second class of every machine."""
    pairs = np.asarray(pairs)
    first = np.zeros((len(pairs), n_classes))
    second = np.zeros((len(pairs), n_classes))
    first[np.arange(len(pairs)), pairs[:, 0]] = 1.0
    second[np.arange(len(pairs)), pairs[:, 1]] = 1.0
    return first, second


def _vote(decision: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    win_i = (decision > 0).astype(float)
    votes = win_i @ first + (1.0 - win_i) @ second
    conf = decision @ (first - second)
    # squash the confidence sums into (-1/3, 1/3) so they only break ties
    conf = conf / (3 * (np.abs(conf) + 1))
    return np.argmax(votes + conf, axis=1)


class LinearOVOSVM(ClassifierMixin, BaseEstimator):
    """Standardised features + linear SVM, one-vs-one (paper 003, sec. 3.1).

    Parameters
    ----------
    C : float, default 1.0
        Penalty factor (paper 003 eq. 5, "M").
    solver : {'liblinear', 'libsvm'}, default 'liblinear'
        'liblinear': one :class:`~sklearn.svm.LinearSVC` per class pair (fast).
        'libsvm': :class:`~sklearn.svm.SVC` with ``kernel='linear'`` (native OVO;
        slow on large sets, kept as the reference).
    loss : {'squared_hinge', 'hinge'}, default 'squared_hinge'
        liblinear loss; 'squared_hinge' is solved in the primal (fast), 'hinge'
        (the paper's eq. 5) in the dual.
    max_iter : int, default 2000
    tol : float, default 1e-4
    random_state : int, default 0
        Seed of liblinear's / libsvm's internal shuffling (determinism).

    Attributes
    ----------
    classes_ : ndarray of str
    mean_, scale_ : ndarray, shape (n_features,)
        The standardisation learned on the training windows.
    pairs_ : ndarray of int, shape (n_pairs, 2)
    coef_ : ndarray, shape (n_pairs, n_features)
        Pairwise weights on the raw (unstandardised) features.
    intercept_ : ndarray, shape (n_pairs,)
    n_features_in_ : int
    """

    input_kind = "features"

    def __init__(
        self,
        C: float = DEFAULT_C,
        *,
        solver: str = "liblinear",
        loss: str = "squared_hinge",
        max_iter: int = 2000,
        tol: float = 1e-4,
        random_state: int = 0,
    ):
        self.C = C
        self.solver = solver
        self.loss = loss
        self.max_iter = max_iter
        self.tol = tol
        self.random_state = random_state

    def _check_params(self) -> None:
        if not (isinstance(self.C, int | float) and np.isfinite(self.C) and self.C > 0):
            raise InputError(f"`C` must be a positive number, got {self.C!r}; e.g. C = 1.0.")
        if self.solver not in ("liblinear", "libsvm"):
            raise InputError(f"`solver` must be 'liblinear' or 'libsvm', got {self.solver!r}.")
        if self.loss not in ("squared_hinge", "hinge"):
            raise InputError(f"`loss` must be 'squared_hinge' or 'hinge', got {self.loss!r}.")

    def fit(self, X, y) -> LinearOVOSVM:
        """Fit the standardisation and the m (m - 1) / 2 pairwise linear machines.

        Parameters
        ----------
        X : array-like, shape (n, n_features)
        y : array-like of str, shape (n,)
        """
        from sklearn.svm import SVC, LinearSVC

        self._check_params()
        X = _as_features(X)
        y = np.asarray(y).astype(str)
        if len(y) != len(X):
            raise InputError(f"X has {len(X)} rows but y has {len(y)} labels; they must match.")
        self.classes_ = np.unique(y)
        if len(self.classes_) < 2:
            raise InputError(
                f"need at least 2 classes to train a classifier, got {', '.join(map(str, self.classes_)) or 'none'}; check the labels of the training data."
            )
        self.n_features_in_ = X.shape[1]
        self.mean_ = X.mean(axis=0)
        scale = X.std(axis=0)
        scale[scale == 0] = 1.0  # constant feature: leave it at 0 after centring
        self.scale_ = scale
        Z = (X - self.mean_) / self.scale_
        codes = np.searchsorted(self.classes_, y)
        pairs = np.array(list(combinations(range(len(self.classes_)), 2)), dtype=int)
        coef = np.zeros((len(pairs), X.shape[1]))
        intercept = np.zeros(len(pairs))
        self.n_iter_ = np.zeros(len(pairs), dtype=int)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConvergenceWarning)
            for k, (i, j) in enumerate(pairs):
                mask = (codes == i) | (codes == j)
                yk = np.where(codes[mask] == i, 1, -1)
                if self.solver == "libsvm":
                    clf = SVC(kernel="linear", C=self.C, tol=self.tol * 10, max_iter=-1, random_state=self.random_state)
                else:
                    clf = LinearSVC(
                        C=self.C,
                        loss=self.loss,
                        dual=self.loss == "hinge",
                        tol=self.tol,
                        max_iter=self.max_iter,
                        random_state=self.random_state,
                    )
                clf.fit(Z[mask], yk)
                # class order of clf is [-1, 1], so a positive decision means class i
                coef[k] = np.ravel(clf.coef_)
                intercept[k] = float(np.ravel(clf.intercept_)[0])
                self.n_iter_[k] = int(np.max(getattr(clf, "n_iter_", 0)))
        self.converged_ = not any(issubclass(w.category, ConvergenceWarning) for w in caught)
        # fold the standardisation in: w.(x - m)/s + b = (w/s).x + (b - w.(m/s))
        self.coef_ = coef / self.scale_
        self.intercept_ = intercept - coef @ (self.mean_ / self.scale_)
        self.pairs_ = pairs
        self.vote_matrices_ = _vote_matrices(pairs, len(self.classes_))
        return self

    def decision_function(self, X) -> np.ndarray:
        """Pairwise decision values, shape (n, n_pairs) (positive: first class of the pair)."""
        if not hasattr(self, "coef_"):  # cheaper than check_is_fitted on the one-window streaming path
            check_is_fitted(self, "coef_")
        X = _as_features(X, self.n_features_in_)
        return X @ self.coef_.T + self.intercept_

    def predict(self, X) -> np.ndarray:
        """Class label of every row by one-vs-one voting."""
        d = self.decision_function(X)
        mats = getattr(self, "vote_matrices_", None)
        first, second = mats if mats is not None else _vote_matrices(self.pairs_, len(self.classes_))
        return self.classes_[_vote(d, first, second)]


def _as_features(X, n_features: int | None = None) -> np.ndarray:
    arr = np.asarray(X, dtype=float)
    if arr.ndim != 2:
        raise InputError(f"the feature matrix must be 2-D (windows x features), got shape {arr.shape}.")
    if n_features is not None and arr.shape[1] != n_features:
        raise InputError(f"the model expects {n_features} features per window, got {arr.shape[1]}; use the feature set it was trained on.")
    if not np.isfinite(arr).all():
        raise InputError("the feature matrix has NaN/inf values; check the recording for gaps or constant channels.")
    return arr
