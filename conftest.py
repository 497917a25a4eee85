"""Session options shared by the library's tests (``tests/``) and the lab's (``experiments/tests/``).

``--random-order`` runs the test modules in a shuffled order and each module's tests
(class by class) in a shuffled order, so that a test that only passes after another one
has run shows up; the seed is printed at the start and the end of the run, and
``--random-order-seed=N`` repeats that order. Shuffling happens before pytest groups tests
by their module- and class-scoped fixtures, so those are still set up once per group.

A run that selects no test at all (a path or marker expression that matches nothing)
fails with exit status 1 and says so, instead of pytest's exit status 5, which a CI
script could take for something other than a failure.
This does what the pytest-randomly plugin's ordering does, in a page, without a test
dependency and without reseeding global random states (tests here use their own seeded
generators, so a reseed would only hide a test that does not).
"""

from __future__ import annotations

import os
import random

import pytest

_SEED = pytest.StashKey[int | None]()
_NO_TESTS = pytest.StashKey[bool]()


def pytest_addoption(parser):
    group = parser.getgroup("random-order")
    group.addoption(
        "--random-order",
        action="store_true",
        default=False,
        help="run modules, and the tests in each module, in a shuffled order (a new seed each run unless given)",
    )
    group.addoption(
        "--random-order-seed",
        type=int,
        default=None,
        metavar="N",
        help="shuffle with seed N (implies --random-order); also read from $GAITML_TEST_SEED",
    )


def pytest_configure(config):
    seed = config.getoption("random_order_seed")
    if seed is None and os.environ.get("GAITML_TEST_SEED", "").strip():
        seed = int(os.environ["GAITML_TEST_SEED"])
    if seed is None and config.getoption("random_order"):
        seed = random.SystemRandom().randrange(1, 2**31)
    config.stash[_SEED] = seed


def _message(config) -> str | None:
    seed = config.stash.get(_SEED, None)
    return None if seed is None else f"random test order: seed {seed} (repeat it with --random-order-seed={seed})"


def pytest_report_header(config):
    return _message(config)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(session, config, items):
    seed = config.stash.get(_SEED, None)
    if seed is None:
        return
    rng = random.Random(seed)
    modules: dict = {}
    for item in items:  # module -> class (or the module's functions) -> items, in collection order
        cls = item.getparent(pytest.Class)
        modules.setdefault(item.path, {}).setdefault(cls.nodeid if cls is not None else None, []).append(item)
    groups = list(modules.values())
    rng.shuffle(groups)
    shuffled = []
    for classes in groups:
        buckets = list(classes.values())
        rng.shuffle(buckets)
        for bucket in buckets:
            rng.shuffle(bucket)
            shuffled.extend(bucket)
    items[:] = shuffled


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    msg = _message(config)
    if msg:
        terminalreporter.write_line(msg)


def pytest_sessionfinish(session, exitstatus):
    if exitstatus == pytest.ExitCode.NO_TESTS_COLLECTED:
        session.config.stash[_NO_TESTS] = True
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    if config.stash.get(_NO_TESTS, False):
        import sys

        print("conftest.py: no test was selected (check the paths and the -m / -k expressions); failing the run", file=sys.stderr)
