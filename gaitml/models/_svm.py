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
from gaitml.models._validation import seed_from, set_classes, standardisation, validate_fit, validate_predict

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


def _vote_scores(decision: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Votes plus squashed confidence sums, shape (n, n_classes): the argmax is the OVO winner."""
    win_i = (decision > 0).astype(float)
    votes = win_i @ first + (1.0 - win_i) @ second
    conf = decision @ (first - second)
    # squash the confidence sums into (-1/3, 1/3) so they only break ties
    return votes + conf / (3 * (np.abs(conf) + 1))


def _vote(decision: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    return np.argmax(_vote_scores(decision, first, second), axis=1)


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
    random_state : int, RandomState instance or None, default 0
        Seed of liblinear's / libsvm's internal shuffling (the dual solvers;
        the default primal solver is deterministic). An int is passed to every
        pairwise machine; None or a RandomState draws one int seed per ``fit``
        (scikit-learn convention).

    Attributes
    ----------
    classes_ : ndarray
        The sorted class labels, of the type given to ``fit`` (str, int...).
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
            Finite numeric features (validated by scikit-learn's ``validate_data``).
        y : array-like, shape (n,)
            Class labels (any type scikit-learn classifies; kept as given).

        Returns
        -------
        self

        Raises
        ------
        InputError
            A bad parameter, bad ``X``/``y``, or fewer than 2 classes.
        """
        from sklearn.svm import SVC, LinearSVC

        self._check_params()
        X, y = validate_fit(self, X, y)
        codes = set_classes(self, y)
        seed = seed_from(self.random_state)
        self.mean_, self.scale_ = standardisation(X)
        Z = (X - self.mean_) / self.scale_
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
                    clf = SVC(kernel="linear", C=self.C, tol=self.tol * 10, max_iter=-1, random_state=seed)
                else:
                    clf = LinearSVC(
                        C=self.C,
                        loss=self.loss,
                        dual=self.loss == "hinge",
                        tol=self.tol,
                        max_iter=self.max_iter,
                        random_state=seed,
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

    def pairwise_decision_function(self, X) -> np.ndarray:
        """Decision values of the pairwise machines, shape (n, n_pairs).

        Column k is machine ``pairs_[k] = (i, j)``: positive means class ``classes_[i]``.

        Raises
        ------
        sklearn.exceptions.NotFittedError
            Before ``fit``.
        InputError
            ``X`` is not a finite numeric (n, ``n_features_in_``) table.
        """
        if "coef_" not in self.__dict__:  # check_is_fitted (tags lookup) only when it will raise: the one-window path
            check_is_fitted(self, "coef_")
        return self._pairwise(validate_predict(self, X))

    def _pairwise(self, X: np.ndarray) -> np.ndarray:
        return X @ self.coef_.T + self.intercept_

    def _scores(self, pairwise: np.ndarray) -> np.ndarray:
        mats = getattr(self, "vote_matrices_", None)
        first, second = mats if mats is not None else _vote_matrices(self.pairs_, len(self.classes_))
        return _vote_scores(pairwise, first, second)

    def decision_function(self, X) -> np.ndarray:
        """Decision values in scikit-learn's convention (the argmax / sign gives ``predict``).

        Two classes: shape (n,), positive means ``classes_[1]`` (the one machine,
        sign flipped). More classes: shape (n, n_classes), the one-vs-one votes
        plus the squashed confidence sums of the vote (as ``SVC`` with
        ``decision_function_shape='ovr'``). The machines' own values are
        :meth:`pairwise_decision_function`.
        """
        d = self.pairwise_decision_function(X)
        if len(self.classes_) == 2:
            return -d[:, 0]
        return self._scores(d)

    def predict(self, X) -> np.ndarray:
        """Class label of every row by one-vs-one voting (labels of the type given to ``fit``)."""
        if "coef_" not in self.__dict__:  # check_is_fitted (tags lookup) only when it will raise: the one-window path
            check_is_fitted(self, "coef_")
        scores = self._scores(self._pairwise(validate_predict(self, X)))
        return self.classes_[np.argmax(scores, axis=1)]

    def _get_state(self) -> tuple[dict, dict[str, np.ndarray]]:
        """Fitted values as (JSON scalars, numeric arrays) for a data-only model file."""
        check_is_fitted(self, "coef_")
        scalars = {"n_features_in_": int(self.n_features_in_), "converged_": bool(getattr(self, "converged_", True))}
        arrays = {
            "classes_": self.classes_,
            "mean_": self.mean_,
            "scale_": self.scale_,
            "coef_": self.coef_,
            "intercept_": self.intercept_,
            "pairs_": self.pairs_,
            "n_iter_": getattr(self, "n_iter_", np.zeros(len(self.pairs_), dtype=int)),
        }
        if hasattr(self, "feature_names_in_"):
            arrays["feature_names_in_"] = self.feature_names_in_
        return scalars, arrays

    @classmethod
    def _from_state(cls, params: dict, scalars: dict, arrays: dict[str, np.ndarray]) -> LinearOVOSVM:
        """Rebuild a fitted estimator from :meth:`_get_state` output (no refit)."""
        est = cls(**params)
        est.n_features_in_ = int(scalars["n_features_in_"])
        est.converged_ = bool(scalars["converged_"])
        for name in ("classes_", "mean_", "scale_", "coef_", "intercept_", "pairs_", "n_iter_"):
            setattr(est, name, np.asarray(arrays[name]))
        if "feature_names_in_" in arrays:
            est.feature_names_in_ = np.asarray(arrays["feature_names_in_"], dtype=object)
        n_pairs = len(est.classes_) * (len(est.classes_) - 1) // 2
        if est.coef_.shape != (n_pairs, est.n_features_in_) or est.intercept_.shape != (n_pairs,) or est.pairs_.shape != (n_pairs, 2):
            raise ValueError(f"array shapes do not fit {len(est.classes_)} classes and {est.n_features_in_} features")
        est.vote_matrices_ = _vote_matrices(est.pairs_, len(est.classes_))
        return est

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = False
        return tags
