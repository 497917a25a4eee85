"""The hostile corpus on the large-file road (issue 28 finding 2): the same outcome per class as a small file.

Every input class of :data:`tests.hostile.corpus.RECORDING_CASES` is run through the
commands that have a chunked road (``steps, zupt, features, predict, pdr``) with that road
forced (``gaitml.io.chunked.LARGE_INPUT_SAMPLES`` below every input) and the file read
in blocks of 300 rows, so that the first block is not the file. The outcome must be
the one the class declares for a small file, and accepted variants of the base walk
must give the small base walk's answer.
"""

from __future__ import annotations

import pytest

import gaitml.io.chunked as ch
from tests.hostile.corpus import OK, RECORDING_CASES
from tests.hostile.runner import check_contract, command_argv, run_cli
from tests.hostile.test_recordings_cli import CASES, _same_answer, _table, base_answers, inputs  # noqa: F401 (fixtures)

CHUNKED_COMMANDS = ("steps", "zupt", "features", "predict", "pdr")
PAIRS = [(c.name, cmd) for c in RECORDING_CASES for cmd in CHUNKED_COMMANDS]


@pytest.mark.parametrize(("case_name", "command"), PAIRS, ids=[f"{c}-{m}" for c, m in PAIRS])
def test_command_on_hostile_input_chunked(case_name, command, inputs, base_answers, tmp_path, monkeypatch):  # noqa: F811
    case = CASES[case_name]
    path = inputs(case)
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1)
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 300)
    out = tmp_path / "out"
    out.mkdir()
    argv = command_argv(command, path, out, case.args)
    code, stdout, stderr = run_cli(argv)
    js = check_contract(argv, code, stdout, stderr, case.outcome(command), out)
    if code != 0:
        return
    table = _table(argv)
    if case.same_as_base:
        _same_answer(case, command, js, table, base_answers)
    if case.check is not None and case.outcome(command) == OK:
        case.check(command, js, table)
