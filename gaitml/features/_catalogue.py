"""The feature catalogue of paper 003 sec. 3.2: F1..F52, named subsets, the generated markdown.

Run ``python -m gaitml.features.catalogue [--out features/catalogue.md]`` to print
(or atomically write) the markdown table that is committed as
``features/catalogue.md``; a test checks that the committed file is up to date.

Numbering (paper 003 sec. 3.2, "每种特征按x轴、y轴、z轴和合加速度顺序进行编号"):
the twelve basic statistics in the order mean, mean absolute value, variance,
mode, maximum, minimum, interquartile range, third quartile, correlation
coefficient, skewness, kurtosis, mean absolute deviation take F1..F47, each over
x, y, z and the magnitude (correlation over the pairs x-y, x-z, y-z); M4 takes
F48..F51 (x, y, z, magnitude) and f(1) on x is F52.

Readings of ambiguous passages (also in :mod:`gaitml.features._extract`):

- magnitude: ``a = |acc| - g`` with g = 9.8 m/s^2 (paper eq. 1), smoothed with a
  centred 3-sample moving average (paper sec. 2.1, N = 3) computed *within each
  window* (shrunk to 2 samples at the window's first and last sample), so a
  window's features depend on its own samples only;
- "互相关系数" (F33-35) is read as the zero-lag Pearson correlation coefficient
  of two axes over the window;
- the paper's feature analysis used 2 s windows ("每2 s时间的采样数据作为一个窗口");
  the window length here is a parameter (default 1.5 s, the paper's choice in sec. 3.3);
- "三四分位距" (F29-32) is read as the third quartile (75th percentile): the
  interquartile range is already F25-28 and the count of 47 basic features only
  works out with a single-valued statistic here;
- quantiles use linear interpolation between order statistics (numpy's default,
  Hyndman-Fan type 7);
- variance, skewness and kurtosis use population (biased, 1/N) moments;
  kurtosis is the excess kurtosis m4 / m2^2 - 3 (0 for a Gaussian);
- "平均绝对误差" (F44-47) is the mean absolute deviation about the window mean;
- mode of continuous values: values are rounded to bins of fixed width
  (0.1 m/s^2 for acceleration, 0.05 rad/s for angular rate) and the centre of
  the most populated bin is returned; ties go to the smallest value;
- M4 and f(1) keep the paper's 1/N normalisation although the sums have N-2
  and N-1 terms (eqs. 8, 9);
- constant windows (standard deviation <= 1e-10 (1 + |mean|)): skewness,
  kurtosis and correlation are defined as 0 instead of NaN.

References
----------
Deng et al., A PDR algorithm based on human motion recognition, J. Chinese
Inertial Technology, 2021 (paper 003), sec. 2.1, 3.2 and Table 1.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from gaitml.errors import InputError
from gaitml.features._forward import FORWARD_BAND_HZ, FORWARD_FACE_NAMES, FORWARD_NAMES

__all__ = [
    "CATALOGUE",
    "GYRO_CATALOGUE",
    "FEATURE_SETS",
    "FORWARD_CATALOGUE",
    "FORWARD_FACE_CATALOGUE",
    "FeatureSpec",
    "PAPER34_NUMBERS",
    "SUBSET_ALIASES",
    "catalogue_markdown",
    "feature_names",
    "feature_specs",
    "resolve_subset",
    "uses_forward",
    "uses_forward_face",
    "uses_gyro",
    "write_catalogue",
    "main",
]

#: Width of the bins that discretise continuous values for the mode (F13-16).
MODE_BIN_WIDTH = {"acc": 0.1, "gyr": 0.05}  # m/s^2, rad/s (our choice; the paper gives none)

#: The 34 features of paper 003 Table 1 (union over the five modes).
PAPER34_NUMBERS = (5, 8, 9, 10, 11, 12, 13, 15, 16, 19, 20, 23, 24, *range(26, 37), 38, 40, 41, 42, 45, 47, 48, 49, 50, 52)

_AXES = ("x", "y", "z", "mag")
_PAIRS = ("xy", "xz", "yz")

# (stat, channels, description, formula with {c} = channel symbol)
_STAT_TABLE = (
    ("mean", _AXES, "mean", "(1/N) sum_i a_i"),
    ("mean_abs", _AXES, "mean of absolute values", "(1/N) sum_i |a_i|"),
    ("var", _AXES, "variance (population, 1/N)", "(1/N) sum_i (a_i - mean)^2"),
    ("mode", _AXES, "mode of values rounded to bins of width w", "w * argmax_k #{i: floor(a_i / w + 1/2) = k}, ties -> smallest k"),
    ("max", _AXES, "maximum", "max_i a_i"),
    ("min", _AXES, "minimum", "min_i a_i"),
    ("iqr", _AXES, "interquartile range", "Q3 - Q1 (linear interpolation, type 7)"),
    ("q3", _AXES, "third quartile (reading of 三四分位距)", "Q3 = 75th percentile (linear interpolation, type 7)"),
    ("corr", _PAIRS, "correlation coefficient (zero-lag Pearson)", "cov(a, b) / sqrt(var(a) var(b)); 0 if a or b is constant"),
    ("skew", _AXES, "skewness (population moments)", "m3 / m2^(3/2); 0 if constant"),
    ("kurt", _AXES, "excess kurtosis (population moments)", "m4 / m2^2 - 3; 0 if constant"),
    ("mad", _AXES, "mean absolute deviation", "(1/N) sum_i |a_i - mean|"),
    ("m4", _AXES, "Hjorth intermediate M4 (paper eq. 8)", "(1/N) sum_{i=3..N} ((a_i - a_{i-1}) - (a_{i-1} - a_{i-2}))^2"),
    ("f1", ("x",), "f(1): mean squared first difference (paper eq. 9)", "(1/N) sum_{i=2..N} (a_i - a_{i-1})^2"),
)


@dataclasses.dataclass(frozen=True)
class FeatureSpec:
    """One catalogue entry.

    Attributes
    ----------
    number : int
        1..52 for the paper's F1..F52 (acceleration); 53..104 for the gyro
        counterparts G1..G52 (``number - 52`` is the mirrored F number).
    code : str
        ``"F<k>"`` or ``"G<k>"``.
    name : str
        The column name ``<channel>__<stat>``.
    sensor : str
        ``"acc"`` or ``"gyr"``.
    channel : str
        ``acc_x``, ``acc_y``, ``acc_z``, ``acc_mag``, ``acc_xy``... (gyro: ``gyr_*``).
    stat : str
        Statistic key (``mean``, ``mean_abs``, ``var``, ``mode``, ``max``, ``min``,
        ``iqr``, ``q3``, ``corr``, ``skew``, ``kurt``, ``mad``, ``m4``, ``f1``).
    description, formula : str
        Human-readable definition.
    """

    number: int
    code: str
    name: str
    sensor: str
    channel: str
    stat: str
    description: str
    formula: str


def _build(sensor: str) -> tuple[FeatureSpec, ...]:
    out = []
    k = 0
    offset = 0 if sensor == "acc" else 52
    prefix = "F" if sensor == "acc" else "G"
    for stat, chans, desc, formula in _STAT_TABLE:
        for ch in chans:
            k += 1
            channel = f"{sensor}_{ch}"
            out.append(
                FeatureSpec(
                    number=k + offset,
                    code=f"{prefix}{k}",
                    name=f"{channel}__{stat}",
                    sensor=sensor,
                    channel=channel,
                    stat=stat,
                    description=desc,
                    formula=formula,
                )
            )
    assert k == 52
    return tuple(out)


#: The 52 acceleration features F1..F52 in the paper's order.
CATALOGUE: tuple[FeatureSpec, ...] = _build("acc")
#: The same statistics on the gyroscope (G1..G52, numbers 53..104).
GYRO_CATALOGUE: tuple[FeatureSpec, ...] = _build("gyr")

#: The forward-vector group W1..W3 (numbers 105..107; opt-in sets ``all52+fwd``, ``all52+gyro+fwd``):
#: the band-passed forward vector's components along the phone's x, y, z, the one time-odd quantity
#: of the catalogue (:mod:`gaitml.features._forward`, not in paper 003).
FORWARD_CATALOGUE: tuple[FeatureSpec, ...] = tuple(
    FeatureSpec(
        number=105 + i,
        code=f"W{i + 1}",
        name=f"acc_{ax}__fwd",
        sensor="acc",
        channel=f"acc_{ax}",
        stat="fwd",
        description=f"forward vector along {ax}: covariance of the horizontal acceleration with d/dt of the vertical one, gait band",
        formula="mean_t h(t) v'(t) / sqrt(mean_t |h|^2 mean_t v'^2), h, v: acc band-passed 0.5-3 Hz, horizontal / vertical part",
    )
    for i, ax in enumerate("xyz")
)
assert tuple(s.name for s in FORWARD_CATALOGUE) == FORWARD_NAMES
#: The face-up-weighted forward vector W4..W6 (numbers 108..110; opt-in sets ``all52+fwdface``,
#: ``all52+gyro+fwdface``): W1..W3 times ``max(0, up_z)``, how face up the phone is (:mod:`gaitml.features._forward`).
FORWARD_FACE_CATALOGUE: tuple[FeatureSpec, ...] = tuple(
    FeatureSpec(
        number=108 + i,
        code=f"W{i + 4}",
        name=f"acc_{ax}__fwdface",
        sensor="acc",
        channel=f"acc_{ax}",
        stat="fwdface",
        description=f"forward vector along {ax} (W{i + 1}) times max(0, up_z), how face up the phone is",
        formula="W{k} * max(0, mean(acc)_z / |mean(acc)|)".replace("{k}", str(i + 1)),
    )
    for i, ax in enumerate("xyz")
)
assert tuple(s.name for s in FORWARD_FACE_CATALOGUE) == FORWARD_FACE_NAMES

#: Named feature subsets: column names in extraction order.
FEATURE_SETS: dict[str, tuple[str, ...]] = {
    "all52": tuple(s.name for s in CATALOGUE),
    "paper34": tuple(s.name for s in CATALOGUE if s.number in PAPER34_NUMBERS),
    "all52+gyro": tuple(s.name for s in CATALOGUE + GYRO_CATALOGUE),
    "all52+fwd": tuple(s.name for s in CATALOGUE + FORWARD_CATALOGUE),
    "all52+gyro+fwd": tuple(s.name for s in CATALOGUE + GYRO_CATALOGUE + FORWARD_CATALOGUE),
    "all52+fwdface": tuple(s.name for s in CATALOGUE + FORWARD_FACE_CATALOGUE),
    "all52+gyro+fwdface": tuple(s.name for s in CATALOGUE + GYRO_CATALOGUE + FORWARD_FACE_CATALOGUE),
}

#: Accepted alternative spellings of subset names.
SUBSET_ALIASES = {"all": "all52"}

_BY_NAME = {s.name: s for s in CATALOGUE + GYRO_CATALOGUE + FORWARD_CATALOGUE + FORWARD_FACE_CATALOGUE}


def uses_gyro(subset: str) -> bool:
    """Whether a (canonical) subset reads the gyroscope (G1..G52)."""
    return "gyro" in resolve_subset(subset).split("+")


def uses_forward(subset: str) -> bool:
    """Whether a (canonical) subset holds a forward-vector group (W1..W3 or W4..W6; :mod:`gaitml.features._forward`)."""
    parts = resolve_subset(subset).split("+")
    return "fwd" in parts or "fwdface" in parts


def uses_forward_face(subset: str) -> bool:
    """Whether a (canonical) subset's forward-vector group is the face-up-weighted one (W4..W6)."""
    return "fwdface" in resolve_subset(subset).split("+")


def resolve_subset(subset: str) -> str:
    """Return the canonical subset name (``'all'`` -> ``'all52'``) or raise InputError."""
    key = SUBSET_ALIASES.get(subset, subset)
    if key not in FEATURE_SETS:
        allowed = ", ".join([*FEATURE_SETS, *SUBSET_ALIASES])
        raise InputError(f"unknown feature subset {subset!r}; use one of: {allowed}.")
    return key


def feature_names(subset: str = "all52") -> list[str]:
    """Column names of a named subset, in extraction order (F numbers ascending)."""
    return list(FEATURE_SETS[resolve_subset(subset)])


def feature_specs(subset: str = "all52") -> list[FeatureSpec]:
    """Catalogue entries of a named subset, in extraction order."""
    return [_BY_NAME[n] for n in feature_names(subset)]


def catalogue_markdown() -> str:
    """The markdown table committed as ``features/catalogue.md`` (deterministic)."""
    p34 = set(PAPER34_NUMBERS)
    lines = [
        "# Feature catalogue",
        "",
        "Generated by `python -m gaitml.features.catalogue --out features/catalogue.md`; do not edit by hand.",
        "",
        "The 52 time-domain features of paper 003 (Deng et al. 2021) sec. 3.2, in the paper's numbering.",
        "Channels: `acc_x`, `acc_y`, `acc_z` (m/s^2, gravity included) and `acc_mag`, the preprocessed",
        "magnitude a = |acc| - 9.8 m/s^2 (paper eq. 1) smoothed by a centred 3-sample moving average",
        "(paper sec. 2.1) within each window (2 samples at the window's first and last sample).",
        "`paper34` marks the 34 features of the paper's Table 1. Subset `all52+gyro` appends G1..G52,",
        "the same statistics on `gyr_x`, `gyr_y`, `gyr_z` (rad/s) and `gyr_mag` = |gyr| (same smoothing,",
        "no offset).",
        "",
        "Readings of the text: 三四分位距 (F29-32) = third quartile; quantiles by linear interpolation",
        "(type 7); variance, skewness, kurtosis from population moments, kurtosis in excess form",
        "(Gaussian = 0); 平均绝对误差 (F44-47) = mean absolute deviation about the mean; the mode",
        f"rounds values to bins of {MODE_BIN_WIDTH['acc']} m/s^2 ({MODE_BIN_WIDTH['gyr']} rad/s for gyro) and returns the",
        "centre of the fullest bin (ties: smallest); M4 and f(1) keep the paper's 1/N. Constant windows",
        "(std <= 1e-10 (1 + |mean|)) get skewness, kurtosis and correlation 0.",
        "",
        "Feature frame (`features.frame`, `gaitml features --frame`): `phone` (default, the paper's) uses the",
        "phone's x, y, z. `gravity` expresses each window in its own gravity-aligned frame: z up along the",
        "window mean of acc, y along the dominant horizontal direction (first principal axis), signed so that",
        "the acceleration along y follows the time derivative of the vertical one (walking: y = direction of",
        "travel), x = y cross z (right); the gyroscope is rotated with the same matrix. A constant rotation of",
        "the phone then changes no feature; F1-F2 (means of x, y) and F33 (x-y correlation) are 0 by",
        "construction. Column names are the same in both frames; a model records its frame. Method and limits:",
        "`gaitml/features/_frame.py`.",
        "",
        "| F | column | channel | statistic | formula | paper34 |",
        "|---|---|---|---|---|---|",
    ]
    for s in CATALOGUE:
        formula = s.formula.replace("|", "\\|")
        lines.append(f"| {s.code} | `{s.name}` | {s.channel} | {s.description} | {formula} | {'yes' if s.number in p34 else ''} |")
    lines += [
        "",
        "Gyro counterparts (subsets `all52+gyro`, `all52+gyro+fwd`, `all52+gyro+fwdface`): G<k> is F<k> computed on the gyroscope,",
        "column `gyr_<channel>__<stat>`, e.g. G1 = `gyr_x__mean`, G33 = `gyr_xy__corr`, G52 = `gyr_x__f1`.",
        "",
        "Forward vector (subsets `all52+fwd`, `all52+gyro+fwd`; not in paper 003): every feature above",
        "is the same for a window played backwards in time; W1..W3 are not. Per window: up = the unit window mean",
        f"of acc; each axis detrended and band-passed to {FORWARD_BAND_HZ[0]:g}-{FORWARD_BAND_HZ[1]:g} Hz (the window's Fourier coefficients",
        "outside the band zeroed); v = the band-passed acc along up, h = its horizontal part; v' = circular",
        "central difference of v; F = mean_t h(t) v'(t) / sqrt(mean |h|^2 mean v'^2), a horizontal vector of",
        "length <= 1 pointing along the direction of travel in walking (inverted pendulum: fastest at heel",
        "strike, where the vertical acceleration peaks). Columns: F along the phone's x, y, z (the feature",
        "frame's axes with `frame = gravity`). Method, sources and limits: `gaitml/features/_forward.py`.",
        "Subsets `all52+fwdface`, `all52+gyro+fwdface` carry W4..W6 instead: F times max(0, up_z), how face up",
        "the phone is (1 flat, 0 upright), so the group is near 0 where the phone's axes are not tied to the body.",
        "The shipped `models/demo` reads `all52+gyro+fwdface`; the default subset stays `all52`.",
        "",
        "| W | column | channel | statistic |",
        "|---|---|---|---|",
        *[f"| {s.code} | `{s.name}` | {s.channel} | {s.description} |" for s in FORWARD_CATALOGUE + FORWARD_FACE_CATALOGUE],
        "",
    ]
    return "\n".join(lines)


def write_catalogue(path) -> None:
    """Write :func:`catalogue_markdown` to ``path`` atomically."""
    from gaitml.io import write_text

    write_text(path, catalogue_markdown())


def main(argv: list[str] | None = None) -> int:
    """``python -m gaitml.features.catalogue [--out FILE]``: print or atomically write the catalogue."""
    ap = argparse.ArgumentParser(prog="python -m gaitml.features.catalogue", description="Print the feature catalogue (markdown).")
    ap.add_argument("--out", metavar="FILE", help="write atomically to FILE instead of stdout")
    args = ap.parse_args(argv)
    if args.out:
        write_catalogue(args.out)
    else:
        sys.stdout.write(catalogue_markdown())
    return 0
