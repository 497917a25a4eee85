"""Augmentation of real training recordings by physically valid variations of the grip: the phone turned in the hand about its swing axis, and the phone put into a pocket another way round.

A phone carried in a swinging hand (or in a hand pumping while running) turns mostly
about one axis: the axis of the arm's swing, across the walker's body. How the hand grips
the phone *about that axis* (top up, top down, top forward or back) is a free choice of the
walker that the swing itself does not depend on: the phone sits at the same place in the
hand and the hand moves the same way whichever way round it is held. Turning the phone
about the swing axis by an angle ``theta`` therefore changes the recording only by a fixed
rotation of the phone frame: the specific force and the angular rate are both rotated by
``R(axis, theta)`` (the small lever arm between the sensor and the centre of the grip is
neglected). Features computed in the phone frame (paper 003, sec. 3.2: per-axis
statistics of the accelerometer) do depend on it, so a model trained on a few people's
grips reads another grip of the same swing as another motion.

:func:`augmented_set` adds, for each real recording in the named carrying positions,
``copies`` rotated copies at angles spread over the full turn (a random offset per
recording, from the config's seed), so that the training data hold every grip about the
swing axis; with ``share_time`` the original and its copies share the recording's time (one
grip per stretch), so the position keeps its weight in training. The swing axis is
estimated per recording (:func:`swing_axis`): the principal axis of the angular rate
high-passed at :data:`SWING_AXIS_HIGHPASS_HZ` (the swing, not the walker's slow turns).
:func:`without_copies` gives the recordings back as they were (the training pipeline fits
the domain record on those: :func:`gaitml.pipeline.runner.fit_training_domain`).

A phone goes into a trouser pocket in four discrete ways: top up or top down, screen toward
the thigh or away from it. The four are related by the 180 deg turns about the phone's own
axes (:func:`flip_rotation`: about x, top and screen both reversed; about y, the screen
reversed, the top kept; about z, the top reversed, the screen kept), exact rigid rotations
of the phone frame, so the specific force and the angular rate are rotated alike (the phone
sits at the same place on the thigh; its few millimetres of thickness are neglected).
``flips`` adds, for each real recording in ``flip_positions``, the copies turned by the
named flips (with swing turns in the same position: every turned grip flipped too). Unlike
the swing turns, a flip needs no gyroscope (it does not estimate an axis).

A phone records at its own sampling rate: many log at 50-200 Hz, some (a smartwatch, a
logging app saving power) at 20 Hz. :func:`gaitml.models.predict_recording` brings every
recording to the model's rate (:func:`gaitml.models.resample_recording`: low-pass at 0.45 x the
new rate when down-sampling, then linear interpolation), so a 20 Hz recording reaches the
classifier with nothing above 9 Hz and its fast detail interpolated: features of the same walk
(paper 003 sec. 3.2: peaks, energies, spectral bins) differ from those at the training rate.
:func:`rate_copies` adds, for each recording and each rate of ``rates``, the copy a phone
recording at that rate would give the model: taken down to the rate and back up to the
model's, through exactly that resampling. A rate copy is an augmented copy like the others
(meta ``augmented``; its ``resampled_from_hz`` is the low rate): it trains the classifier, not
the domain record, and cross-validation does not score it.

A runner runs at their own tempo. Across recreational runners the preferred step frequency
spreads far more than one runner's does over a run (21 experienced recreational runners outdoors:
165 +- 8 steps/min at a comfortable 3.0 m/s, rising only 3 steps/min at a 15 % higher speed, Eur. J.
Sport Sci. 2019; Heiderscheit et al. 2011 ran 45 recreational runners at their preferred rate and
at +-5 % and +-10 % of it), and the phone on a
faster runner's thigh turns faster. :func:`tempo_copies` adds, for each real recording holding a
label of ``labels`` (``run``), the recording replayed at each tempo factor ``s``: the motion
``x(t)`` becomes ``x(s t)``, so the time axis is compressed by ``s`` (the copy is ``1/s`` as long,
at the same sampling rate), the angular rate is multiplied by ``s``, the linear acceleration by
``s**2``, the attitude path is the same path gone through faster, and gravity is unchanged. The
accelerometer's reading (gravity-up convention of the package: ``acc = a_lin + g_up_b``, ``g_up_b``
the phone-frame up vector times g) becomes ``s**2 (acc - g_up_b) + g_up_b``. ``g_up_b`` is taken
per sample from the package's attitude filter (:class:`gaitml.pdr.AttitudeEstimator`: the
gyroscope integrated, tilt corrected towards the low-passed gravity), which follows the thigh's
turns within a stride where a low-pass of the accelerometer cannot. Time-warped and
magnitude-scaled copies of wearable data as training augmentation: Um et al. 2017. A tempo copy
is meta ``augmented`` like the others (cross-validation does not score it) but, unlike them, it
is a motion a runner can make in a grip the walkers used, so by default it enters the domain record
(meta ``augment_in_domain``; :func:`without_copies` with ``keep_in_domain``): a faster runner
is then neither read by a model that never saw their tempo nor flagged for it. With
``in_domain=False`` the copies train the classifier only, like the other copies. ``positions``
limits the copies to recordings carried in the named positions (meta ``position``, e.g. tyrex's
``pocket``). Both are measured in experiments/reports/default-model.md ("Tempo copies of real
running, round 2"). In the hand, a slowed run lands on brisk walking with a swinging hand, and
copies in the domain record take its held-out thresholds with them; a run in a pocket does neither.

This is ours: the papers train on the grips their walkers used, at one rate.

References
----------
Preferred and heart-rate-optimal step frequency of 21 experienced recreational runners outdoors
(Vrije Universiteit Amsterdam), Eur. J. Sport Sci., 2019, doi:10.1080/17461391.2019.1626911.
B. C. Heiderscheit, E. S. Chumanov, M. P. Michalski, C. M. Wille, M. B. Ryan, "Effects of step rate
manipulation on joint mechanics during running", Med. Sci. Sports Exerc. 43(2):296-302, 2011.
T. T. Um, F. M. J. Pfister, D. Pichler, S. Endo, M. Lang, S. Hirche, U. Fietzek, D. Kulic, "Data
augmentation of wearable sensor data for Parkinson's disease monitoring using convolutional
neural networks", ICMI 2017 (time-warping and magnitude-warping augmentation).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from gaitml.errors import InputError

__all__ = [
    "FLIP_AXES",
    "POCKET_POSITIONS",
    "SWING_AXIS_HIGHPASS_HZ",
    "SWING_POSITIONS",
    "SHARE_BLOCK_S",
    "TEMPO_LABELS",
    "TEMPO_LIMITS",
    "augment_recordings",
    "phone_up_gravity",
    "tempo_copies",
    "tempo_recording",
    "rate_copies",
    "augmented_set",
    "without_copies",
    "axis_rotation",
    "flip_rotation",
    "rotate_recording",
    "swing_axis",
]

#: high-pass corner (Hz) applied to the angular rate before its principal axis is taken: above
#: the walker's turns (a room loop, well under 0.2 Hz), below the slowest stride of a swinging arm
#: (about 0.5 Hz at 1 stride/s)
SWING_AXIS_HIGHPASS_HZ = 0.4
#: the default carrying positions (``meta["position"]`` of the tyrex folder source) given copies: the swinging hand
#: (walking). The running hand (tyrex ``hand``: a pumping, swinging hand) swings too and may be named explicitly.
SWING_POSITIONS = ("swinging-hand",)
#: the phone axes a pocket flip turns about by 180 deg (:func:`flip_rotation`)
FLIP_AXES = ("x", "y", "z")
#: the default carrying positions (``meta["position"]`` of the tyrex folder source) given pocket flips: the front and
#: back trouser pockets (walking) and the pocket of the running recordings
POCKET_POSITIONS = ("front-pocket", "back-pocket", "pocket")


def swing_axis(gyr: np.ndarray, sampling_rate_hz: float, highpass_hz: float = SWING_AXIS_HIGHPASS_HZ) -> np.ndarray:
    """The phone-frame unit axis the phone turns about most: the principal axis of the high-passed angular rate.

    Parameters
    ----------
    gyr : (n, 3) angular rate (rad/s), phone frame.
    sampling_rate_hz : its rate.
    highpass_hz : the corner of the 2nd-order Butterworth high-pass (zero phase) that removes the walker's turns.

    Returns
    -------
    (3,) unit vector (its sign is arbitrary: a rotation about it covers the full turn either way).
    """
    from scipy.signal import butter, sosfiltfilt

    g = np.asarray(gyr, dtype=float)
    if g.ndim != 2 or g.shape[1] != 3 or len(g) < 4:
        raise InputError("swing_axis needs an (n, 3) angular rate with n >= 4 samples; pass the recording's gyroscope.")
    sos = butter(2, highpass_hz, btype="highpass", fs=sampling_rate_hz, output="sos")
    padlen = min(len(g) - 1, 3 * (2 * len(sos) + 1))
    h = sosfiltfilt(sos, g, axis=0, padlen=padlen)
    _, vec = np.linalg.eigh(h.T @ h)
    return vec[:, -1]


def axis_rotation(axis: Sequence[float], theta_rad: float) -> np.ndarray:
    """The 3x3 rotation matrix by ``theta_rad`` about the unit ``axis`` (Rodrigues' formula)."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(theta_rad) * K + (1.0 - np.cos(theta_rad)) * (K @ K)


def flip_rotation(axis: str) -> np.ndarray:
    """The 180 deg turn of the phone about its own ``axis`` ("x", "y" or "z"): a proper rotation (determinant +1).

    About x (across the screen): top and screen both reversed; about y (along the phone, top up):
    the screen reversed; about z (the screen normal): the top reversed. With the identity, the
    four ways a phone lies flat in a pocket.
    """
    if axis not in FLIP_AXES:
        raise InputError(f"a pocket flip turns about the phone's x, y or z axis, got {axis!r}; use one of {', '.join(FLIP_AXES)}.")
    d = -np.ones(3)
    d[FLIP_AXES.index(axis)] = 1.0
    return np.diag(d)


def rotate_recording(rec, R: np.ndarray, note: str):
    """``rec`` seen by a phone turned by ``R`` (phone frame): accelerometer and gyroscope rotated, ``meta["augmented"] = note``.

    Phone-frame references (orientation truth) would no longer hold and are dropped.
    """
    R = np.asarray(R, dtype=float)
    prev = rec.meta.get("augmented")  # a tempo copy turned: both notes
    full = f"{note}, {prev}" if prev else note
    meta = {**rec.meta, "augmented": full, "id": f"{rec.meta.get('id', rec.meta.get('session', 'recording'))} [{note}]"}
    meta.pop("augment_in_domain", None)  # a turned grip is no grip the walkers used (fit_training_domain)
    return rec.replace(
        acc=rec.acc @ R.T,
        gyr=None if rec.gyr is None else rec.gyr @ R.T,
        meta=meta,
        reference={},
        check_units=False,
    )


#: length (s) of the stretches a recording is cut into when its grips share its time (``share_time``): two
#: 1.5 s windows at 50 % overlap, so that most windows lie within one grip
SHARE_BLOCK_S = 3.0


def _check_flips(flips: Sequence[str]) -> tuple[str, ...]:
    flips = tuple(flips)
    bad = [f for f in flips if f not in FLIP_AXES]
    if bad:
        raise InputError(f"pocket flips name the phone axes {', '.join(FLIP_AXES)}, got {bad[0]!r}; fix the list.")
    if len(set(flips)) != len(flips):
        raise InputError(f"pocket flips list an axis twice ({list(flips)}); list each of {', '.join(FLIP_AXES)} at most once.")
    return flips


def _plans(recs, copies, positions, seed, highpass_hz, flips, flip_positions) -> list:
    """Per recording: ``None`` (no copy) or ``(grips, shift)``, ``grips`` the (rotation, note) of every copy, in order.

    The swing-turn draws (offset, grip shift) come from ``default_rng(seed)`` in the same order
    whatever the flips, so that a config without flips gives the copies it gave before flips existed;
    a flipped recording draws its grip shift from a second stream.
    """
    if copies < 0:
        raise InputError(f"augmentation copies must be >= 0, got {copies}; use 0 for none.")
    flips = _check_flips(flips)
    want, want_flip = set(positions), set(flip_positions)
    rng = np.random.default_rng(seed)
    rng_flip = np.random.default_rng([seed, _FLIP_STREAM])
    plans = []
    for rec in recs:
        grips = []
        shift = 0
        if copies > 0:
            u = rng.uniform(-0.5, 0.5)  # drawn for every recording so that a position list does not shift the others
            shift = int(rng.integers(copies + 1))
            if rec.gyr is not None and str(rec.meta.get("position", "")) in want:
                axis = swing_axis(rec.gyr, rec.sampling_rate_hz, highpass_hz)
                for k in range(1, copies + 1):
                    theta = 2.0 * np.pi * (k + u) / (copies + 1)
                    grips.append((axis_rotation(axis, theta), f"turned {np.degrees(theta):.0f} deg about the swing axis"))
        if flips:
            v = rng_flip.uniform()
            if str(rec.meta.get("position", "")) in want_flip:
                base = [(np.eye(3), ""), *grips]
                for f in flips:
                    F = flip_rotation(f)
                    for R, note in base:
                        grips.append((F @ R, f"flipped about {f}" + (f", {note}" if note else "")))
                shift = int(v * (len(grips) + 1))
        plans.append((grips, shift) if grips else None)
    return plans


#: the random stream (with the seed) of the pocket flips' grip shifts, apart from the swing turns' draws
_FLIP_STREAM = 1


def augment_recordings(
    recs: Sequence,
    copies: int,
    positions: Iterable[str] = SWING_POSITIONS,
    seed: int = 0,
    highpass_hz: float = SWING_AXIS_HIGHPASS_HZ,
    share_time: bool = False,
    block_s: float = SHARE_BLOCK_S,
    flips: Sequence[str] = (),
    flip_positions: Iterable[str] = POCKET_POSITIONS,
) -> list:
    """Rotated copies of the recordings: turned about the swing axis (``positions``) and/or flipped (``flip_positions``).

    Swing turns: ``copies`` per recording in ``positions``, at angles ``2 pi (k + u) / (copies + 1)``,
    ``k = 1..copies``, with one offset ``u`` uniform in [-0.5, 0.5) per recording (``seed``): with the
    original, ``copies + 1`` grips spread over the full turn. Recordings without a gyroscope get no
    turned copy.

    Pocket flips: for each axis in ``flips`` (of :data:`FLIP_AXES`), every recording in
    ``flip_positions`` also enters turned by :func:`flip_rotation` of that axis; a recording that
    is turned about its swing axis too has each of its grips flipped (``(1 + copies) (1 + len(flips))``
    grips in all).

    ``share_time``: the original and its copies share the recording's time instead of each
    holding all of it, as if the walker changed grip every ``block_s`` seconds: the recording is
    cut into stretches of ``block_s``, stretch ``j`` keeps its labels in grip ``(j + s) mod
    n_grips`` (``s`` random per recording; grip 0 is the original) and is ``unlabelled`` in
    the others. The position then keeps its number of training windows (its weight against the
    other positions and modes); without it, it counts ``n_grips`` times.

    Returns the copies only. With ``share_time`` the originals must give up the copies' stretches
    too: use :func:`augmented_set`, which does both with the same draws.
    """
    plans = _plans(recs, copies, positions, seed, highpass_hz, flips, flip_positions)
    return _copies(recs, plans, share_time, block_s)


def _copies(recs, plans, share_time, block_s) -> list:
    out = []
    for rec, plan in zip(recs, plans, strict=True):
        if plan is None:
            continue
        grips, shift = plan
        for k, (R, note) in enumerate(grips, start=1):
            c = rotate_recording(rec, R, note)
            if share_time:  # one grip per stretch: the copy holds only its stretches
                meta = {**c.meta, "augmented_shares_time": True}
                c = c.replace(labels=_grip_labels(rec, k, len(grips) + 1, shift, block_s), meta=meta, check_units=False)
            out.append(c)
    return out


def _grip_labels(rec, grip: int, n_grips: int, shift: int, block_s: float) -> np.ndarray:
    """``rec``'s labels in the stretches of ``block_s`` that belong to ``grip`` (of ``n_grips``), ``unlabelled`` elsewhere."""
    from gaitml.labels import UNLABELLED

    if rec.labels is None:
        raise InputError(f"{rec.name}: sharing a recording's time between grips needs its labels; label it first.")
    block = max(1, int(round(block_s * rec.sampling_rate_hz)))
    owner = (np.arange(rec.n_samples) // block + shift) % n_grips
    lab = np.asarray(rec.labels, dtype=object)
    return np.where(owner == grip, lab, UNLABELLED).astype(object)


def augmented_set(
    recs: Sequence,
    copies: int,
    positions: Iterable[str] = SWING_POSITIONS,
    seed: int = 0,
    share_time: bool = False,
    block_s: float = SHARE_BLOCK_S,
    flips: Sequence[str] = (),
    flip_positions: Iterable[str] = POCKET_POSITIONS,
) -> tuple[list, list]:
    """``recs`` with the rotated copies of :func:`augment_recordings`: ``(recordings, copies)``.

    Without ``share_time`` the recordings are ``recs`` unchanged plus the copies; with it the
    originals that have copies keep only their own grip's stretches (the same draws as the
    copies), so that every stretch of the recording is trained once, in one grip; their full
    labels are kept in ``meta["augment_full_labels"]`` (:func:`without_copies` restores them).
    """
    plans = _plans(recs, copies, positions, seed, SWING_AXIS_HIGHPASS_HZ, flips, flip_positions)
    extra = _copies(recs, plans, share_time, block_s)
    if not share_time or not extra:
        return [*recs, *extra], extra
    out = []
    for rec, plan in zip(recs, plans, strict=True):
        if plan is None:
            out.append(rec)
        else:
            grips, shift = plan
            # the full labels stay in the meta: the domain record is fitted on the recording as it was
            meta = {**rec.meta, "augment_full_labels": rec.labels}
            out.append(rec.replace(labels=_grip_labels(rec, 0, len(grips) + 1, shift, block_s), meta=meta, check_units=False))
    return [*out, *extra], extra


def rate_copies(recs: Sequence, rates: Iterable[float]) -> list:
    """Copies of ``recs`` as phones recording at each of ``rates`` (Hz) would give them to the model.

    Each recording (at the model's rate) is taken down to the rate and back up to its own rate with
    :func:`gaitml.models.resample_recording`, the resampling :func:`gaitml.models.predict_recording`
    applies to an input at another rate (low-pass at 0.45 x the low rate, then linear
    interpolation; labels sample-and-hold both ways). Every rate must lie below the recordings'
    rate. A copy's meta: ``augmented`` (e.g. ``"recorded at 20 Hz"``), ``augment_rate_hz``, and
    ``resampled_from_hz`` the low rate (the rate its information comes from); its references
    (truth at the original samples) are dropped. Copies of copies (the rotated grips) are made
    alike, so every grip is also seen at every rate. Returns the copies only, recording by
    recording, rate by rate.
    """
    from gaitml.models import resample_recording

    rates = [float(r) for r in rates]
    out = []
    for rec in recs:
        fs = float(rec.sampling_rate_hz)
        for r in rates:
            if not 0.0 < r < fs:
                raise InputError(f"a rate copy goes down to a rate below the recording's {fs:g} Hz, got {r:g} Hz; list rates below it.")
            low = resample_recording(rec, r)
            up = resample_recording(low, fs)
            n = min(up.n_samples, rec.n_samples)
            note = f"recorded at {r:g} Hz"
            prev = rec.meta.get("augmented")
            meta = {
                **rec.meta,
                "augmented": f"{prev}, {note}" if prev else note,
                "augment_rate_hz": r,
                "resampled_from_hz": r,
                "id": f"{rec.meta.get('id', rec.meta.get('session', 'recording'))} [{note}]",
            }
            meta.pop("augment_in_domain", None)  # the domain record holds the model's rate only
            # the grid back up may end a sample short of the original's; keep the original's labels sample for sample
            labels = None if rec.labels is None else np.asarray(rec.labels, dtype=object)[:n]
            out.append(
                rec.replace(
                    acc=up.acc[:n],
                    gyr=None if up.gyr is None else up.gyr[:n],
                    labels=labels,
                    meta=meta,
                    reference={},
                    check_units=False,
                )
            )
    return out


def without_copies(recs: Sequence, groups: Sequence, *, keep_in_domain: bool = False) -> tuple[list, list]:
    """The recordings as they were before :func:`augmented_set`: copies dropped, shared originals given back their full labels.

    ``keep_in_domain``: the copies marked ``augment_in_domain`` (the tempo copies of
    :func:`tempo_copies`, not turned, flipped or at another rate) are kept: what the domain record
    is fitted on. Cross-validation scores the recordings without them.
    """
    out, out_groups = [], []
    for r, g in zip(recs, groups, strict=True):
        if r.meta.get("augmented") and not (keep_in_domain and r.meta.get("augment_in_domain")):
            continue
        full = r.meta.get("augment_full_labels")
        if full is not None:
            meta = {k: v for k, v in r.meta.items() if k != "augment_full_labels"}
            r = r.replace(labels=full, meta=meta, check_units=False)
        out.append(r)
        out_groups.append(g)
    return out, out_groups


#: the per-sample labels whose recordings get tempo copies by default: running (the tyrex RunningHand and
#: RunningPocket recordings carry ``run`` where the runner moves, ``still`` elsewhere)
TEMPO_LABELS = ("run",)
#: the tempo factors accepted (exclusive bounds): within a factor of 2 either way, far beyond the spread of
#: recreational runners' step frequency (165 +- 8 steps/min, Eur. J. Sport Sci. 2019) and short of a tempo at
#: which the recording's content (up to 0.45 x its rate) would be mostly filtered away
TEMPO_LIMITS = (0.5, 2.0)


def phone_up_gravity(rec) -> np.ndarray:
    """Gravity as the accelerometer reads it at rest, in the phone frame, per sample: (n, 3) m/s^2 along the phone's up.

    From the package's attitude filter (:class:`gaitml.pdr.AttitudeEstimator` at its defaults: the
    gyroscope integrated, gyroscope bias from still stretches tracked online, tilt pulled towards the
    low-passed gravity at 0.5 1/s), ``R_k^T (0, 0, g)`` with ``R_k`` the phone-to-navigation attitude of
    sample ``k``. It follows turns within a stride (a thigh in a pocket turns by tens of degrees each
    stride) that a low-pass of the accelerometer would average away. Needs the gyroscope.
    """
    from gaitml.consts import GRAVITY_MS2
    from gaitml.pdr.attitude import AttitudeEstimator

    if rec.gyr is None:
        raise InputError(f"{rec.name}: the phone's gravity along its turns needs the gyroscope; this recording has none.")
    est = AttitudeEstimator().estimate(rec)
    return est.rotation_.inv().apply(np.array([0.0, 0.0, GRAVITY_MS2]))


def _check_tempo(factors) -> list[float]:
    out = []
    for f in factors:
        if isinstance(f, bool) or not isinstance(f, int | float) or not TEMPO_LIMITS[0] < float(f) < TEMPO_LIMITS[1]:
            raise InputError(
                f"a tempo factor is a number between {TEMPO_LIMITS[0]:g} and {TEMPO_LIMITS[1]:g} (exclusive), got {f!r}; "
                "list factors such as 0.87, 1.15."
            )
        if float(f) == 1.0:
            raise InputError("a tempo factor of 1 is the recording itself; list factors other than 1.")
        out.append(float(f))
    if len(set(out)) != len(out):
        raise InputError(f"tempo factors list a factor twice ({out}); list each at most once.")
    return out


def tempo_recording(rec, factor: float, gravity_up_b: np.ndarray | None = None, *, in_domain: bool = True):
    """``rec`` replayed at tempo ``factor``: the motion ``x(t)`` as ``x(factor t)``, at ``rec``'s own sampling rate.

    Parameters
    ----------
    rec : Recording with a gyroscope (or ``gravity_up_b`` given).
    factor : the tempo ``s`` (> 1 faster, < 1 slower).
    gravity_up_b : (n, 3) gravity in the phone frame as the accelerometer reads it at rest (m/s^2), per sample
        of ``rec``; default :func:`phone_up_gravity`.
    in_domain : mark the copy ``augment_in_domain`` (the domain record keeps it); False: it trains the
        classifier only, like the turned, flipped and rate copies.

    Returns
    -------
    Recording of ``floor((n - 1) / s) + 1`` samples: sample ``k`` is the original's motion at
    ``t = s k / fs``, with angular rate ``s gyr`` and specific force ``s**2 (acc - g_up_b) + g_up_b``
    (linear interpolation between the original samples; for ``s > 1`` the original is first
    low-passed at ``0.45 fs / s`` (4th-order Butterworth, zero phase), so that nothing above
    0.45 x the rate reaches the copy, as :func:`gaitml.models.resample_recording` does when it
    down-samples). Labels follow the time axis (sample and hold). Meta ``augmented`` (``"tempo
    1.15x"``), ``augment_tempo`` and, with ``in_domain``, ``augment_in_domain``; references (truth on
    the original's time axis) are dropped.
    """
    from gaitml.models._dataset import ANTI_ALIAS_FRACTION
    from gaitml.signal import lowpass

    s = _check_tempo([factor])[0]
    fs = float(rec.sampling_rate_hz)
    acc = np.asarray(rec.acc, dtype=float)
    g_b = phone_up_gravity(rec) if gravity_up_b is None else np.asarray(gravity_up_b, dtype=float)
    if g_b.shape != acc.shape:
        raise InputError(f"`gravity_up_b` must have the accelerometer's shape {acc.shape}, got {g_b.shape}; give one vector per sample.")
    acc_s = s**2 * (acc - g_b) + g_b
    gyr_s = None if rec.gyr is None else s * np.asarray(rec.gyr, dtype=float)
    n = rec.n_samples
    if s > 1.0 and n > 15:  # the copy's content is the original's times s: keep it below 0.45 fs
        acc_s = lowpass(acc_s, ANTI_ALIAS_FRACTION * fs / s, fs)
        gyr_s = None if gyr_s is None else lowpass(gyr_s, ANTI_ALIAS_FRACTION * fs / s, fs)
    n_new = int(np.floor((n - 1) / s + 1e-9)) + 1
    pos = s * np.arange(n_new)  # the copy's samples on the original's sample axis
    i0 = np.minimum(np.floor(pos + 1e-9).astype(np.int64), n - 1)
    i1 = np.minimum(i0 + 1, n - 1)
    w = (pos - i0)[:, None]

    def warp(x):
        return (1.0 - w) * x[i0] + w * x[i1]

    note = f"tempo {s:g}x"
    prev = rec.meta.get("augmented")
    meta = {
        **{k: v for k, v in rec.meta.items() if k != "augment_in_domain"},
        "augmented": f"{prev}, {note}" if prev else note,
        "augment_tempo": s,
        "id": f"{rec.meta.get('id', rec.meta.get('session', 'recording'))} [{note}]",
    }
    if in_domain:
        meta["augment_in_domain"] = True
    labels = None if rec.labels is None else np.asarray(rec.labels, dtype=object)[i0]
    return rec.replace(
        acc=warp(acc_s),
        gyr=None if gyr_s is None else warp(gyr_s),
        labels=labels,
        meta=meta,
        reference={},
        check_units=False,
    )


def tempo_copies(
    recs: Sequence,
    factors: Iterable[float],
    labels: Iterable[str] = TEMPO_LABELS,
    *,
    positions: Iterable[str] | None = None,
    in_domain: bool = True,
) -> list:
    """Tempo copies (:func:`tempo_recording`) of the recordings in ``recs`` whose per-sample labels hold one of ``labels``.

    One copy per such recording and factor, recording by recording, factor by factor; the phone's
    gravity is estimated once per recording (:func:`phone_up_gravity`). Recordings without a
    gyroscope get none (their gravity along the turns is unknown): the caller reports it.
    ``positions``: only recordings whose meta ``position`` is one of them (None: any position).
    ``in_domain``: passed to :func:`tempo_recording`. Returns the copies only.
    """
    factors = _check_tempo(list(factors))
    want = set(labels)
    where = None if positions is None else {str(p) for p in positions}
    out = []
    for rec in recs:
        if rec.gyr is None or rec.labels is None or not want.intersection(np.unique(np.asarray(rec.labels, dtype=object).astype(str))):
            continue
        if where is not None and str(rec.meta.get("position", "")) not in where:
            continue
        g_b = phone_up_gravity(rec)
        out.extend(tempo_recording(rec, s, g_b, in_domain=in_domain) for s in factors)
    return out
