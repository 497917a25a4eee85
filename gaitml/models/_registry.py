"""Model kinds by name, behind one scikit-learn estimator interface.

Every kind is a scikit-learn classifier (``fit(X, y)`` returns self,
``predict(X)`` returns labels) with a class attribute ``input_kind``:
``'features'`` (a feature matrix, windows x features) or ``'raw'`` (raw windows,
windows x samples x channels). The cross-validation runner and ``predict`` pick
the matching input from a :class:`~gaitml.models.WindowDataset`.
"""

from __future__ import annotations

from typing import Any

from gaitml.errors import ConfigError
from gaitml.models._svm import LinearOVOSVM
from gaitml.models._torch import TorchCNN1DClassifier, TorchMLPClassifier, require_torch

__all__ = ["MODEL_KINDS", "TORCH_KINDS", "make_model", "model_class", "model_param_names"]

#: kind -> estimator class
MODEL_KINDS = {
    "linear-ovo-svm": LinearOVOSVM,
    "mlp": TorchMLPClassifier,
    "cnn1d": TorchCNN1DClassifier,
}
#: kinds that need the optional torch extra
TORCH_KINDS = ("mlp", "cnn1d")


def model_class(kind: str):
    """The estimator class of ``kind`` (ConfigError listing the kinds if unknown)."""
    try:
        return MODEL_KINDS[kind]
    except KeyError:
        raise ConfigError(f"model.kind = {kind!r} is not a model kind; allowed: {', '.join(MODEL_KINDS)}.") from None


def model_param_names(kind: str) -> list[str]:
    """Constructor parameters of ``kind`` (what ``[model] params`` may set)."""
    return sorted(model_class(kind)().get_params(deep=False))


def make_model(kind: str, params: dict[str, Any] | None = None, *, seed: int = 0):
    """Build an unfitted estimator of ``kind`` with ``params`` (``random_state`` defaults to ``seed``).

    Raises
    ------
    ConfigError
        Unknown kind or parameter (naming the allowed ones).
    ModelError
        A torch kind while torch is not installed (naming the extra).
    """
    cls = model_class(kind)
    if kind in TORCH_KINDS:
        require_torch(f"model kind {kind!r}")
    params = dict(params or {})
    allowed = model_param_names(kind)
    for k in params:
        if k not in allowed:
            raise ConfigError(f"model.params.{k} is not a parameter of {kind!r}; allowed: {', '.join(allowed)}.")
    params.setdefault("random_state", int(seed))
    for k in ("hidden", "channels"):
        if k in params and isinstance(params[k], list):
            params[k] = tuple(params[k])
    return cls(**params)
