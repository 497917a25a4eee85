"""Optional torch baselines: a small MLP on the features and a small 1-D CNN on raw windows.

These are not in paper 003; they are baselines to put the linear OVO SVM of
sec. 3.3 in context. torch is imported only when one of them is built or
fitted, and its absence raises :class:`~gaitml.errors.ModelError` naming the
extra to install (``pip install 'gaitml[torch]'``).

Determinism: ``fit`` seeds torch with ``random_state``, switches torch to
deterministic algorithms, uses ``n_threads`` CPU threads (default 1, so that
cross-validation folds running in parallel do not oversubscribe the cores) and
shuffles mini-batches with a seeded generator; the same data and seed give the
same weights and predictions.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils.validation import check_is_fitted

from gaitml.errors import InputError, ModelError
from gaitml.models._validation import seed_from, set_classes, standardisation, validate_fit, validate_predict

__all__ = ["TorchMLPClassifier", "TorchCNN1DClassifier", "require_torch", "torch_available"]

TORCH_HINT = "install the optional extra: pip install 'gaitml[torch]'"


def torch_available() -> bool:
    """Whether torch can be imported."""
    try:
        import torch  # noqa: F401
    except ImportError:
        return False
    return True


def require_torch(what: str):
    """Import and return torch, or raise ModelError naming the extra."""
    try:
        import torch
    except ImportError as exc:
        raise ModelError(f"{what} needs torch, which is not installed; {TORCH_HINT}.") from exc
    return torch


class _TorchClassifier(ClassifierMixin, BaseEstimator):
    """Common fit/predict loop (Adam, cross-entropy, mini-batches)."""

    input_kind = "features"

    def _build(self, torch, n_in: int, n_classes: int):  # pragma: no cover - abstract
        """The untrained network for ``n_in`` inputs (MLP: features; CNN: channels)."""
        raise NotImplementedError

    def _prepare(self, X, fitting: bool) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _check_params(self) -> None:
        """Raise InputError naming a bad constructor parameter."""
        for name in ("epochs", "batch_size", "n_threads"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise InputError(f"`{name}` must be a positive integer, got {v!r}.")
        for name in ("learning_rate", "weight_decay"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | float) or v < 0 or (name == "learning_rate" and v == 0):
                raise InputError(f"`{name}` must be a {'positive' if name == 'learning_rate' else 'non-negative'} number, got {v!r}.")
        for name in ("hidden", "channels"):
            v = getattr(self, name, None)
            if v is not None and (
                not isinstance(v, tuple | list) or not v or any(isinstance(h, bool) or not isinstance(h, int) or h < 1 for h in v)
            ):
                raise InputError(f"`{name}` must be a list of positive integers, got {v!r}.")
        if hasattr(self, "channels") and len(self.channels) != 2:
            raise InputError(f"`channels` must give the filters of the 2 conv layers, e.g. [16, 32], got {self.channels!r}.")
        d = getattr(self, "dropout", 0.0)
        if isinstance(d, bool) or not isinstance(d, int | float) or not 0 <= d < 1:
            raise InputError(f"`dropout` must be in [0, 1), got {d!r}.")
        k = getattr(self, "kernel_size", 1)
        if isinstance(k, bool) or not isinstance(k, int) or k < 1:
            raise InputError(f"`kernel_size` must be a positive integer, got {k!r}.")

    #: ``validate_data`` settings of the input (the CNN takes 3-D raw windows).
    _allow_nd = False
    _min_features = 1

    def fit(self, X, y):
        """Train the network.

        Parameters
        ----------
        X : array-like
            Feature matrix (n, n_features) for the MLP; raw windows
            (n, length_samples, n_channels) or one-channel windows (n, length_samples)
            for the CNN. Finite numbers (scikit-learn's ``validate_data``).
        y : array-like, shape (n,)
            Class labels, kept in their own type.

        Returns
        -------
        self

        Raises
        ------
        InputError
            A bad parameter, bad ``X``/``y``, or fewer than 2 classes.
        ModelError
            torch is not installed.
        """
        torch = require_torch(f"model kind {self._kind!r}")
        self._check_params()
        X, y = validate_fit(self, X, y, allow_nd=self._allow_nd, ensure_min_features=self._min_features)
        codes = set_classes(self, y)
        Xp = self._prepare(X, fitting=True)
        seed = seed_from(self.random_state)
        torch.manual_seed(seed)
        prev_det = torch.are_deterministic_algorithms_enabled()
        prev_threads = torch.get_num_threads()
        torch.use_deterministic_algorithms(True)
        torch.set_num_threads(self.n_threads)
        try:
            net = self._build(torch, Xp.shape[1], len(self.classes_))
            opt = torch.optim.Adam(net.parameters(), lr=self.learning_rate, weight_decay=self.weight_decay)
            loss_fn = torch.nn.CrossEntropyLoss()
            xt = torch.as_tensor(Xp, dtype=torch.float32)
            yt = torch.as_tensor(codes, dtype=torch.long)
            gen = torch.Generator().manual_seed(seed)
            n = len(xt)
            self.loss_curve_ = []
            net.train()
            for _ in range(self.epochs):
                perm = torch.randperm(n, generator=gen)
                total = 0.0
                for s in range(0, n, self.batch_size):
                    idx = perm[s : s + self.batch_size]
                    opt.zero_grad()
                    loss = loss_fn(net(xt[idx]), yt[idx])
                    loss.backward()
                    opt.step()
                    total += float(loss.detach()) * len(idx)
                self.loss_curve_.append(total / n)
            net.eval()
        finally:
            torch.use_deterministic_algorithms(prev_det)
            torch.set_num_threads(prev_threads)
        self.net_ = net
        return self

    def predict_proba(self, X) -> np.ndarray:
        """Class probabilities, shape (n, n_classes), columns in ``classes_`` order.

        Raises
        ------
        sklearn.exceptions.NotFittedError
            Before ``fit``.
        InputError
            ``X`` does not have the shape the model was fitted on, or is not finite.
        """
        check_is_fitted(self, "net_")
        torch = require_torch(f"model kind {self._kind!r}")
        X = validate_predict(self, X, allow_nd=self._allow_nd)
        Xp = self._prepare(X, fitting=False)
        with torch.no_grad():
            logits = self.net_(torch.as_tensor(Xp, dtype=torch.float32))
            return torch.softmax(logits, dim=1).numpy().astype(float)

    def predict(self, X) -> np.ndarray:
        """Most probable class of every row (labels of the type given to ``fit``)."""
        check_is_fitted(self, "net_")
        proba = self.predict_proba(X)
        return self.classes_[np.argmax(proba, axis=1)]

    def _get_state(self) -> tuple[dict, dict[str, np.ndarray], dict]:
        """Fitted values as (JSON scalars, numeric arrays, torch state_dict) for data-only files."""
        check_is_fitted(self, "net_")
        scalars = {"n_features_in_": int(self.n_features_in_), "loss_curve_": [float(v) for v in getattr(self, "loss_curve_", [])]}
        if hasattr(self, "window_shape_"):
            scalars["window_shape_"] = [int(v) for v in self.window_shape_]
        arrays = {"classes_": self.classes_, "mean_": self.mean_, "scale_": self.scale_}
        if hasattr(self, "feature_names_in_"):
            arrays["feature_names_in_"] = self.feature_names_in_
        return scalars, arrays, {k: v.detach().clone() for k, v in self.net_.state_dict().items()}

    @classmethod
    def _from_state(cls, params: dict, scalars: dict, arrays: dict[str, np.ndarray], state_dict: dict):
        """Rebuild a fitted estimator: the architecture from ``params``, then the weights (no refit)."""
        torch = require_torch(f"model kind {cls._kind!r}")
        est = cls(**params)
        est.n_features_in_ = int(scalars["n_features_in_"])
        est.loss_curve_ = list(scalars.get("loss_curve_", []))
        if "window_shape_" in scalars:
            est.window_shape_ = tuple(int(v) for v in scalars["window_shape_"])
        for name in ("classes_", "mean_", "scale_"):
            setattr(est, name, np.asarray(arrays[name]))
        if "feature_names_in_" in arrays:
            est.feature_names_in_ = np.asarray(arrays["feature_names_in_"], dtype=object)
        n_in = est.window_shape_[1] if hasattr(est, "window_shape_") else est.n_features_in_
        net = est._build(torch, n_in, len(est.classes_))
        net.load_state_dict(state_dict, strict=True)
        net.eval()
        est.net_ = net
        return est

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.three_d_array = self._allow_nd
        return tags


class TorchMLPClassifier(_TorchClassifier):
    """Small multilayer perceptron on standardised window features.

    Parameters
    ----------
    hidden : tuple of int, default (64, 32)
        Sizes of the hidden layers (ReLU).
    dropout : float, default 0.1
    epochs : int, default 40
    batch_size : int, default 128
    learning_rate : float, default 1e-3
    weight_decay : float, default 1e-4
    random_state : int, RandomState instance or None, default 0
        Seed of the weight initialisation, dropout and batch shuffling; None or a
        RandomState draws one int seed per ``fit`` (scikit-learn convention).
    n_threads : int, default 1
        CPU threads torch uses while fitting.
    """

    _kind = "mlp"
    input_kind = "features"

    def __init__(
        self,
        hidden=(64, 32),
        *,
        dropout: float = 0.1,
        epochs: int = 40,
        batch_size: int = 128,
        learning_rate: float = 1e-3,
        weight_decay: float = 1e-4,
        random_state: int = 0,
        n_threads: int = 1,
    ):
        self.hidden = hidden
        self.dropout = dropout
        self.epochs = epochs
        self.batch_size = batch_size
        self.learning_rate = learning_rate
        self.weight_decay = weight_decay
        self.random_state = random_state
        self.n_threads = n_threads

    def _prepare(self, X, fitting: bool) -> np.ndarray:
        """Standardise a validated 2-D feature matrix (fitting: learn mean and scale)."""
        arr = np.asarray(X, dtype=float)
        if fitting:
            self.mean_, self.scale_ = standardisation(arr)
        return (arr - self.mean_) / self.scale_

    def _build(self, torch, n_in, n_classes):
        nn = torch.nn
        layers = []
        for h in tuple(self.hidden):
            layers += [nn.Linear(n_in, int(h)), nn.ReLU(), nn.Dropout(self.dropout)]
            n_in = int(h)
        layers.append(nn.Linear(n_in, n_classes))
        return nn.Sequential(*layers)


class TorchCNN1DClassifier(_TorchClassifier):
    """Small 1-D convolutional network on the raw window samples.

    Input: raw windows of shape (n, length_samples, n_channels) (acc x, y, z and
    the gravity-free magnitude; see :func:`gaitml.models.raw_window_channels`),
    standardised per channel with the training mean and std. A 2-D array
    (n, length_samples) is read as one channel (this is also what lets
    scikit-learn's estimator checks, which feed 2-D tables, run on it).

    Architecture: two Conv1d (kernel 5, ReLU, ``channels`` filters each), max
    pooling by 2 after the first, global average pooling, a linear layer.

    Parameters
    ----------
    channels : tuple of int, default (16, 32)
    kernel_size : int, default 5
    epochs : int, default 30
    batch_size : int, default 64
    learning_rate : float, default 2e-3
    weight_decay : float, default 1e-4
    random_state : int, RandomState instance or None, default 0
        Seed of the weight initialisation, dropout and batch shuffling; None or a
        RandomState draws one int seed per ``fit`` (scikit-learn convention).
    n_threads : int, default 1
        CPU threads torch uses while fitting.
    """

    _kind = "cnn1d"
    input_kind = "raw"

    def __init__(
        self,
        channels=(16, 32),
        *,
        kernel_size: int = 5,
        epochs: int = 30,
        batch_size: int = 64,
        learning_rate: float = 2e-3,
        weight_decay: float = 1e-4,
        random_state: int = 0,
        n_threads: int = 1,
    ):
        self.channels = channels
        self.kernel_size = kernel_size
        self.epochs = epochs
        self.batch_size = batch_size
        self.learning_rate = learning_rate
        self.weight_decay = weight_decay
        self.random_state = random_state
        self.n_threads = n_threads

    _allow_nd = True
    _min_features = 2  # window length in samples: the max pooling halves it

    def _prepare(self, X, fitting: bool) -> np.ndarray:
        """Standardise validated raw windows per channel; 2-D input is one channel."""
        arr = np.asarray(X, dtype=float)
        if arr.ndim == 2:
            arr = arr[:, :, None]
        if arr.ndim != 3:
            raise InputError(f"the 1-D CNN needs raw windows of shape (n, length, channels) or (n, length), got shape {arr.shape}.")
        if fitting:
            self.window_shape_ = arr.shape[1:]
            self.mean_, self.scale_ = standardisation(arr, axis=(0, 1))
        elif arr.shape[1:] != tuple(self.window_shape_):
            raise InputError(
                f"the model expects raw windows of shape {tuple(self.window_shape_)}, got {arr.shape[1:]}; use its window length and rate."
            )
        z = (arr - self.mean_) / self.scale_
        return np.ascontiguousarray(np.transpose(z, (0, 2, 1)))  # torch wants (n, channels, length)

    def _build(self, torch, n_in, n_classes):
        nn = torch.nn
        c1, c2 = (int(c) for c in self.channels)
        k = int(self.kernel_size)
        return nn.Sequential(
            nn.Conv1d(int(n_in), c1, k, padding=k // 2),
            nn.ReLU(),
            nn.MaxPool1d(2),
            nn.Conv1d(c1, c2, k, padding=k // 2),
            nn.ReLU(),
            nn.AdaptiveAvgPool1d(1),
            nn.Flatten(),
            nn.Linear(c2, n_classes),
        )
