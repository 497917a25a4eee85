"""Linear one-vs-one SVM on standardised features (paper 003, sec. 3.1 and 3.3).

The paper classifies the five motion modes with a linear-kernel SVM, trained one
pair of classes at a time (OVO: m (m - 1) / 2 binary machines, majority vote),
on its time-domain features, with a penalty factor (called M in eq. 5, C here).

Implementation choice (timed by ``gaitml bench``, ``benchmarks/models.py``): each pairwise
machine is a :class:`sklearn.svm.LinearSVC` (liblinear) solved in the primal
(``dual=False``), which is linear in the number of windows; libsvm's
``SVC(kernel='linear')`` (also one-vs-one) grows faster than linearly
(``benchmarks/README.md``). ``solver='libsvm'`` keeps
that path selectable as the reference. liblinear's primal solver needs the
squared hinge loss; the paper's eq. (5) is the plain hinge. Both give a maximum
margin linear separator with penalty C; ``loss='hinge'`` (dual solver) is
available for a literal reading.

Convergence: the primal objective ``0.5 |w|^2 + C sum max(0, 1 - y w.x)^2`` (bias
included in ``w``, as liblinear penalises it) is 1-strongly convex, so a weight vector
whose gradient has norm g lies within g of the exact optimum (Boyd and Vandenberghe,
*Convex Optimization*, sec. 9.1.2). liblinear's Newton solver (TRON, Lin, Weng and
Keerthi 2008, *JMLR* 9: 627-650) stops when the gradient norm falls below ``tol``
times its norm at w = 0, which on thousands of windows is of order 1e4: at
scikit-learn's ``tol=1e-4`` a weight may then sit anywhere within about 1 of the
optimum, and a last-bit change of the input or of a BLAS dot product (another CPU,
another thread count) moves it there. The primal default here is ``tol=1e-10``
(Newton converges quadratically: a handful more iterations), and the fit records
every pair's final gradient norm (``gradient_norm_``): the bound on how far the weights
can be from the optimum, hence from a retrain on another machine. liblinear's dot
products are BLAS calls; the fit runs them with one BLAS thread so that their order
of summation is fixed.

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

__all__ = ["LinearOVOSVM", "ovo_vote", "primal_gradient_norm"]

#: Penalty factor default (paper 003 eq. 5 calls it M; its value is not given).
DEFAULT_C = 1.0
#: Default stopping tolerance of the primal Newton solver (relative gradient norm; see the module docstring).
PRIMAL_TOL = 1e-10
#: Default stopping tolerance of the dual solvers (liblinear ``loss='hinge'``; libsvm gets ten times it), scikit-learn's.
DUAL_TOL = 1e-4


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


def primal_gradient_norm(Z: np.ndarray, y: np.ndarray, w: np.ndarray, b: float, C: float) -> float:
    """Norm of the gradient of liblinear's primal L2-loss SVM objective at (w, b).

    The objective is ``0.5 (|w|^2 + b^2) + C sum_i max(0, 1 - y_i (w.z_i + b))^2``
    (Fan et al. 2008, *JMLR* 9: 1871-1874, eq. 2, with the bias as a constant feature
    of value 1, scikit-learn's ``intercept_scaling=1``). It is 1-strongly convex, so the
    returned norm bounds the distance of (w, b) to the exact optimum.

    Parameters
    ----------
    Z : ndarray, shape (n, n_features)
        Standardised features of the pair's windows.
    y : ndarray, shape (n,)
        +1 / -1 labels.
    w : ndarray, shape (n_features,)
    b : float
    C : float
    """
    y = np.asarray(y, dtype=float)
    margin = 1.0 - y * (Z @ w + b)
    act = margin > 0
    r = 2.0 * C * y[act] * margin[act]
    gw = w - r @ Z[act]
    gb = b - r.sum()
    return float(np.sqrt(gw @ gw + gb * gb))


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
    tol : float or None, default None
        Stopping tolerance. None: :data:`PRIMAL_TOL` (1e-10) for the primal solver
        (``loss='squared_hinge'``, converged to within ``gradient_norm_`` of the
        optimum), :data:`DUAL_TOL` (1e-4) for the dual solvers, whose coordinate
        steps converge linearly.
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
    n_iter_ : ndarray of int, shape (n_pairs,)
        Solver iterations of every pair (all below ``max_iter`` when ``converged_``).
    gradient_norm_ : ndarray, shape (n_pairs,)
        Primal solver only (NaN otherwise): the norm of every pair's objective gradient
        at the fitted (standardised) weights and bias, an upper bound on their distance
        to the exact optimum.
    converged_ : bool
        Every pair stopped on its tolerance before ``max_iter``.
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
        tol: float | None = None,
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
        if self.tol is not None and not (isinstance(self.tol, int | float) and np.isfinite(self.tol) and self.tol > 0):
            raise InputError(f"`tol` must be a positive number or None (the solver's default), got {self.tol!r}; e.g. tol = 1e-10.")

    def _primal(self) -> bool:
        return self.solver == "liblinear" and self.loss == "squared_hinge"

    def _tol(self) -> float:
        if self.tol is not None:
            return float(self.tol)
        return PRIMAL_TOL if self._primal() else DUAL_TOL

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
        from threadpoolctl import threadpool_limits

        self._check_params()
        tol = self._tol()
        X, y = validate_fit(self, X, y)
        codes = set_classes(self, y)
        seed = seed_from(self.random_state)
        self.mean_, self.scale_ = standardisation(X)
        Z = (X - self.mean_) / self.scale_
        pairs = np.array(list(combinations(range(len(self.classes_)), 2)), dtype=int)
        coef = np.zeros((len(pairs), X.shape[1]))
        intercept = np.zeros(len(pairs))
        self.n_iter_ = np.zeros(len(pairs), dtype=int)
        self.gradient_norm_ = np.full(len(pairs), np.nan)
        with warnings.catch_warnings(record=True) as caught, threadpool_limits(limits=1, user_api="blas"):
            warnings.simplefilter("always", ConvergenceWarning)
            for k, (i, j) in enumerate(pairs):
                mask = (codes == i) | (codes == j)
                yk = np.where(codes[mask] == i, 1, -1)
                if self.solver == "libsvm":
                    clf = SVC(kernel="linear", C=self.C, tol=tol * 10, max_iter=-1, random_state=seed)
                else:
                    clf = LinearSVC(
                        C=self.C,
                        loss=self.loss,
                        dual=self.loss == "hinge",
                        tol=tol,
                        max_iter=self.max_iter,
                        random_state=seed,
                    )
                clf.fit(Z[mask], yk)
                # class order of clf is [-1, 1], so a positive decision means class i
                coef[k] = np.ravel(clf.coef_)
                intercept[k] = float(np.ravel(clf.intercept_)[0])
                self.n_iter_[k] = int(np.max(getattr(clf, "n_iter_", 0)))
                if self._primal():
                    self.gradient_norm_[k] = primal_gradient_norm(Z[mask], yk, coef[k], intercept[k], self.C)
        self.converged_ = not any(issubclass(w.category, ConvergenceWarning) for w in caught)
        if self.solver == "liblinear":
            self.converged_ = self.converged_ and bool(np.all(self.n_iter_ < self.max_iter))
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
        n_iter = getattr(self, "n_iter_", None)
        if n_iter is not None and len(n_iter):
            scalars["n_iter_max_"] = int(np.max(n_iter))
        gnorm = getattr(self, "gradient_norm_", None)
        if gnorm is not None and np.isfinite(gnorm).any():  # the model card states the bound
            scalars["gradient_norm_max_"] = float(np.nanmax(gnorm))
        arrays = {
            "classes_": self.classes_,
            "mean_": self.mean_,
            "scale_": self.scale_,
            "coef_": self.coef_,
            "intercept_": self.intercept_,
            "pairs_": self.pairs_,
            "n_iter_": getattr(self, "n_iter_", np.zeros(len(self.pairs_), dtype=int)),
        }
        if gnorm is not None:
            arrays["gradient_norm_"] = np.asarray(gnorm, dtype=float)
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
        # models saved before the bound was recorded have no gradient_norm_
        est.gradient_norm_ = np.asarray(arrays.get("gradient_norm_", np.full(len(est.pairs_), np.nan)), dtype=float)
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
