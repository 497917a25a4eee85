"""The ``gaitml`` command: argument parsing only; the work is done by library code.

Every subcommand of DESIGN sec. 5 is registered here; its handler lives in
``gaitml/commands/<name>.py`` as ``run(args) -> int``. Exit status: 0 success,
2 bad input or arguments (one line on stderr naming the problem and the fix,
no traceback), 1 internal error.
"""

from __future__ import annotations

import argparse
import importlib
import os
import select
import sys
import traceback
from collections.abc import Callable, Sequence

from gaitml.errors import GaitmlError

__all__ = ["main", "build_parser", "REGISTRY_CHOICES", "STEP_DETECTORS", "ZUPT_DETECTORS"]


class _Names(Sequence):
    """Choices read from a registry on first use, so that building the parser imports no algorithm.

    argparse reads choices only to check a given value and to format help or an
    error; the options that use them set a ``metavar`` so that nothing is read
    while the parser is built.
    """

    def __init__(self, load: Callable[[], object]):
        self._load = load
        self._names: tuple[str, ...] | None = None

    def _get(self) -> tuple[str, ...]:
        if self._names is None:
            self._names = tuple(self._load())
        return self._names

    def __getitem__(self, i):
        return self._get()[i]

    def __len__(self) -> int:
        return len(self._get())

    def __contains__(self, x) -> bool:
        return x in self._get()

    def __iter__(self):
        return iter(self._get())

    def __repr__(self) -> str:
        return repr(self._get())


def _step_detectors():
    from gaitml.steps import detector_names

    return detector_names()


def _zupt_detectors():
    from gaitml.zupt import DETECTORS

    return DETECTORS


def _heading_sources():
    from gaitml.pdr import HEADING_SOURCES

    return HEADING_SOURCES


def _mode_sources():
    from gaitml.pdr import MODE_SOURCES

    return MODE_SOURCES


def _mode_assignments():
    from gaitml.pdr.step_modes import MODE_ASSIGNMENTS

    return MODE_ASSIGNMENTS


def _formats():
    from gaitml.io import FORMATS

    return FORMATS


def _feature_sets():
    from gaitml.features import FEATURE_SETS
    from gaitml.features._catalogue import SUBSET_ALIASES

    return (*FEATURE_SETS, *SUBSET_ALIASES)


def _feature_frames():
    from gaitml.features import FEATURE_FRAMES

    return FEATURE_FRAMES


#: Names of the step and zero-velocity detectors: lazy views of the registries.
STEP_DETECTORS = _Names(_step_detectors)
ZUPT_DETECTORS = _Names(_zupt_detectors)
#: The registry behind each option with fixed choices: ``{(command, option): names}``.
REGISTRY_CHOICES: dict[tuple[str, str], Sequence] = {}


def _choices(command: str, option: str, load: Callable[[], object]) -> dict:
    """``add_argument`` keywords for an option whose choices come from a registry."""
    names = REGISTRY_CHOICES.setdefault((command, option), _Names(load))
    return {"choices": names, "metavar": option.lstrip("-").replace("-", "_").upper()}


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (exit 2) instead of usage + message."""

    def error(self, message: str) -> None:  # noqa: D102
        raise _UsageError(f"{message}; see '{self.prog} --help'.")


def _input_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("input")
    g.add_argument(
        "--format",
        **_choices(p.prog.split()[-1], "--format", _formats),
        help="input format: %(choices)s (default: detected from the content)",
    )
    g.add_argument("--sensor", choices=("left", "right"), default="left", help="foot of a two-sensor gaitmap file (default: left)")
    g.add_argument(
        "--sampling-rate-hz",
        type=float,
        help="resample to this uniform rate (Oxford default 100 Hz), or the rate of a file without a time base",
    )
    g.add_argument("--acc-unit", choices=("m/s^2", "g"), default="m/s^2", help="unit of a gaitml-csv's acc columns (default m/s^2)")
    g.add_argument("--gyr-unit", choices=("rad/s", "deg/s"), default="rad/s", help="unit of a gaitml-csv's gyr columns (default rad/s)")
    g.add_argument(
        "--columns",
        metavar="MAP",
        help="read any CSV by naming its columns: t=COL,acc_x=COL,acc_y=COL,acc_z=COL[,gyr_x=COL,gyr_y=COL,gyr_z=COL][,t_gyr=COL][,label=COL]",
    )
    g.add_argument("--time-unit", choices=("s", "ms", "us", "ns"), default="s", help="unit of the --columns time column (default s)")


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser (used by ``main`` and by the docs tests)."""
    from gaitml import __version__

    parser = _Parser(prog="gaitml", description="Smartphone gait, motion-mode recognition and PDR.")
    parser.add_argument("--version", action="version", version=f"gaitml {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser("info", help="describe a recording or data set")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _input_options(p)

    p = sub.add_parser("split", help="cut a recording at its long timestamp gaps into separate files (with a manifest)")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for one gaitml-csv per segment and manifest.csv")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _input_options(p)

    p = sub.add_parser("simulate", help="simulate recordings with full ground truth")
    p.add_argument("out_dir", metavar="OUT_DIR")
    p.add_argument("--subjects", type=int, default=4)
    p.add_argument("--duration-s", type=float, default=None, help="seconds per recording (default 120; straight/random routes only)")
    p.add_argument("--modes", default="walk,run,side_left,side_right,backward", help="comma-separated motion modes")
    p.add_argument("--route", default="straight", help="straight | rectangle | arc | random")
    p.add_argument("--sampling-rate-hz", type=float, default=None)
    p.add_argument("--seed", type=int, default=0)
    # issue 12: carrying positions (comma list, checked against gaitml.simulate.POSITIONS)
    p.add_argument(
        "--positions",
        metavar="LIST",
        default=None,
        help="comma-separated carrying positions, e.g. front-pocket,belt (a wrong name lists them all; default: the hand-held "
        "flat phone, one recording per subject; with a list, one recording per subject and position)",
    )

    p = sub.add_parser("steps", help="detect steps")
    p.add_argument("input", metavar="INPUT")
    p.add_argument(
        "--detector", **_choices("steps", "--detector", _step_detectors), default="single-peak", help="%(choices)s (default %(default)s)"
    )
    p.add_argument("--out", metavar="FILE", help="write the step table as CSV")
    p.add_argument("--json", action="store_true")
    _input_options(p)

    p = sub.add_parser("zupt", help="detect zero-velocity intervals")
    p.add_argument("input", metavar="INPUT")
    p.add_argument(
        "--detector", **_choices("zupt", "--detector", _zupt_detectors), default="pseudo-std", help="%(choices)s (default %(default)s)"
    )
    p.add_argument("--threshold-rads", type=float, help="detector threshold in rad/s (pseudo-std)")
    # --- issue 30: interval rules ---
    p.add_argument(
        "--interval-rules",
        choices=("stride", "fixed", "none"),
        help="pseudo-std, magnitude: stride (default: follow the local stride period), fixed (seconds), none (per-sample rule)",
    )
    # --- end issue 30 ---
    p.add_argument("--out", metavar="FILE", help="write the interval table as CSV")
    p.add_argument("--json", action="store_true")
    _input_options(p)

    p = sub.add_parser("features", help="extract windowed features")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--window-s", type=float, default=1.5)
    p.add_argument("--overlap", type=float, default=0.5)
    p.add_argument("--subset", **_choices("features", "--subset", _feature_sets), default="all52", help="%(choices)s (default %(default)s)")
    p.add_argument(
        "--frame",
        **_choices("features", "--frame", _feature_frames),
        default="phone",
        help="axes of the x/y/z features: phone (the phone's own, paper 003) or gravity (per-window up/forward/right, "
        "independent of the phone's orientation) (default %(default)s)",
    )
    p.add_argument("--out", metavar="FILE", help="write the feature table as CSV")
    _input_options(p)

    p = sub.add_parser("train", help="train a model from an experiment config")
    p.add_argument("config", metavar="CONFIG")
    p.add_argument("--out", metavar="MODEL_DIR")

    p = sub.add_parser("evaluate", help="run an experiment config (cross-validation, or the step-detector evaluation)")
    p.add_argument("config", metavar="CONFIG")
    p.add_argument("--out", metavar="RUN_DIR")
    p.add_argument("--data", metavar="DIR", help="read the data from DIR instead of the config's data.path")
    p.add_argument("--json", action="store_true")
    p.add_argument("--backend", default="joblib", help="joblib | dask")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address (with --backend dask)")

    p = sub.add_parser("predict", help="predict motion modes with a saved model")
    p.add_argument("model_dir", metavar="MODEL_DIR")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--out", metavar="FILE")
    p.add_argument("--no-correction", action="store_true", help="skip the adjacent-window correction")
    p.add_argument("--json", action="store_true")
    _input_options(p)

    p = sub.add_parser("pdr", help="pedestrian dead reckoning trajectory")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--model", metavar="MODEL_DIR")
    p.add_argument("--out", metavar="FILE")
    p.add_argument("--plot", metavar="PNG")
    p.add_argument("--json", action="store_true")
    p.add_argument(
        "--heading", **_choices("pdr", "--heading", _heading_sources), default="hde", help="heading source: %(choices)s (default hde)"
    )
    p.add_argument(
        "--modes",
        **_choices("pdr", "--modes", _mode_sources),
        help="motion modes per step: %(choices)s (default: model with --model, else the labels, else forward)",
    )
    p.add_argument(
        "--mode-boundaries",
        **_choices("pdr", "--mode-boundaries", _mode_assignments),
        default="auto",
        help="with --model: re-place each mode change at the most likely step (refine) or keep the nearest window's mode (nearest), "
        "or take the window nearest the middle of each step (middle); auto (default) refines when steps are timed by their peaks",
    )
    p.add_argument(
        "--detector",
        **_choices("pdr", "--detector", _step_detectors),
        default=None,
        help="step detector: %(choices)s (default single-peak, or a step-window model's own detector)",
    )
    p.add_argument("--step-length", metavar="JSON", help="calibrated step length model (StepLengthModel.save)")
    p.add_argument(
        "--initial-heading-rad",
        type=float,
        default=None,
        help="compass heading at the start (default: the reference trajectory's when the input has one, else 0 = north)",
    )
    _input_options(p)

    # --- gaitml model convert|export|card (gaitml/commands/model.py) ---
    p = sub.add_parser("model", help="convert, export or describe a saved model")
    msub = p.add_subparsers(dest="model_command", metavar="SUBCOMMAND", parser_class=_Parser, required=True)
    q = msub.add_parser(
        "convert", help="convert an old pickle model (model.joblib) to the data-only format; UNPICKLES it: trusted models only"
    )
    q.add_argument("old_dir", metavar="OLD_DIR")
    q.add_argument("new_dir", metavar="NEW_DIR")
    q = msub.add_parser("export", help="portable export: self-describing JSON (linear OVO SVM) or ONNX (extra gaitml[onnx])")
    q.add_argument("model_dir", metavar="MODEL_DIR")
    q.add_argument("--format", choices=("json", "onnx"), required=True)
    q.add_argument("--out", metavar="FILE", required=True)
    q = msub.add_parser("card", help="the model card (markdown) to stdout or --out")
    q.add_argument("model_dir", metavar="MODEL_DIR")
    q.add_argument("--out", metavar="FILE")
    # --- end gaitml model ---

    p = sub.add_parser("label", help="label a recording from time intervals, snapped to detected steps or strides")
    p.add_argument("input", metavar="INPUT")
    p.add_argument(
        "--intervals", metavar="FILE", required=True, help="CSV start_s,end_s,label or an Audacity label track (start<TAB>end<TAB>label)"
    )
    p.add_argument(
        "--snap", choices=("steps", "strides", "none"), default="steps", help="move boundaries to step or stride boundaries (default steps)"
    )
    p.add_argument(
        "--detector", help="step detector (steps/none; default single-peak) or zero-velocity detector (strides; default pseudo-std)"
    )
    p.add_argument(
        "--boundary",
        choices=("peak", "edges"),
        default="peak",
        help="step boundaries at the step events (default) or the detector's step start/end",
    )
    p.add_argument("--max-snap-s", type=float, default=0.5, help="largest move of a boundary in s (default 0.5)")
    p.add_argument(
        "--boundary-noise-s",
        type=float,
        help="the most a written boundary is off (s): snap only to the one step boundary within it, never guess (default: nearest)",
    )
    p.add_argument("--unlabelled", default="unlabelled", help="label of samples outside every interval (default unlabelled)")
    p.add_argument("--out", metavar="OUT.csv", required=True, help="labelled gaitml-csv; OUT.step-labels.csv is written beside it")
    p.add_argument("--report", metavar="PNG", help="plot the signal, intervals, steps and snapped boundaries")
    p.add_argument("--json", action="store_true")
    _input_options(p)

    # --- gaitml segment (gaitml/commands/segment.py) ---
    p = sub.add_parser("segment", help="cut a recording into steps, strides or zero-velocity intervals (a table of segments)")
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--by", choices=("steps", "strides", "zupt"), default="steps", help="%(choices)s (default %(default)s)")
    p.add_argument(
        "--detector",
        help="step detector for --by steps (default single-peak), zero-velocity detector for strides/zupt (default pseudo-std)",
    )
    p.add_argument(
        "--interval-rules",
        choices=("stride", "fixed", "none"),
        help="strides/zupt with pseudo-std or magnitude: stride (default), fixed, none (the per-sample rule)",
    )
    p.add_argument("--out", metavar="FILE", required=True, help="write the segment table as CSV")
    p.add_argument("--json", action="store_true")
    _input_options(p)
    # --- end gaitml segment ---

    p = sub.add_parser("demo", help="the main job end to end on simulated data")
    p.add_argument("--out", metavar="DIR", default="demo-out")

    p = sub.add_parser("bench", help="throughput benchmarks against reference implementations")
    p.add_argument("--out", metavar="DIR", default="bench-out")
    p.add_argument("--quick", action="store_true", help="smaller inputs (a smoke run)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            print("gaitml: error: no command given; see 'gaitml --help' for the commands.", file=sys.stderr)
            return 2
        module = importlib.import_module(f"gaitml.commands.{args.command}")
        return int(module.run(args) or 0)
    except _UsageError as exc:
        print(f"gaitml: error: {exc}", file=sys.stderr)
        return 2
    except GaitmlError as exc:
        msg = " ".join(str(exc).split())
        print(f"gaitml: error: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("gaitml: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError as exc:
        if _stdout_closed():  # `gaitml ... | head`: the reader went away, not an error of ours
            return 0
        return _internal_error(exc)
    except (PermissionError, IsADirectoryError, NotADirectoryError, FileExistsError) as exc:
        where = f" {exc.filename}" if exc.filename else ""
        print(f"gaitml: error: {exc.strerror or type(exc).__name__}:{where}; check the path and its permissions.", file=sys.stderr)
        return 2
    except Exception as exc:  # an internal error: a bug to report
        return _internal_error(exc)


def _stdout_closed() -> bool:
    """Whether stdout is a pipe whose reading end was closed."""
    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLERR)
        return bool(poller.poll(0))
    except (OSError, ValueError, AttributeError):
        return False


def _internal_error(exc: BaseException) -> int:
    if os.environ.get("GAITML_DEBUG"):
        traceback.print_exception(exc)
    msg = " ".join(str(exc).split())
    print(f"gaitml: internal error: {type(exc).__name__}: {msg} (set GAITML_DEBUG=1 for the traceback; please report it)", file=sys.stderr)
    return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
