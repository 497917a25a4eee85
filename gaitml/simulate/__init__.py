"""Gait simulator: five motion modes, subjects, routes, full ground truth (DESIGN sec. 7).

Real recordings of all five motion modes of paper 003 (walk, run, side_left,
side_right, backward) are not publicly available, so gaitml simulates them,
with the true steps, step lengths, headings, positions and per-sample labels.

Quick use::

    from gaitml.simulate import simulate_dataset, simulate_route, write_simulation
    recs = simulate_dataset(n_subjects=8, duration_s=120, seed=0)   # one per subject
    loop = simulate_route("rectangle", seed=1)                       # ~262 m, mixed modes
    write_simulation(recs + [loop], "sim-out")

The model
---------
Conventions (DESIGN sec. 2): navigation frame x = east, y = north, z = up;
the facing heading ``theta`` is clockwise from north; a forward step of length
``L`` moves ``L (sin theta, cos theta)`` (paper 003 eq. 10); backward moves
along ``theta + pi``, a left side step along ``theta - pi/2``, a right side step
along ``theta + pi/2`` -- the person keeps facing ``theta`` while side-stepping
or walking backward. Phone frame: x right, y forward, z up when held flat.

1. *Subjects* (:mod:`.subject`): height, cadence and step length per mode,
   vertical amplitude and harmonic content, phase skew, speed fluctuation,
   lateral sway, left/right asymmetry of step time and peak, step-to-step
   jitter, phone pose (flat ~3-12 deg pitch or tilted 14-50 deg), slow
   orientation wander, accelerometer/gyroscope noise and bias, the sizes
   of the step-to-step and slow variability (below), and the hand gain: how
   much of the trunk's acceleration reaches a hand-held phone (0.25-1.2,
   calm to vigorous walkers; walk, side and backward steps; fitted to the real
   hand-held walks by ``experiments/scripts/hand_gain.py``). A phone carried in
   a pocket or a bag draws a vigour instead (:data:`.positions.VIGOUR_RANGE`,
   fitted to the Oxford pocket and purse walks by
   ``experiments/scripts/carry_vigour.py``).
2. *Route and steps* (:mod:`.route`, :mod:`.plan`): a path of straight legs,
   turns and arcs (rectangle ~262 m and arc ~400 m of paper 003 sec. 4.3,
   straight legs with turns, random); mode segments of 8-20 s in shuffled
   rounds, optional pauses (label ``stand``, only with ``pauses=True``). Each
   step moves along the path; the person faces the direction of travel minus
   the mode's offset, so switching e.g. from walking to side-stepping turns the
   body by 90 deg (a real rotation the gyroscope sees). Turns are taken while
   walking (corner radius 0.4-3 m), so the angular rate is that of real turns.
3. *Body acceleration per step* (:mod:`.modes`), as a function of the step
   phase ``u`` (0 at a step event, 1 at the next):

   - walk (inverted pendulum): vertical ``A sum_h c_h cos(2 pi h w(u))`` with a
     step-frequency fundamental and 2nd/3rd harmonics (``w`` a monotone phase
     warp for the steeper rise before heel strike), zero mean, maximal at heel
     strike (centre of mass lowest, ground reaction force highest) and minimal
     at mid-stance; forward speed ``L/T (1 + c cos 2 pi u + ...)``, fastest at
     double support, slowest at mid-stance, so the forward acceleration brakes
     after heel strike and pushes before the next; lateral sway at *half* the
     step frequency ``cos(pi phi) + h3 cos(3 pi phi)`` (``phi`` counts steps)
     towards the side opposite the stance foot, with left/right asymmetry of
     peak height and step time;
   - run (spring-mass): a raised-cosine stance pulse of height ``2 k g / D``
     (duty ``D`` 0.38-0.48) centred on mid-stance and a flight phase at
     ``-k g`` (``k`` 0.4-0.62: the arm holding the phone is only partly in
     free fall), cadence 2.5-3.1 steps/s, so larger swings of the magnitude
     (1st-99th percentile about 5-27 m/s^2) than walking (about 4-16 m/s^2);
     braking then propulsion within stance;
   - side steps (one step = lead foot out + trailing foot closing): the lead
     foot lands and brakes the sideways motion hardest at impact (lateral and
     vertical peaks coincide), the body is slowest when the trailing foot
     closes, then the trailing leg pushes; the lateral speed swings by
     +/-45-75 % of its mean, so the dominant signal is lateral (about
     +/-4-6 m/s^2), with opposite sign for left and right (mirror images); a
     sharper vertical landing peak with a 2nd-harmonic bump when the trailing
     foot closes;
   - backward: toe-first contact, smaller and smoother vertical peak, shorter
     (0.38-0.55 m) and slower (1.45-1.85 /s) steps; the speed profile of
     walking along ``theta + pi``, so on the body's forward axis the
     braking/push pattern is reversed.

   On top of the smooth pattern: a narrow heel-strike impact spike (Gaussian,
   sigma 10-20 ms, 1.5-5 m/s^2, random per step; larger when running, smaller
   for backward toe landings) centred on the step event, and for walking a
   secondary "shoulder" bump about 0.1-0.15 s after the peak (the arm and
   phone rebound and the trailing leg's push-off), both seen in the real
   flat-held walks. The first step of a new mode blends the old and new pattern linearly in
   phase; a walking bout starts from rest (amplitude ramp over the first half
   step) and ends with a half-step settling ramp. Turning adds the
   centripetal acceleration ``v psi'`` towards the inside of the turn.
   *Variability* (:mod:`.variability`): no two steps are alike. Step time
   and length scatter 2-4.5 % (stride-time CV of healthy adults 2-4 %); the
   walking speed drifts slowly (1.5-4 %, 3-8 s); each step's amplitude
   follows its speed squared (inverted pendulum) and its heel-strike peak
   and mid-stance trough vary by another 5-11 % (the compliant arm and wrist
   between trunk and phone); the harmonic shape, the lateral sway and the
   forward speed swing vary per step; the hand shake drifts slowly. All
   per-step values are smooth knots at half steps, so the signal stays
   continuous and the step event stays the peak. Sized against the real
   flat-held walks' window-to-window statistics (the CV across 0.5 s and
   1.5 s windows of the window variance of ``|acc|``;
   ``experiments/reports/simulator-hand.md``).
4. *Phone and sensor* (:mod:`.sensor`): attitude ``Rz(-theta + yaw bob +
   wander) Rx(pitch) Ry(roll)`` with gait-induced bobbing (pitch at the step
   frequency, roll and yaw at half of it) and a smooth random wander; the
   accelerometer gives ``R^T (a + g z)``, the gyroscope ``R^T R'`` from the
   same angles (so a right turn reads a negative z rate when the phone is
   flat); the body acceleration scaled by the subject's hand gain (not in
   running); hand/arm vibration (3-15 Hz band noise, 0.25-0.65 m/s^2 per axis
   while moving, 15 % of it while standing), bias, white noise, rounding to
   1e-4 m/s^2 and 1e-5 rad/s;
   sampling rate 20-500 Hz (phones: 50-200 Hz).

5. *Carrying positions* (:mod:`.positions`): besides the hand-held
   phone (``hand-flat``, ``hand-tilted``: item 4, the default), the phone can
   ride on the thigh (``front-pocket``: it turns with one leg once per
   stride, in reverse when walking backwards; ``back-pocket``: a blend of the
   thigh's and the pelvis's motion, fitted to real back-pocket walks), the pelvis (``belt``),
   the swinging arm (``swinging-hand``) or in a ``bag`` (a damped, delayed
   pendulum of the trunk), with a random placement per subject
   (:class:`~gaitml.simulate.positions.Placement`). ``simulate_dataset(...,
   positions=POSITIONS)`` makes one recording per subject and position;
   ``reference['attitude_wxyz']`` holds the phone's attitude truth. Realism per
   position against the Oxford walks: ``python -m experiments.scripts.realism
   --positions`` (``experiments/reports/simulator-positions.md``).

The true step event
-------------------
``reference['steps_t_s']`` (and ``steps['t_s']``) is the time of the
vertical acceleration peak of the step, which is also the peak of ``|acc|``
(``find_peaks`` on the N = 5 smoothed magnitude lands within one sample of
it, median, in every mode; tested): heel strike / loading response for walking,
forefoot contact for backward walking, mid-stance for running, lead-foot
landing for side steps. Evaluate peak detectors against it directly (paper
003's single-peak detector, ``t_peak_s``); FSM detectors that report step
*completion* (paper 000 Table 3, ``t_end_s``) report about half a step later.
The step's displacement happens between the previous event and this one.

Ground truth written with each recording: ``steps`` (``t_s, mode,
step_length_m, heading_rad`` (facing, wrapped to [-pi, pi)), ``foot``,
``t_start_s``, ``x_m, y_m`` (position after the step)), ``trajectory``
(every sample: ``t, x_m, y_m, heading_rad``), ``n_steps_true``. Integrating
the steps with the conventions above gives the trajectory's end point.

Reproducibility: the same seed gives the same arrays and byte-identical
files (every random draw comes from a ``numpy`` ``SeedSequence`` spawned from
the seed, subject index and session).

Realism (lab scripts of the repository, not installed): ``python -m
experiments.scripts.realism`` compares a simulated flat-held walk with the two
real flat-held walks of ``ifsm-flat-phone``; ``python -m experiments.scripts.shortwin
DATA_DIR`` compares the growth of feature noise from 1.5 s to 0.5 s windows and
the per-step shape spread with real walking.

References
----------
Paper 003 (Deng et al. 2021), sec. 2.1 (50 Hz phone, |acc| - g), sec. 4
(eq. 10-11, multi-state PDR), sec. 4.3 (rectangle 262 m, arc 400 m).
Paper 000 (Bi et al. 2021), sec. 3 and Table 3 (flat-held walks, step
durations 0.50-0.64 s).
"""

from gaitml.simulate.dataset import (
    SAMPLING_RATE_RANGE_HZ,
    simulate_dataset,
    simulate_recording,
    simulate_route,
    synthesize,
    write_simulation,
)
from gaitml.simulate.modes import MODE_OFFSET_RAD, STAND, ModeGait, check_modes, mode_gait
from gaitml.simulate.plan import StepPlan, mode_schedule, plan_steps
from gaitml.simulate.positions import CARRIED_POSITIONS, HAND_POSITIONS, POSITIONS, Placement, check_positions
from gaitml.simulate.route import ROUTES, Path, arc_path, make_path, random_path, rectangle_path, straight_path
from gaitml.simulate.subject import POSES, Subject, sample_subjects

__all__ = [
    "CARRIED_POSITIONS",
    "HAND_POSITIONS",
    "MODE_OFFSET_RAD",
    "POSES",
    "POSITIONS",
    "Placement",
    "ROUTES",
    "SAMPLING_RATE_RANGE_HZ",
    "STAND",
    "ModeGait",
    "Path",
    "StepPlan",
    "Subject",
    "arc_path",
    "check_modes",
    "check_positions",
    "make_path",
    "mode_gait",
    "mode_schedule",
    "plan_steps",
    "random_path",
    "rectangle_path",
    "sample_subjects",
    "simulate_dataset",
    "simulate_recording",
    "simulate_route",
    "straight_path",
    "synthesize",
    "write_simulation",
]
