"""Routes: the path a simulated person follows, as heading versus distance.

A :class:`Path` is a chain of pieces of constant curvature (straight legs,
circular turns and arcs), in the plane x = east, y = north, with the compass
heading ``psi`` of the direction of travel measured clockwise from north (a
right turn increases ``psi``; DESIGN sec. 2). ``psi`` is the direction the
body *moves*; the direction it *faces* is ``psi`` minus the mode's offset
(see :data:`gaitml.simulate.modes.MODE_OFFSET_RAD`), so a person side-stepping
along a corridor faces the wall.

Routes:

- ``rectangle``: a closed rectangle of about 262 m (paper 003 sec. 4.3,
  Fig. 11-12: "全长约 262 m 的矩形路线", start and end at the same point),
  sides 81 x 50 m with 1 m corner radius, clockwise (right turns);
- ``arc``: a closed loop of about 400 m (paper 003 sec. 4.3, Fig. 13, "弧形
  路线 ... 约 400 m"); the figure is not in the text, so we read "arc field"
  as a 400 m running-track shape: two 100 m straights joined by two 100 m
  semicircles (radius 31.8 m), clockwise;
- ``straight``: straight legs of 15-40 m joined by 90 deg (left or right) or
  180 deg turns taken while walking;
- ``random``: legs of 5-30 m joined by turns of random angle and radius, with
  occasional long arcs.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gaitml.errors import InputError

__all__ = ["Path", "ROUTES", "make_path", "rectangle_path", "arc_path", "straight_path", "random_path"]

#: Route names understood by :func:`make_path`.
ROUTES = ("straight", "rectangle", "arc", "random")

#: paper 003 sec. 4.3: reference path lengths of the two field experiments.
RECTANGLE_LENGTH_M = 262.0
ARC_LENGTH_M = 400.0


@dataclasses.dataclass(frozen=True)
class Path:
    """Pieces of constant curvature: start distance, length, start heading, curvature.

    ``curvature_radpm`` > 0 turns right (clockwise), < 0 left.
    """

    name: str
    length_m: np.ndarray
    heading0_rad: np.ndarray
    curvature_radpm: np.ndarray
    closed: bool = False

    @property
    def start_m(self) -> np.ndarray:
        """Distance along the path where each piece starts."""
        return np.concatenate([[0.0], np.cumsum(self.length_m)[:-1]])

    @property
    def total_length_m(self) -> float:
        """The path length."""
        return float(np.sum(self.length_m))

    def heading_at(self, s_m) -> np.ndarray:
        """Heading of travel (rad, clockwise from north) at distance ``s_m`` (held after the end)."""
        s = np.asarray(s_m, dtype=float)
        start = self.start_m
        i = np.clip(np.searchsorted(start, s, side="right") - 1, 0, len(start) - 1)
        ds = np.clip(s - start[i], 0.0, self.length_m[i])
        return self.heading0_rad[i] + self.curvature_radpm[i] * ds

    def points(self, step_m: float = 0.5) -> np.ndarray:
        """Points (x_m, y_m) along the path every ``step_m`` (exact integration of each piece)."""
        xs, ys = [0.0], [0.0]
        x = y = 0.0
        for length, h0, k in zip(self.length_m, self.heading0_rad, self.curvature_radpm, strict=True):
            n = max(1, int(np.ceil(length / step_m)))
            d = np.linspace(0, length, n + 1)[1:]
            if abs(k) < 1e-12:
                px, py = x + d * np.sin(h0), y + d * np.cos(h0)
            else:
                px = x + (np.cos(h0) - np.cos(h0 + k * d)) / k
                py = y + (np.sin(h0 + k * d) - np.sin(h0)) / k
            xs.extend(px)
            ys.extend(py)
            x, y = px[-1], py[-1]
        return np.column_stack([xs, ys])


def _build(name: str, pieces: list[tuple[float, float]], closed: bool = False, heading0: float = 0.0) -> Path:
    """Pieces given as (length_m, heading change over the piece in rad)."""
    lengths = np.array([p[0] for p in pieces], dtype=float)
    turns = np.array([p[1] for p in pieces], dtype=float)
    h0 = heading0 + np.concatenate([[0.0], np.cumsum(turns)[:-1]])
    return Path(name, lengths, h0, turns / lengths, closed)


def _turn(angle_rad: float, radius_m: float) -> tuple[float, float]:
    return (abs(angle_rad) * radius_m, angle_rad)


def rectangle_path(perimeter_m: float = RECTANGLE_LENGTH_M, *, aspect: float = 81.0 / 50.0, corner_radius_m: float = 1.0) -> Path:
    """Closed clockwise rectangle of ``perimeter_m`` (paper 003 sec. 4.3: about 262 m)."""
    straight_total = perimeter_m - 2 * np.pi * corner_radius_m
    b = straight_total / (2 * (1 + aspect))
    a = aspect * b
    pieces = []
    for side in (a, b, a, b):
        pieces += [(side, 0.0), _turn(np.pi / 2, corner_radius_m)]
    return _build("rectangle", pieces, closed=True)


def arc_path(length_m: float = ARC_LENGTH_M) -> Path:
    """Closed clockwise running-track loop of ``length_m`` (paper 003 sec. 4.3: about 400 m)."""
    q = length_m / 4
    return _build("arc", [(q, 0.0), (q, np.pi), (q, 0.0), (q, np.pi)], closed=True)


def straight_path(rng: np.random.Generator, min_length_m: float) -> Path:
    """Straight legs of 15-40 m with 90 deg or 180 deg turns taken while walking."""
    pieces: list[tuple[float, float]] = []
    total = 0.0
    while total < min_length_m:
        leg = rng.uniform(15.0, 40.0)
        pieces.append((leg, 0.0))
        r = rng.uniform()
        angle = np.pi / 2 if r < 0.4 else (-np.pi / 2 if r < 0.8 else np.pi)
        turn = _turn(angle, rng.uniform(0.6, 1.2) if abs(angle) < 3 else rng.uniform(0.4, 0.7))
        pieces.append(turn)
        total += leg + turn[0]
    return _build("straight", pieces)


def random_path(rng: np.random.Generator, min_length_m: float) -> Path:
    """Legs of 5-30 m joined by random turns (+/-20-150 deg) and occasional long arcs."""
    pieces: list[tuple[float, float]] = []
    total = 0.0
    heading0 = rng.uniform(-np.pi, np.pi)
    while total < min_length_m:
        leg = rng.uniform(5.0, 30.0)
        pieces.append((leg, 0.0))
        sign = 1.0 if rng.uniform() < 0.5 else -1.0
        if rng.uniform() < 0.25:
            turn = _turn(sign * rng.uniform(np.pi / 3, np.pi), rng.uniform(8.0, 25.0))
        else:
            turn = _turn(sign * rng.uniform(np.pi / 9, 5 * np.pi / 6), rng.uniform(0.6, 3.0))
        pieces.append(turn)
        total += leg + turn[0]
    return _build("random", pieces, heading0=heading0)


def make_path(route: str, rng: np.random.Generator, *, min_length_m: float = 500.0) -> Path:
    """The :class:`Path` of a named route (``straight`` and ``random`` are at least ``min_length_m`` long)."""
    if route == "rectangle":
        return rectangle_path()
    if route == "arc":
        return arc_path()
    if route == "straight":
        return straight_path(rng, min_length_m)
    if route == "random":
        return random_path(rng, min_length_m)
    raise InputError(f"unknown route {route!r}; choose from {', '.join(ROUTES)}.")
