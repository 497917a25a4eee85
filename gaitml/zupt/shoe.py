"""SHOE: the stance hypothesis optimal detector (Skog et al., IEEE TBME 2010).

I. Skog, P. Handel, J.-O. Nilsson, J. Rantakokko, "Zero-velocity detection --
an algorithm evaluation", IEEE Trans. Biomed. Eng. 57(11), 2010: the generalised
likelihood ratio test (GLRT) for a stationary IMU over a window of W samples.
The usual reference detector of the field; not one of the package's papers.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from gaitml._base import POSITIVE, POSITIVE_INTEGER
from gaitml.consts import DEG2RAD, GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.zupt._base import BaseZuptDetector, empirical_upper_threshold, labelled_samples
from gaitml.zupt._intervals import apply_blockwise, centered_sums

__all__ = ["ShoeZuptDetector", "shoe_statistic", "DEFAULT_SIGMA_A_MS2", "DEFAULT_SIGMA_W_RADS", "DEFAULT_GAMMA", "DEFAULT_WINDOW_SAMPLES"]

#: Accelerometer noise standard deviation sigma_a (m/s^2): the OpenShoe / Skog et al. default 0.01.
DEFAULT_SIGMA_A_MS2 = 0.01
#: Gyroscope noise standard deviation sigma_w: 0.1 deg/s (OpenShoe default), in rad/s.
DEFAULT_SIGMA_W_RADS = 0.1 * DEG2RAD
#: Detection threshold gamma on T (OpenShoe default 0.3e5).
DEFAULT_GAMMA = 0.3e5
#: Window length W in samples (OpenShoe default 3).
DEFAULT_WINDOW_SAMPLES = 3


def shoe_statistic(
    acc_ms2: np.ndarray,
    gyr_rads: np.ndarray,
    half_window_samples: int,
    *,
    sigma_a_ms2: float = DEFAULT_SIGMA_A_MS2,
    sigma_w_rads: float = DEFAULT_SIGMA_W_RADS,
    gravity_ms2: float = GRAVITY_MS2,
) -> np.ndarray:
    """The SHOE test statistic over the centred window ``[n - h, n + h]``.

        T_n = (1/W) sum_k ||a_k - g mean_a / ||mean_a|| ||^2 / sigma_a^2 + ||w_k||^2 / sigma_w^2

    with ``mean_a`` the window mean of the specific force. Vectorised with
    cumulative sums: with ``S = sum_k a_k`` the acceleration term is
    ``sum_k |a_k|^2 - 2 g |S| + W g^2`` (because ``mean_a/|mean_a| = S/|S|``).
    At the edges the window is truncated (W = the samples that exist).

    Parameters
    ----------
    acc_ms2, gyr_rads : ndarray, shape (n, 3)
    half_window_samples : int
        h >= 0; W = 2h + 1 samples away from the edges.

    Returns
    -------
    ndarray, shape (n,)
        T (dimensionless); small means stationary.
    """
    a = np.asarray(acc_ms2, dtype=float)
    w = np.asarray(gyr_rads, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3 or w.shape != a.shape:
        raise InputError(f"acc and gyr must both have shape (n, 3), got {a.shape} and {w.shape}.")
    if sigma_a_ms2 <= 0 or sigma_w_rads <= 0:
        raise InputError(f"noise levels must be > 0, got sigma_a_ms2={sigma_a_ms2} and sigma_w_rads={sigma_w_rads}.")
    h = int(half_window_samples)
    if h < 0:
        raise InputError(f"`half_window_samples` must be >= 0, got {half_window_samples}.")
    cols = np.column_stack([a, np.einsum("ij,ij->i", a, a), np.einsum("ij,ij->i", w, w)])
    sums, counts = centered_sums(cols, h)
    norm_s = np.sqrt(np.einsum("ij,ij->i", sums[:, :3], sums[:, :3]))
    acc_term = np.maximum(sums[:, 3] - 2.0 * gravity_ms2 * norm_s + counts * gravity_ms2**2, 0.0)
    return (acc_term / sigma_a_ms2**2 + sums[:, 4] / sigma_w_rads**2) / counts


class ShoeZuptDetector(BaseZuptDetector):
    """Zero velocity where the SHOE statistic is below gamma (Skog et al. 2010).

    Parameters
    ----------
    gamma : float
        Threshold on T (default 0.3e5, OpenShoe). ``fit`` replaces it.
    sigma_a_ms2, sigma_w_rads : float
        Noise standard deviations (defaults 0.01 m/s^2 and 0.1 deg/s, OpenShoe).
    window_samples : int
        W, odd (default 3, OpenShoe). Ignored when ``window_s`` is given.
    window_s : float, optional
        Window length in seconds; W = 2 round(window_s fs / 2) + 1.
    eps : float
        Fraction of labelled zero-velocity samples ``fit`` may miss: gamma is set
        to the empirical ``1 - eps`` quantile of T on those samples (a
        nonparametric Neyman-Pearson choice, as paper 001 does parametrically).

    Notes
    -----
    Only the ratio gamma sigma^2 matters, so the default noise levels are
    nominal, not the sensor's. g is standard gravity (OpenShoe uses the local
    value from latitude and altitude). The defaults were tuned by their authors
    for their own foot-mounted IMUs; on other sensors gamma usually needs
    refitting (``fit``).

    References
    ----------
    Skog et al., IEEE TBME 57(11):2657-2666, 2010, sec. III (GLRT / SHOE).
    """

    name = "shoe"
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "gamma": [POSITIVE],
        "sigma_a_ms2": [POSITIVE],
        "sigma_w_rads": [POSITIVE],
        "window_samples": [POSITIVE_INTEGER],
        "eps": [POSITIVE],
        "window_s": [None, POSITIVE],
    }

    def __init__(
        self,
        *,
        gamma: float = DEFAULT_GAMMA,
        sigma_a_ms2: float = DEFAULT_SIGMA_A_MS2,
        sigma_w_rads: float = DEFAULT_SIGMA_W_RADS,
        window_samples: int = DEFAULT_WINDOW_SAMPLES,
        window_s: float | None = None,
        eps: float = 0.002,
    ):
        self.gamma = gamma
        self.sigma_a_ms2 = sigma_a_ms2
        self.sigma_w_rads = sigma_w_rads
        self.window_samples = window_samples
        self.window_s = window_s
        self.eps = eps

    def _half(self, fs: float) -> int:
        if self.window_s is not None:
            return int(round(self.window_s * fs / 2.0))
        if int(self.window_samples) < 1 or int(self.window_samples) % 2 == 0:
            raise InputError(f"`window_samples` must be an odd number >= 1 (a centred window), got {self.window_samples!r}.")
        return int(self.window_samples) // 2

    def _window_samples(self, sampling_rate_hz: float) -> int:
        return 2 * self._half(sampling_rate_hz) + 1

    def _statistic(self, recording: Recording) -> np.ndarray:
        gyr = recording.require_gyr("the SHOE zero-velocity detector")
        h = self._half(recording.sampling_rate_hz)
        return apply_blockwise(
            lambda a, w: shoe_statistic(a, w, h, sigma_a_ms2=self.sigma_a_ms2, sigma_w_rads=self.sigma_w_rads), (recording.acc, gyr), h
        )

    def _mask(self, recording: Recording):
        t = self._statistic(recording)
        gamma = getattr(self, "fitted_gamma_", float(self.gamma))
        if not gamma > 0:
            raise InputError(f"`gamma` must be > 0, got {self.gamma!r}.")
        self.gamma_ = gamma
        return t < gamma, t

    def fit(self, recordings, reference=None) -> ShoeZuptDetector:
        """Set gamma to the ``1 - eps`` quantile of T on labelled zero-velocity samples."""
        self._validate_params()
        pairs = labelled_samples(recordings, reference)
        vals = np.concatenate([self._statistic(r)[m] for r, m in pairs])
        self.fitted_gamma_ = empirical_upper_threshold(vals, self.eps)
        self.gamma_ = self.fitted_gamma_
        return self
