"""The CLI's fixed choices are the package registries' names (one source for names)."""

from __future__ import annotations

import argparse
import sys

import pytest

from gaitml.cli import REGISTRY_CHOICES, build_parser, main


def _option(command: str, option: str) -> argparse.Action:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return next(a for a in sub.choices[command]._actions if option in a.option_strings)


def _registries() -> dict:
    import gaitml.features
    import gaitml.io
    import gaitml.pdr
    import gaitml.steps
    import gaitml.zupt
    from gaitml.features._catalogue import SUBSET_ALIASES
    from gaitml.pdr.attitude import GYRO_BIAS_MODES
    from gaitml.pdr.step_modes import MODE_ASSIGNMENTS

    return {
        ("steps", "--detector"): tuple(gaitml.steps.detector_names()),
        ("pdr", "--detector"): tuple(gaitml.steps.detector_names()),
        ("zupt", "--detector"): tuple(gaitml.zupt.DETECTORS),
        ("pdr", "--heading"): tuple(gaitml.pdr.HEADING_SOURCES),
        ("pdr", "--modes"): tuple(gaitml.pdr.MODE_SOURCES),
        ("pdr", "--mode-boundaries"): tuple(MODE_ASSIGNMENTS),
        ("pdr", "--gyro-bias"): tuple(GYRO_BIAS_MODES),
        ("features", "--subset"): (*gaitml.features.FEATURE_SETS, *SUBSET_ALIASES),
        ("features", "--frame"): tuple(gaitml.features.FEATURE_FRAMES),
        **{
            (c, "--format"): tuple(gaitml.io.FORMATS)
            for c in ("info", "steps", "zupt", "features", "predict", "pdr", "label", "split", "segment")
        },
    }


@pytest.mark.parametrize("key", sorted(_registries()), ids=lambda k: f"{k[0]} {k[1]}")
def test_cli_choices_equal_the_registry(key):
    command, option = key
    assert tuple(_option(command, option).choices) == _registries()[key]


def test_every_registry_backed_option_is_checked():
    build_parser()
    assert set(REGISTRY_CHOICES) == set(_registries())


def test_building_the_parser_imports_no_algorithm():
    """`gaitml --help` stays fast: the registries are read only when a value is checked."""
    import subprocess

    code = (
        "import sys; from gaitml.cli import build_parser; build_parser(); print(sorted(m for m in sys.modules if m.startswith('gaitml.')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert not {"gaitml.steps", "gaitml.zupt", "gaitml.pdr", "gaitml.features"} & set(eval(out))


def test_a_name_outside_the_registry_is_a_one_line_usage_error(capsys):
    assert main(["zupt", "x.csv", "--detector", "nope"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "invalid choice: 'nope'" in err and "'pseudo-std'" in err
