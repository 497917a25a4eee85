"""Carrying positions: which body segment moves the phone, and how the phone sits in it.

The hand-held phone in front of the body (``hand-flat``, ``hand-tilted``) is
:mod:`.sensor`'s; this module adds the other ways people carry a phone. Each
position follows the body segment that carries it; the segment's motion is a
kinematic model driven by the same gait (step phase, mode, heading) as the body
acceleration of :mod:`.modes`. The ranges every model draws its parameters from
are in :meth:`Placement.random` and the constants below; the fits behind them and
their realism are in ``experiments/reports/simulator-positions.md``.

- ``front-pocket`` (trouser front pocket) and ``back-pocket``: the phone
  rotates with the *thigh* of one leg. The thigh's sagittal angle
  (flexion +) follows a stride-periodic curve: most flexed at that leg's heel
  strike, most extended just before toe-off, flexing again in swing (Winter,
  *Biomechanics and Motor Control of Human Movement*, 4th ed., ch. 4 joint
  angles). Only one leg carries the phone, so the rotation (and the gravity
  direction in the phone) repeats once per *stride* (two steps). Walking
  backwards runs the pattern in reverse: the foot lands behind the body with
  the thigh extended and the thigh flexes during stance, so the thigh's pitch
  rate in stance changes sign. Side steps move the thigh sideways (ab-/adduction,
  one cycle per side step).
- ``back-pocket``: the phone lies on the buttock's surface near the hip joint (a
  shorter lever), which faces backward and down whichever way up the phone is
  (so the screen's normal, not the phone's top, decides the sign of gravity on
  the phone's z axis). The buttock's surface belongs to the pelvis and the
  gluteal tissue more than to the thigh, so its rotation is a blend,
  ``(1 - pelvis_share)`` times the thigh's (with a smaller amplitude than the
  front pocket's) plus ``pelvis_share`` times the pelvis's (the belt's model
  below); a loose pocket also lets the phone turn in the screen's plane
  (``pocket_roll_deg``). Both are drawn over :data:`BACK_POCKET_RANGE`.
  **Turning in the pocket** (``pocket_turn_deg``): the loose phone also turns
  about itself, irregularly, while its carrier moves: a small rotation (band-
  limited noise in :data:`POCKET_TURN_BAND_HZ`, standard deviation
  ``pocket_turn_deg`` per axis, zero when standing) between the buttock's surface
  and the phone. Real back-pocket phones (motion capture) turn several times more
  than the pelvis does while their acceleration keeps the pelvis's step rhythm,
  and their rotation is not locked to the stride or the step: an irregular
  turning reproduces both (:data:`POCKET_TURN_DEG_RANGE`).
  **The one-sided step** (``stance_gate``): the gluteus maximus and medius of
  the carrying side are active from terminal swing through the loading response
  (Perry & Burnfield, *Gait Analysis: Normal and Pathological Function*, the
  hip's muscle activity in gait): in that leg's stance the buttock's tissue under
  the phone is stiff and passes the trunk's acceleration to it; in that leg's
  swing the relaxed tissue (and the loose pocket) isolates the phone from much
  of it. So the trunk's acceleration at a back-pocket phone (:func:`stance_gate`)
  is multiplied by 1 in the carrying leg's step and by ``1 - stance_gate`` in the
  other's, with edges of :data:`STANCE_GATE_EDGE` of a step at each heel strike.
  Being constant within a step, the gate keeps each step's net velocity change
  zero; the heel-strike impacts stay one-sided (``other_leg_impact``). Drawn last
  of all over :data:`STANCE_GATE_RANGE`.
- ``belt`` (waist clip): the phone follows the *pelvis*: the trunk bounce
  and sway of :mod:`.modes` plus the pelvic rotations of gait: transverse
  rotation (yaw) and obliquity (roll) at the stride frequency and anterior
  tilt (pitch) at the step frequency, on a lever of the waist radius at a
  random azimuth around the waist.
- ``swinging-hand``: the hand hangs and the arm swings as a pendulum about the
  shoulder at the stride frequency, in counter-phase with the leg on the same
  side (the arm is forward when the other leg's heel strikes), with a large
  pitch rotation (``arm_swing_deg``) and the centripetal and tangential
  acceleration of the arm's lever (``lever_m``; :data:`RUN_ARM_LEVER` of it when
  running, the elbow bent); the grip (the phone's angle in the hand) is random.
- ``bag`` (shoulder bag / backpack): the bag is a damped, delayed
  spring-pendulum driven by the trunk: its acceleration is the trunk's passed
  through a second-order system (natural frequencies ``bag_vertical_hz``, which
  amplifies the step bounce, and a lower ``bag_horizontal_hz``; the horizontal
  part saturating near :data:`BAG_SWING_LIMIT_MS2`), and it tilts like a
  pendulum by the filtered horizontal acceleration over g; the phone lies in
  the bag at a uniformly random orientation.

Per subject and position a :class:`Placement` is drawn (side of the body,
the phone's orientation in the segment: upright or upside down, screen
towards or away from the body, small random tilts; the segment's motion
amplitudes and lever). The phone's attitude is
``R(t) = Rz(-theta + yaw_s) Rx(pitch_s) Ry(roll_s) M`` (person heading, the
segment's own rotation, the constant mount ``M`` whose columns are the phone
axes in segment coordinates). As in :mod:`.sensor` the accelerometer reads
``R^T (a + g z_up)`` with ``a`` the body acceleration plus the lever arm's
``d^2/dt^2 (R_seg r)``, and the gyroscope the body rate of the same ``R``
(:func:`~gaitml.simulate.sensor.body_rates` of the segment chain, rotated by
``M^T``), so gravity and the gyroscope agree (integrating the noise-free
gyroscope reproduces the attitude).

Randomness: the placement and the carried-phone noise come from their own
generators (spawned children of the recording's seed), so the hand-held
path keeps its random stream.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import scipy.signal

from gaitml.consts import GRAVITY_MS2, MOTION_MODES
from gaitml.errors import InputError
from gaitml.simulate.sensor import band_noise, body_rates, nav_to_phone, smooth_noise

__all__ = [
    "POSITIONS",
    "HAND_POSITIONS",
    "CARRIED_POSITIONS",
    "Placement",
    "VIGOUR_RANGE",
    "BACK_POCKET_RANGE",
    "ARM_SWING_DEG_RANGE",
    "POCKET_TURN_DEG_RANGE",
    "POCKET_TURN_BAND_HZ",
    "STANCE_GATE_RANGE",
    "stance_gate",
    "check_positions",
    "carried_signals",
    "rotation_matrices",
    "quaternions",
]

#: Carrying positions the simulator knows (``gaitml simulate --positions``,
#: ``data.simulated.positions``). ``hand-flat`` / ``hand-tilted`` are the
#: hand-held phone of :mod:`.sensor` (unchanged); the others are this module's.
POSITIONS = ("hand-flat", "hand-tilted", "front-pocket", "back-pocket", "belt", "swinging-hand", "bag")
#: Hand-held positions -> the subject's phone pose.
HAND_POSITIONS = {"hand-flat": "flat", "hand-tilted": "tilted"}
#: Positions carried by a body segment (this module).
CARRIED_POSITIONS = tuple(p for p in POSITIONS if p not in HAND_POSITIONS)

_MODE_INDEX = {m: i for i, m in enumerate(MOTION_MODES)}
_DEG = np.pi / 180.0
#: Soft-tissue wobble of a carried phone after a heel strike (thigh and buttock tissue,
#: a loose pocket): natural frequency (Hz) and damping ratio.
WOBBLE_HZ = 9.0
WOBBLE_DAMPING = 0.2
#: Stride-to-stride variation of the segment's rotation amplitude (log-normal sd, correlation 1.5 s).
SEGMENT_AMP_CV = 0.15
#: The bag's horizontal acceleration saturates at about this (m/s^2): the strap and the body stop it.
BAG_SWING_LIMIT_MS2 = 4.0
#: Running: the elbow is bent (about 90 deg), so the hand is this fraction of the arm's length from the shoulder.
RUN_ARM_LEVER = 0.55
#: Ranges (log-uniform) of :attr:`Placement.vigour` per carried position: how vigorously the
#: subject walks, as the carrying segment feels it, relative to the placement's other ranges.
#: Fitted to the walking ``|acc|`` spread of the real Oxford walks in each position by
#: ``python -m experiments.scripts.carry_vigour`` (``experiments/reports/simulator-positions.md``,
#: "Vigour of carried walks"). Positions without an entry keep vigour 1 and draw nothing.
VIGOUR_RANGE = {"front-pocket": (0.7, 1.8), "back-pocket": (1.2, 1.75), "bag": (0.95, 1.1)}
#: Ranges (uniform) of the back pocket's own fields, drawn after the vigour (:meth:`Placement.random`):
#: ``pelvis_share``, how much the buttock follows the pelvis instead of the thigh (0: the thigh's
#: rotation only; 1: the pelvis's only), and ``pocket_roll_deg``, an extra in-plane turn of the phone
#: in the pocket (deg, added to ``tilt_z_deg``). The share is fitted jointly with the one-sided step
#: by ``python -m experiments.scripts.back_pocket`` (report sections "Back pocket: pelvis and roll"
#: and "Back pocket: the one-sided step"); patch the ranges with
#: ``experiments.scripts.back_pocket.back_pocket_ranges``.
BACK_POCKET_RANGE = {"pelvis_share": (0.8, 1.0), "pocket_roll_deg": (0.0, 0.0)}
#: Range (uniform) of the back pocket's :attr:`Placement.stance_gate`, drawn last of all its fields
#: (:meth:`Placement.random`): how much less of the trunk's acceleration the phone feels in the
#: other leg's step than in the carrying leg's (module docstring, "the one-sided step"); 0: no gate.
#: Fitted with ``pelvis_share`` by ``python -m experiments.scripts.back_pocket``.
STANCE_GATE_RANGE = (1.0, 1.0)
#: Half-width of the gate's edges (in steps) around each heel strike: the tissue stiffens and
#: relaxes over about a tenth of a step (loading response), not at once.
STANCE_GATE_EDGE = 0.1
#: The pelvis's rotation amplitudes (deg) drawn for the back pocket (the belt's ranges): transverse
#: rotation, obliquity, anterior tilt.
BACK_POCKET_PELVIS_DEG = {"yaw": (3.0, 6.0), "roll": (3.0, 6.0), "pitch": (1.0, 3.0)}
#: Range (uniform, deg) of the back pocket's :attr:`Placement.pocket_turn_deg`, drawn after every
#: other field of the back pocket: the loose phone turns in the pocket, irregularly, while its
#: carrier moves (module docstring). Fitted to the phone's rotation in real back pockets (the rate
#: about the horizontal and the swing of the tilt, motion capture, tyrex; each person held out in
#: turn) by ``python -m experiments.scripts.realism_tyrex`` (``experiments/reports/simulator-tyrex.md``).
POCKET_TURN_DEG_RANGE = (1.5, 4.5)
#: The band (Hz) of that turning: the gait's band, from half the stride frequency to a few step
#: harmonics. A slower turning (0.5-1.5 Hz) matches the real pockets' rotation a little better but
#: moves the acceleration's power from the step to the stride frequency, against the step rhythm of
#: real back pockets (``experiments/reports/simulator-tyrex.md``).
POCKET_TURN_BAND_HZ = (0.5, 4.0)
#: Range (uniform, deg) of the swinging hand's :attr:`Placement.arm_swing_deg`, the arm's pitch
#: amplitude about the shoulder in walking.
ARM_SWING_DEG_RANGE = (10.0, 25.0)


def check_positions(positions) -> tuple[str, ...]:
    """Validate carrying positions (a sequence or a comma-separated string).

    Underscores are accepted for hyphens (``front_pocket`` = ``front-pocket``).
    Returns the names without duplicates, in the given order.
    """
    if isinstance(positions, str):
        positions = [p for p in positions.split(",")]
    names = tuple(str(p).strip().lower().replace("_", "-") for p in positions)
    names = tuple(p for p in names if p)
    if not names:
        raise InputError(f"no carrying position given; choose from {', '.join(POSITIONS)}.")
    bad = [p for p in names if p not in POSITIONS]
    if bad:
        raise InputError(f"unknown carrying position {bad[0]!r}; choose from {', '.join(POSITIONS)}.")
    return tuple(dict.fromkeys(names))


# ---------------------------------------------------------------------- rotations
def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rotation_matrices(yaw, pitch, roll, mount: np.ndarray | None = None) -> np.ndarray:
    """Attitudes ``Rz(yaw) Rx(pitch) Ry(roll) M`` (n, 3, 3), phone -> navigation frame."""
    yaw, pitch, roll = (np.asarray(v, dtype=float) for v in (yaw, pitch, roll))
    n = len(yaw)
    cz, sz, cx, sx, cy, sy = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch), np.cos(roll), np.sin(roll)
    z, o = np.zeros(n), np.ones(n)
    rz = np.stack([np.stack([cz, -sz, z], -1), np.stack([sz, cz, z], -1), np.stack([z, z, o], -1)], 1)
    rx = np.stack([np.stack([o, z, z], -1), np.stack([z, cx, -sx], -1), np.stack([z, sx, cx], -1)], 1)
    ry = np.stack([np.stack([cy, z, sy], -1), np.stack([z, o, z], -1), np.stack([-sy, z, cy], -1)], 1)
    r = rz @ rx @ ry
    return r if mount is None else r @ mount


def quaternions(r: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(w, x, y, z)`` (n, 4) of rotation matrices (n, 3, 3), ``w >= 0``."""
    from scipy.spatial.transform import Rotation

    q = Rotation.from_matrix(r).as_quat()  # x, y, z, w
    q = np.column_stack([q[:, 3], q[:, :3]])
    return q * np.where(q[:, :1] < 0, -1.0, 1.0)


def _mount(y_axis, z_axis, tilt_deg) -> np.ndarray:
    """Mount matrix: columns are the phone's x, y, z axes in segment coordinates, then tilted in the phone frame."""
    y = np.asarray(y_axis, dtype=float)
    z = np.asarray(z_axis, dtype=float)
    y = y / np.linalg.norm(y)
    z = z - y * (z @ y)
    z = z / np.linalg.norm(z)
    m = np.column_stack([np.cross(y, z), y, z])
    tx, ty, tz = (v * _DEG for v in tilt_deg)
    return m @ _rx(tx) @ _ry(ty) @ _rz(tz)


# ---------------------------------------------------------------------- placements
@dataclasses.dataclass(frozen=True)
class Placement:
    """Where and how one subject carries the phone (one carried position).

    Angles in degrees, lengths in m, frequencies in Hz. ``side`` is +1 for the
    right leg / hip / hand, -1 for the left. Fields that do not apply to the
    position are 0 (the gains 1). See the module docstring for the models.
    """

    position: str
    side: float = 1.0
    upright: bool = True  # phone top towards the segment's proximal end (the hip / shoulder)
    screen_out: bool = True  # screen away from the body
    tilt_x_deg: float = 0.0  # small tilts of the phone in the segment (phone axes; back pocket: the buttock surface's angle, body frame)
    tilt_y_deg: float = 0.0
    tilt_z_deg: float = 0.0
    azimuth_deg: float = 0.0  # belt: where around the waist (0 front, 90 right side)
    grip_deg: float = 0.0  # swinging hand: angle of the phone's long axis in the hand (0 = pointing down)
    mount_quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)  # bag: the phone's orientation in the bag
    thigh_flex_mean_deg: float = 0.0  # pockets: mean thigh flexion while walking
    thigh_flex_amp_deg: float = 0.0  # pockets: amplitude of the stride-frequency thigh rotation
    thigh_h2: float = 0.0  # pockets: 2nd harmonic / fundamental of the thigh rotation
    thigh_abduction_deg: float = 0.0  # pockets: side-step ab-/adduction amplitude
    thigh_rotation_deg: float = 0.0  # pockets: internal/external rotation and ab-/adduction in walking
    pelvis_yaw_deg: float = 0.0  # belt
    pelvis_roll_deg: float = 0.0
    pelvis_pitch_deg: float = 0.0
    arm_swing_deg: float = 0.0  # swinging hand: amplitude in walking
    lever_m: float = 0.0  # distance of the phone from the joint (hip, pelvis centre, shoulder)
    bag_vertical_hz: float = 0.0  # bag: natural frequencies and damping ratio
    bag_horizontal_hz: float = 0.0
    bag_damping: float = 0.0
    bag_tilt_gain: float = 0.0
    bag_horizontal_gain: float = 0.0  # bag: the hip and thigh knock the bag: horizontal driving gain
    vertical_gain: float = 1.0  # the trunk's step bounce at this segment, relative to the hand-held model
    impact_gain: float = 1.0  # heel-strike impact at this segment, relative to the hand-held model
    other_leg_impact: float = 1.0  # impact of the other leg's heel strikes, relative to this side's
    impact_cv: float = 0.0  # extra step-to-step variation of the impact at this segment (log-normal sd)
    leg_asymmetry: float = 0.0  # step bounce larger on this side's steps: (1 + a cos(pi phi'))
    wobble_gain: float = 0.0  # soft-tissue wobble: the impact along a random direction per step, relative
    vibration_ms2: float = 0.3  # 3-15 Hz soft-tissue / fabric vibration per axis while moving
    wander_deg: float = 1.5  # slow orientation wander of the phone in the segment
    vigour: float = 1.0  # walk, side and backward steps: the trunk acceleration and impact at the segment scale by this (VIGOUR_RANGE)
    pelvis_share: float = 0.0  # back pocket: the buttock's rotation is (1 - share) x the thigh's + share x the pelvis's (BACK_POCKET_RANGE)
    pocket_roll_deg: float = 0.0  # back pocket: extra in-plane turn of the phone in the pocket, added to tilt_z_deg (BACK_POCKET_RANGE)
    stance_gate: float = 0.0  # back pocket: the trunk's acceleration at the phone is x1 in the carrying leg's step, x(1 - g) in the other's (STANCE_GATE_RANGE)
    pocket_turn_deg: float = 0.0  # back pocket: the phone's turning in the pocket (std per axis; POCKET_TURN_DEG_RANGE)

    def __post_init__(self) -> None:
        if self.position not in CARRIED_POSITIONS:
            raise InputError(f"Placement.position must be one of {', '.join(CARRIED_POSITIONS)}, got {self.position!r}.")
        if not 0.2 <= self.vigour <= 3.0:
            raise InputError(f"Placement.vigour must be a gain in 0.2-3, got {self.vigour!r}.")
        if not 0.0 <= self.pelvis_share <= 1.0:
            raise InputError(f"Placement.pelvis_share must be a fraction in 0-1, got {self.pelvis_share!r}.")
        if not 0.0 <= self.stance_gate <= 1.0:
            raise InputError(f"Placement.stance_gate must be a fraction in 0-1, got {self.stance_gate!r}.")
        if not 0.0 <= self.pocket_turn_deg <= 30.0:
            raise InputError(f"Placement.pocket_turn_deg must be an angle in 0-30 deg, got {self.pocket_turn_deg!r}.")

    @classmethod
    def random(cls, position: str, rng: np.random.Generator) -> Placement:
        """Draw a placement of ``position`` (a carried position) for one subject.

        The ranges of each position's fields are the uniform draws written out in
        :meth:`_random_placement` (thigh flexion, pelvic rotations, arm swing, levers,
        bag frequencies, gains and noise), sized against the Oxford walks
        (``experiments/reports/simulator-positions.md``). The vigour is
        drawn last, log-uniformly over :data:`VIGOUR_RANGE` (positions without
        an entry keep 1 and draw nothing), so the other fields of a seed do not
        depend on it. The back pocket then draws its pelvis share and extra
        in-pocket roll (uniform over :data:`BACK_POCKET_RANGE`) and its pelvis's
        rotation amplitudes (:data:`BACK_POCKET_PELVIS_DEG`), after the vigour
        for the same reason, then its stance gate (uniform over
        :data:`STANCE_GATE_RANGE`: the one-sided step) and last of all its turning in
        the pocket (uniform over :data:`POCKET_TURN_DEG_RANGE`).
        """
        p = cls._random_placement(position, rng)
        if position in VIGOUR_RANGE:
            lo, hi = VIGOUR_RANGE[position]
            p = dataclasses.replace(p, vigour=float(np.exp(rng.uniform(np.log(lo), np.log(hi)))))
        if position != "back-pocket":
            return p
        # the back pocket's own fields, after the vigour: the rest of a seed's placement stays the same
        share = float(rng.uniform(*BACK_POCKET_RANGE["pelvis_share"]))
        roll = float(rng.uniform(*BACK_POCKET_RANGE["pocket_roll_deg"]))
        pelvis = {f"pelvis_{k}_deg": float(rng.uniform(lo, hi)) for k, (lo, hi) in BACK_POCKET_PELVIS_DEG.items()}
        p = dataclasses.replace(p, pelvis_share=share, pocket_roll_deg=roll, **pelvis)
        # the one-sided step: every other field of a seed's back pocket stays the same
        p = dataclasses.replace(p, stance_gate=float(rng.uniform(*STANCE_GATE_RANGE)))
        # the turning in the pocket, last of all (the same reason)
        return dataclasses.replace(p, pocket_turn_deg=float(rng.uniform(*POCKET_TURN_DEG_RANGE)))

    @classmethod
    def _random_placement(cls, position: str, rng: np.random.Generator) -> Placement:
        """Every field of :meth:`random` but the vigour."""
        u = rng.uniform
        side = 1.0 if u() < 0.5 else -1.0
        if position == "front-pocket":
            return cls(
                position, side, upright=bool(u() < 0.75), screen_out=bool(u() < 0.5),
                tilt_x_deg=u(-8, 8), tilt_y_deg=u(-8, 8), tilt_z_deg=u(-12, 12),
                thigh_flex_mean_deg=u(4, 12), thigh_flex_amp_deg=u(14, 22), thigh_h2=u(0.1, 0.25),
                thigh_abduction_deg=u(6, 12), lever_m=u(0.10, 0.18),
                vertical_gain=u(0.75, 1.0), impact_gain=u(0.9, 1.9), other_leg_impact=u(0.05, 0.25), leg_asymmetry=u(0.75, 1.0), impact_cv=u(0.2, 0.4), wobble_gain=u(0.5, 1.0), thigh_rotation_deg=u(4, 10),
                vibration_ms2=u(0.3, 0.8), wander_deg=u(1.0, 3.0),
            )  # fmt: skip
        if position == "back-pocket":
            return cls(
                position, side, upright=bool(u() < 0.6), screen_out=bool(u() < 0.5),
                tilt_x_deg=u(15, 30), tilt_y_deg=u(-12, 12), tilt_z_deg=u(-15, 15),  # tilt_x: the buttock's surface
                thigh_flex_mean_deg=u(4, 12), thigh_flex_amp_deg=0.6 * u(14, 22), thigh_h2=u(0.1, 0.25),
                thigh_abduction_deg=u(4, 8), lever_m=u(0.08, 0.14),
                vertical_gain=u(0.7, 1.0), impact_gain=u(2.0, 3.5), other_leg_impact=u(0.1, 0.3), leg_asymmetry=u(0.5, 0.8), impact_cv=u(0.2, 0.4), wobble_gain=u(0.5, 1.0), thigh_rotation_deg=u(4, 10),
                vibration_ms2=u(0.4, 1.0), wander_deg=u(1.0, 3.0),
            )  # fmt: skip
        if position == "belt":
            return cls(
                position, side, upright=bool(u() < 0.8), screen_out=bool(u() < 0.7),
                tilt_x_deg=u(-10, 10), tilt_y_deg=u(-10, 10), tilt_z_deg=u(-10, 10), azimuth_deg=side * u(10, 110),
                pelvis_yaw_deg=u(3, 6), pelvis_roll_deg=u(3, 6), pelvis_pitch_deg=u(1, 3), lever_m=u(0.12, 0.18),
                vertical_gain=u(0.9, 1.2), impact_gain=u(1.0, 2.0), vibration_ms2=u(0.2, 0.5), wander_deg=u(0.5, 1.5),
            )  # fmt: skip
        if position == "swinging-hand":
            return cls(
                position, side, screen_out=bool(u() < 0.5),
                tilt_x_deg=u(-10, 10), tilt_y_deg=u(-10, 10), grip_deg=u(0, 360),
                arm_swing_deg=u(*ARM_SWING_DEG_RANGE), lever_m=u(0.4, 0.55),
                vertical_gain=u(0.5, 0.8), impact_gain=u(0.2, 0.6), leg_asymmetry=u(0.3, 0.5), impact_cv=u(0.3, 0.5), vibration_ms2=u(0.2, 0.5), wander_deg=u(2.0, 5.0),
            )  # fmt: skip
        if position == "bag":
            q = rng.standard_normal(4)
            q = q / np.linalg.norm(q)
            q = q * (1.0 if q[0] >= 0 else -1.0)
            return cls(
                position, side, mount_quat=tuple(float(v) for v in q),
                bag_vertical_hz=u(3.0, 5.0), bag_horizontal_hz=u(1.5, 2.5), bag_damping=u(0.15, 0.3), bag_tilt_gain=u(0.5, 1.0),
                bag_horizontal_gain=u(1.0, 2.0), impact_cv=u(0.15, 0.3), leg_asymmetry=u(0.1, 0.3),
                vertical_gain=u(0.7, 0.9), impact_gain=u(0.4, 1.0), vibration_ms2=u(0.1, 0.3), wander_deg=u(1.0, 4.0),
            )  # fmt: skip
        raise InputError(f"unknown carried position {position!r}; choose from {', '.join(CARRIED_POSITIONS)}.")

    def mount(self) -> np.ndarray:
        """The mount matrix ``M`` (3, 3): columns are the phone's x, y, z axes in segment coordinates.

        Segment frame at rest: x right, y forward, z up (the person frame).
        """
        tilt = (self.tilt_x_deg, self.tilt_y_deg, self.tilt_z_deg)
        up = 1.0 if self.upright else -1.0
        if self.position == "front-pocket":  # on the front of the thigh, screen forward (out) or towards the leg
            return _mount([0, 0, up], [0, 1.0 if self.screen_out else -1.0, 0], tilt)
        if self.position == "back-pocket":  # on the buttock, screen backward (out) or towards the body
            # the buttock's surface faces backward and down by tilt_x_deg (a property of the body,
            # so it does not flip with the phone: an upside-down phone lies on the same surface)
            a = self.tilt_x_deg * _DEG
            normal = np.array([0.0, -np.cos(a), -np.sin(a)])
            along = np.array([0.0, -np.sin(a), np.cos(a)])
            return _mount(
                up * along, normal if self.screen_out else -normal, (0.0, self.tilt_y_deg, self.tilt_z_deg + self.pocket_roll_deg)
            )
        if self.position == "belt":  # on the waist at an azimuth, screen radially out or in
            b = self.azimuth_deg * _DEG
            radial = np.array([np.sin(b), np.cos(b), 0.0])
            return _mount([0, 0, up], radial if self.screen_out else -radial, tilt)
        if self.position == "swinging-hand":  # in the hanging hand: long axis in the sagittal plane, screen sideways
            gr = self.grip_deg * _DEG
            y = [0.0, np.sin(gr), -np.cos(gr)]
            return _mount(y, [self.side if self.screen_out else -self.side, 0, 0], tilt)
        from scipy.spatial.transform import Rotation

        w, x, y, z = self.mount_quat
        return Rotation.from_quat([x, y, z, w]).as_matrix()

    def lever(self) -> np.ndarray:
        """The phone's position relative to the segment's joint (m, segment frame at rest)."""
        s, r = self.side, self.lever_m
        if self.position == "front-pocket":
            return np.array([0.09 * s, 0.07, -r])
        if self.position == "back-pocket":
            return np.array([0.08 * s, -0.10, -r])
        if self.position == "belt":
            b = self.azimuth_deg * _DEG
            return r * np.array([np.sin(b), np.cos(b), 0.0])
        if self.position == "swinging-hand":
            return np.array([0.0, 0.0, -r])
        return np.zeros(3)

    def to_dict(self, *, digits: int = 6) -> dict[str, Any]:
        """Flat ``carry_*`` dict for the manifest (the fields that apply, floats rounded)."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            if f.name == "position":
                continue
            v = getattr(self, f.name)
            if f.name == "mount_quat":
                if self.position == "bag":
                    for c, q in zip("wxyz", v, strict=True):
                        out[f"carry_mount_q{c}"] = round(float(q), digits)
                continue
            out[f"carry_{f.name}"] = round(float(v), digits) if isinstance(v, float) else v
        return out


# ---------------------------------------------------------------------- segment motion
def _smooth_weights(mode_idx: np.ndarray, env: np.ndarray, fs: float) -> np.ndarray:
    """Per-mode weights (n, 5): one-hot mode times the motion envelope, smoothed over 0.3 s (Hann)."""
    w = np.zeros((len(mode_idx), len(MOTION_MODES)))
    w[np.arange(len(mode_idx)), mode_idx] = 1.0
    w *= env[:, None]
    m = max(3, int(round(0.3 * fs)) | 1)
    ker = np.hanning(m + 2)[1:-1]
    ker /= ker.sum()
    pad = m // 2
    wp = np.pad(w, ((pad, pad), (0, 0)), mode="edge")
    return np.stack([np.convolve(wp[:, c], ker, mode="valid") for c in range(w.shape[1])], axis=1)


def _thigh_curve(psi, mean, amp, h2):
    """Sagittal thigh angle (rad) over the stride phase ``psi`` (0 at the heel strike of that leg)."""
    return mean + amp * (np.cos(2 * np.pi * psi) + h2 * np.cos(4 * np.pi * psi - 0.6 * np.pi))


def _pelvis_angles(p: Placement, phi: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pelvis's rotation (yaw, pitch, roll in rad, person frame) per sample: transverse rotation and
    obliquity once per stride, anterior tilt once per step (``p.pelvis_*_deg``; ``w`` as :func:`_smooth_weights`)."""
    iw, ir, isl, isr, ib = (_MODE_INDEX[m] for m in ("walk", "run", "side_left", "side_right", "backward"))
    side_dir = w[:, isl] - w[:, isr]  # +1 moving left, -1 moving right
    w_side = w[:, isl] + w[:, isr]
    a_y, a_r, a_p = p.pelvis_yaw_deg * _DEG, p.pelvis_roll_deg * _DEG, p.pelvis_pitch_deg * _DEG
    walkish = w[:, iw] + 1.3 * w[:, ir] + 0.8 * w[:, ib]
    # the pelvis turns forward on the side of the swinging leg; it drops on the swing side
    right = (phi - 1.0) / 2.0
    direction = w[:, iw] + w[:, ir] - w[:, ib]
    yaw = -a_y * np.cos(2 * np.pi * right) * direction + w_side * 0.5 * a_y * np.cos(2 * np.pi * phi)
    roll = a_r * np.sin(2 * np.pi * right) * walkish + w_side * side_dir * a_r * np.sin(2 * np.pi * phi)
    pitch = a_p * np.cos(2 * np.pi * phi) * (walkish + 0.5 * w_side)
    return yaw, pitch, roll


def _segment_angles(p: Placement, phi: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The segment's own rotation (yaw, pitch, roll in rad, person frame) per sample."""
    iw, ir, isl, isr, ib = (_MODE_INDEX[m] for m in ("walk", "run", "side_left", "side_right", "backward"))
    n = len(phi)
    yaw, pitch, roll = np.zeros(n), np.zeros(n), np.zeros(n)
    # stride phase of the carrying leg (left heel strikes at even phi) and of the other leg
    leg0 = 0.0 if p.side < 0 else 1.0
    psi = (phi - leg0) / 2.0
    psi_other = psi - 0.5
    side_dir = w[:, isl] - w[:, isr]  # +1 moving left, -1 moving right
    w_side = w[:, isl] + w[:, isr]
    if p.position in ("front-pocket", "back-pocket"):
        mean, amp, h2 = p.thigh_flex_mean_deg * _DEG, p.thigh_flex_amp_deg * _DEG, p.thigh_h2
        fwd = _thigh_curve(psi, mean, amp, h2)
        back = _thigh_curve(0.5 - psi, mean, 0.8 * amp, h2)  # reversed: lands extended, flexes in stance
        run = _thigh_curve(psi, 2.0 * mean, 1.5 * amp, 0.6 * h2)
        pitch = w[:, iw] * fwd + w[:, ir] * run + w[:, ib] * back + w_side * mean * 0.5
        # side steps: one ab-/adduction cycle per side step, both legs towards the direction of motion
        lead = (p.side < 0) == (side_dir > 0)
        cyc = phi + np.where(lead, 0.0, 0.3)
        roll = -side_dir * p.thigh_abduction_deg * _DEG * 0.5 * (1 - np.cos(2 * np.pi * cyc))
        pitch = pitch + w_side * 0.25 * amp * np.cos(2 * np.pi * cyc)
        # in walking the thigh also rotates about its long axis and ab-/adducts a little, once per stride
        gait = w[:, iw] + w[:, ir] + w[:, ib]
        rot = p.thigh_rotation_deg * _DEG * gait
        yaw = p.side * rot * np.sin(2 * np.pi * psi)
        roll = roll + p.side * 0.6 * rot * np.cos(2 * np.pi * psi + 0.3 * np.pi)
        if p.position == "back-pocket" and p.pelvis_share > 0:
            # the buttock's surface moves with the pelvis (and the gluteal tissue) as much as with the thigh
            s = p.pelvis_share
            py, pp, pr = _pelvis_angles(p, phi, w)
            yaw, pitch, roll = (1 - s) * yaw + s * py, (1 - s) * pitch + s * pp, (1 - s) * roll + s * pr
    elif p.position == "belt":
        yaw, pitch, roll = _pelvis_angles(p, phi, w)
    elif p.position == "swinging-hand":
        a = p.arm_swing_deg * _DEG
        # the arm is forward (flexed) when the other leg lands; backward walking runs it in reverse
        fwd = a * np.cos(2 * np.pi * psi_other)
        back = 0.8 * a * np.cos(2 * np.pi * (0.5 - psi_other))
        pitch = w[:, iw] * fwd + w[:, ir] * (fwd + 0.3) + w[:, ib] * back + w_side * 0.25 * a * np.cos(2 * np.pi * phi)
        roll = p.side * 0.5 * a * np.sin(2 * np.pi * psi_other) * (w[:, iw] + w[:, ir] + w[:, ib])
        roll = roll + w_side * side_dir * 0.3 * a * np.sin(2 * np.pi * phi)
    return yaw, pitch, roll


def _right_jacobian_times(v: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``J_r(v) w`` per row for rotation vectors ``v`` (n, 3): the body rate of ``exp([v]x)`` when ``v``
    changes at ``w``; ``J_r = I - (1 - cos t) / t^2 [v]x + (t - sin t) / t^3 [v]x^2`` (series near 0)."""
    t = np.linalg.norm(v, axis=1)
    small = t < 1e-4
    ts = np.where(small, 1.0, t)
    a = np.where(small, 0.5 - t**2 / 24.0, (1.0 - np.cos(ts)) / ts**2)
    b = np.where(small, 1.0 / 6.0 - t**2 / 120.0, (ts - np.sin(ts)) / ts**3)
    vw = np.cross(v, w)
    return w - a[:, None] * vw + b[:, None] * np.cross(v, vw)


def stance_gate(phi: np.ndarray, side: float, gate: float) -> np.ndarray:
    """The one-sided step's gain on the trunk's acceleration at a back-pocket phone, per sample.

    1 through the step of the carrying leg (``side``: +1 right, -1 left; from its heel strike to
    the other leg's), ``1 - gate`` through the other leg's step, with smooth edges of half-width
    about :data:`STANCE_GATE_EDGE` steps at each heel strike (a ``tanh`` of the stride phase).
    ``phi`` is the continuous step count of :func:`carried_signals` (left heel strikes at even ``phi``).
    """
    leg0 = 0.0 if side < 0 else 1.0
    k = 1.0 / (np.pi * STANCE_GATE_EDGE)  # tanh(k sin(pi x)) turns within about +-STANCE_GATE_EDGE of each strike
    q = np.tanh(k * np.sin(np.pi * (np.asarray(phi, dtype=float) - leg0))) / np.tanh(k)
    return 1.0 - 0.5 * gate * (1.0 - q)


def _second_order(x: np.ndarray, fs: float, f_hz: float, zeta: float) -> np.ndarray:
    """A base-excited damped oscillator's acceleration: ``(2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2)``
    applied to the driving acceleration ``x`` (n, c); bilinear transform, causal (so delayed)."""
    w0 = 2 * np.pi * f_hz
    b, a = scipy.signal.bilinear([2 * zeta * w0, w0**2], [1.0, 2 * zeta * w0, w0**2], fs=fs)
    return scipy.signal.lfilter(b, a, x, axis=0)


def carried_signals(
    p: Placement,
    *,
    fs: float,
    phi: np.ndarray,
    mode_idx: np.ndarray,
    env: np.ndarray,
    theta: np.ndarray,
    theta_rate: np.ndarray,
    acc_person: np.ndarray,
    rng: np.random.Generator,
    impact: np.ndarray | None = None,
    impact_step: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Accelerometer, gyroscope and attitude of a phone carried at ``p`` (noise-free, no sensor errors).

    Parameters
    ----------
    phi : (n,) continuous step count (``phi = k`` at the event of global step ``k``; left foot on even ``k``)
    mode_idx : (n,) index into :data:`gaitml.consts.MOTION_MODES` of each sample's step
    env : (n,) motion envelope (0 standing, 1 walking; ramps at the ends of a bout)
    theta, theta_rate : (n,) facing heading (rad, clockwise from north) and its rate (rad/s)
    acc_person : (n, 3) body acceleration (right, forward, up; m/s^2, gravity excluded), the
        segment gains already applied
    rng : the placement's generator (orientation wander, vibration)
    impact, impact_step : (n,) the heel-strike impact (m/s^2) and the index of the step it
        belongs to; with ``p.wobble_gain`` > 0 the soft tissue carrying the phone wobbles: the
        impact repeated along a random direction (person frame) per step

    Returns
    -------
    dict
        ``acc`` (n, 3) specific force in the phone frame (m/s^2), ``gyr`` (n, 3) body rate
        (rad/s), ``attitude`` (n, 3, 3) phone -> navigation rotation, ``segment_rate`` (n, 3)
        the segment's rate in its own frame (before the mount).
    """
    n = len(phi)
    dt = 1.0 / fs
    w = _smooth_weights(mode_idx, env, fs)
    yaw_s, pitch_s, roll_s = _segment_angles(p, phi, w)
    acc_p = np.array(acc_person, dtype=float)
    if p.wobble_gain > 0 and impact is not None:
        # the impact rings the soft tissue (a 9 Hz, lightly damped resonance) along a new direction each step
        d = rng.standard_normal((int(np.max(impact_step)) + 1, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        w0 = 2 * np.pi * WOBBLE_HZ
        b, a = scipy.signal.bilinear([w0**2], [1.0, 2 * WOBBLE_DAMPING * w0, w0**2], fs=fs)
        acc_p += p.wobble_gain * scipy.signal.lfilter(b, a, impact[:, None] * d[impact_step], axis=0)
    if p.position == "bag":
        acc_p[:, 2] = _second_order(acc_p[:, 2], fs, p.bag_vertical_hz, p.bag_damping)
        acc_p[:, :2] = _second_order(p.bag_horizontal_gain * acc_p[:, :2], fs, p.bag_horizontal_hz, p.bag_damping)
        # the strap and the body stop the bag: its horizontal swing saturates
        acc_p[:, :2] = BAG_SWING_LIMIT_MS2 * np.tanh(acc_p[:, :2] / BAG_SWING_LIMIT_MS2)
        pitch_s = pitch_s - p.bag_tilt_gain * np.arctan2(acc_p[:, 1], GRAVITY_MS2)
        roll_s = roll_s + p.bag_tilt_gain * np.arctan2(acc_p[:, 0], GRAVITY_MS2)
    wander = smooth_noise(rng, n, fs, 3.0, 3) * (p.wander_deg * _DEG)
    amp = np.exp(SEGMENT_AMP_CV * smooth_noise(rng, n, fs, 1.5)[:, 0])
    yaw_s, pitch_s, roll_s = amp * yaw_s, amp * pitch_s, amp * roll_s
    yaw_s, pitch_s, roll_s = yaw_s + 0.5 * wander[:, 0], pitch_s + wander[:, 1], roll_s + wander[:, 2]
    yaw = -theta + yaw_s
    yaw_rate = -theta_rate + np.gradient(yaw_s, dt)
    seg_rate = body_rates(yaw_rate, pitch_s, np.gradient(pitch_s, dt), roll_s, np.gradient(roll_s, dt))
    mount = p.mount()
    att = rotation_matrices(yaw, pitch_s, roll_s, mount)
    # body acceleration in the navigation frame, plus the lever arm's acceleration
    ct, sn = np.cos(theta), np.sin(theta)
    acc_nav = np.column_stack([acc_p[:, 0] * ct + acc_p[:, 1] * sn, -acc_p[:, 0] * sn + acc_p[:, 1] * ct, acc_p[:, 2]])
    lever = p.lever()
    if np.any(lever):
        seg = rotation_matrices(yaw, pitch_s, roll_s)
        pos = seg @ lever
        if p.position == "swinging-hand":  # the elbow bends when running: a shorter lever
            pos = pos * (1.0 - (1.0 - RUN_ARM_LEVER) * w[:, _MODE_INDEX["run"]])[:, None]
        acc_lever = np.zeros_like(pos)
        acc_lever[1:-1] = (pos[2:] - 2 * pos[1:-1] + pos[:-2]) / dt**2
        acc_lever[0], acc_lever[-1] = acc_lever[1], acc_lever[-2]
        acc_nav = acc_nav + acc_lever
    f = acc_nav.copy()
    f[:, 2] += GRAVITY_MS2
    acc = nav_to_phone(f, yaw, pitch_s, roll_s) @ mount
    gyr = seg_rate @ mount
    if p.pocket_turn_deg > 0:
        # the loose phone turns about itself in the pocket while its carrier moves: a rotation vector
        # delta (phone axes) of band-limited noise, T = exp([delta]x); the turned phone's attitude is
        # att T, its specific force T^T f and its body rate T^T omega + J_r(delta) delta' (J_r the right
        # Jacobian of SO(3), so that the gyroscope integrates to the attitude exactly)
        from scipy.spatial.transform import Rotation

        delta = band_noise(rng, n, fs, *POCKET_TURN_BAND_HZ, 3) * (p.pocket_turn_deg * _DEG * env)[:, None]
        turn = Rotation.from_rotvec(delta).as_matrix()  # turned phone -> phone
        acc = np.einsum("nji,nj->ni", turn, acc)
        gyr = np.einsum("nji,nj->ni", turn, gyr) + _right_jacobian_times(delta, np.gradient(delta, dt, axis=0))
        att = att @ turn
    return {"acc": acc, "gyr": gyr, "attitude": att, "segment_rate": seg_rate}
