"""Hostile model folders, experiment configs and output places, through the CLI: one-line refusals, nothing left behind.

Model files are attacked through the loader's public behaviour only (a refusal
names the model and a fix, exit 2), so these tests hold whatever the files of a
model folder are: every file of ``models/demo`` is truncated and edited in turn.
Outputs go where nothing can be written *even by root* (the tests run as root, so
a chmod-ed folder would not stop them): under a regular file, into ``/proc``, onto
``/dev/full``, and onto a full disk simulated by lowering ``RLIMIT_FSIZE`` (writes
past the limit fail with EFBIG, as on a full disk).
"""

from __future__ import annotations

import contextlib
import json
import os
import resource
import shutil
import signal
import stat
from pathlib import Path

import pytest

from tests.hostile.corpus import BASE_CSV, DEMO_MODEL, OK
from tests.hostile.runner import check_contract, command_argv, files_in, run_cli, run_subprocess
from tests.models.synth import write_synth_folder

MODEL = r"model"


# ----------------------------------------------------------------- models
def _model_files() -> list[str]:
    return sorted(p.name for p in DEMO_MODEL.iterdir() if p.is_file())


def _copy_model(d: Path) -> Path:
    m = d / "model"
    shutil.copytree(DEMO_MODEL, m)
    return m


def _truncate(name: str):
    def make(d: Path) -> Path:
        m = _copy_model(d)
        f = m / name
        f.write_bytes(f.read_bytes()[: f.stat().st_size // 2])
        return m

    return make


def _edit(name: str):
    """Edit one file: a byte flipped in the middle of a data file, a setting changed in a JSON file."""

    def make(d: Path) -> Path:
        m = _copy_model(d)
        f = m / name
        if name.endswith(".json"):
            info = json.loads(f.read_text())
            assert isinstance(info.get("window"), dict) and "length_s" in info["window"], (
                "assumption: model.json keeps window.length_s (edit another training setting here if the format changed)"
            )
            info["window"]["length_s"] = float(info["window"]["length_s"]) * 2
            f.write_text(json.dumps(info, indent=2))
        else:
            data = bytearray(f.read_bytes())
            data[len(data) // 2] ^= 0xFF
            f.write_bytes(bytes(data))
        return m

    return make


def _symlink_ok(d: Path) -> Path:
    (d / "link").symlink_to(DEMO_MODEL, target_is_directory=True)
    return d / "link"


def _symlink_dangling(d: Path) -> Path:
    (d / "link").symlink_to(d / "gone", target_is_directory=True)
    return d / "link"


def _symlink_loop(d: Path) -> Path:
    (d / "a").symlink_to(d / "b")
    (d / "b").symlink_to(d / "a")
    return d / "a"


def _symlinked_files(d: Path) -> Path:
    """A model folder whose files are symlinks to the shipped model's files."""
    m = d / "model"
    m.mkdir()
    for name in _model_files():
        (m / name).symlink_to(DEMO_MODEL / name)
    return m


def _empty(d: Path) -> Path:
    (d / "model").mkdir()
    return d / "model"


def _a_file(d: Path) -> Path:
    (d / "model").write_text("not a model\n")
    return d / "model"


MODEL_CASES = {
    "symlinked-folder": (_symlink_ok, OK),
    "symlinked-files": (_symlinked_files, OK),
    "dangling-symlink": (_symlink_dangling, MODEL),
    "symlink-loop": (_symlink_loop, MODEL),
    "empty-folder": (_empty, MODEL),
    "a-file": (_a_file, MODEL),
    # a damaged data file is refused; MODEL.md is the human-readable card, never read to predict:
    # damaging it changes nothing (same answer as the shipped model)
    **{f"truncated-{n}": (_truncate(n), OK if n == "MODEL.md" else MODEL) for n in _model_files()},
    **{f"edited-{n}": (_edit(n), OK if n == "MODEL.md" else MODEL) for n in _model_files()},
}
MODEL_PAIRS = [(name, cmd) for name in MODEL_CASES for cmd in ("predict", "pdr")]


@pytest.fixture(scope="module")
def demo_answers(tmp_path_factory):
    out = {}
    for cmd in ("predict", "pdr"):
        d = tmp_path_factory.mktemp(f"demo-{cmd}")
        argv = _model_argv(cmd, DEMO_MODEL, d)
        code, stdout, stderr = run_cli(argv)
        out[cmd] = check_contract(argv, code, stdout, stderr, OK, d)
    return out


def _model_argv(cmd: str, model: Path, out: Path) -> list[str]:
    if cmd == "predict":
        return command_argv("predict", BASE_CSV, out, model=model)
    return command_argv("pdr", BASE_CSV, out, ("--model", str(model)))


@pytest.mark.parametrize(("case", "command"), MODEL_PAIRS, ids=[f"{a}-{b}" for a, b in MODEL_PAIRS])
def test_hostile_model_folder(case, command, tmp_path, demo_answers):
    make, expect = MODEL_CASES[case]
    model = make(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    argv = _model_argv(command, model, out)
    code, stdout, stderr = run_cli(argv)
    js = check_contract(argv, code, stdout, stderr, expect, out)
    if js is not None:  # a symlinked model (or one with a damaged card) is the shipped model: the same answer
        strip = {"model"}
        assert {k: v for k, v in js.items() if k not in strip} == {k: v for k, v in demo_answers[command].items() if k not in strip}


# ----------------------------------------------------------------- configs
@pytest.fixture(scope="module")
def config_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("configs")
    write_synth_folder(d / "data", n_subjects=3, seconds_per_mode=6.0)
    write_synth_folder(d / "nolabels", n_subjects=3, seconds_per_mode=6.0, with_labels=False)
    return d


_BASE_TOML = 'name = "hostile"\n[data]\nsource = "folder"\npath = "data"\n[cv]\nn_jobs = 1\n'
_GRID = ", ".join(str(0.5 + i / 100) for i in range(100))
CONFIG_CASES = {
    # name: (toml text, expected outcome)
    "ok": (_BASE_TOML, OK),
    "unknown-top-key": (_BASE_TOML + "[windowz]\nlength_s = 2.0\n", r"unknown key windowz"),
    "unknown-nested-key": (_BASE_TOML + "[windows]\nlenght_s = 2.0\n", r"lenght_s"),
    "huge-sweep-grid": (
        _BASE_TOML + f'[sweep]\n"windows.length_s" = [{_GRID}]\n"windows.overlap" = [{", ".join(str(i / 200) for i in range(100))}]\n',
        r"10000 grid points \(100 x 100\), more than 1000",
    ),
    "n-jobs-in-the-thousands": (_BASE_TOML.replace("n_jobs = 1", "n_jobs = 5000"), OK),
    "missing-labels": (_BASE_TOML.replace('path = "data"', 'path = "nolabels"'), r"label"),
    "one-class": (_BASE_TOML.replace('path = "data"', 'path = "data"\nlabels = ["walk"]'), r"at least 2"),
    "bad-toml": ('name = "x"\n[data\n', r"not valid TOML"),
    "binary-config": ("\x00\x01\x02 garbage \xff", r"TOML|config"),
    "empty-config": ("", r"name"),
}
CONFIG_PAIRS = [(name, cmd) for name in CONFIG_CASES for cmd in ("evaluate", "train")]


def _config_argv(cmd: str, cfg: Path, out: Path) -> list[str]:
    argv = [cmd, str(cfg), "--out", str(out / ("run" if cmd == "evaluate" else "model"))]
    return argv + (["--json"] if cmd == "evaluate" else [])


@pytest.mark.parametrize(("case", "command"), CONFIG_PAIRS, ids=[f"{a}-{b}" for a, b in CONFIG_PAIRS])
def test_hostile_config(case, command, config_dir, tmp_path):
    if case == "n-jobs-in-the-thousands" and command == "train":
        pytest.skip("train runs the same cross-validation as evaluate (covered there)")
    text, expect = CONFIG_CASES[case]
    cfg = config_dir / f"{case}-{command}.toml"
    cfg.write_text(text, encoding="utf-8", errors="surrogateescape")
    out = tmp_path / "out"
    out.mkdir()
    argv = _config_argv(command, cfg, out)
    code, stdout, stderr = run_cli(argv)
    # evaluate shows a progress bar on stderr; the contract concerns the last line of a failure
    stderr_lines = [ln for ln in stderr.replace("\r", "\n").split("\n") if ln.strip() and "it/s]" not in ln and "s/it]" not in ln]
    js = check_contract(argv, code, stdout, "\n".join(stderr_lines) + "\n", expect, out)
    if code == 0 and command == "evaluate":
        assert js["accuracy"] > 0.9, js  # three well separated synthetic modes
    if code == 0 and command == "train":
        p_out = tmp_path / "p"
        p_out.mkdir()
        pargv = command_argv("predict", config_dir / "data" / "s0_InHand.csv", p_out, model=out / "model")
        code2, so, se = run_cli(pargv)
        assert len(check_contract(pargv, code2, so, se, OK, p_out)["windows"]) > 0


# ----------------------------------------------------------------- outputs
def _under_a_file(tmp: Path) -> Path:
    f = tmp / "plain-file"
    f.write_text("x")
    return f / "sub" / "out"


OUTPUT_PLACES = {
    "under-a-regular-file": (_under_a_file, r"a part of its folder path is a file|is a file, not a folder|not a directory"),
    "in-proc": (lambda tmp: Path("/proc/gaitml-hostile-out"), r"cannot write|No such file|Permission|not permitted"),
    "existing-folder-of-other-files": (lambda tmp: _folder_of_files(tmp), r"folder|is a directory|existing"),
}


def _folder_of_files(tmp: Path) -> Path:
    d = tmp / "precious"
    d.mkdir()
    (d / "thesis.tex").write_text("keep me")
    return d


OUTPUT_COMMANDS = ("steps", "features", "pdr", "train", "evaluate")


def _out_argv(command: str, target: Path, config_dir: Path) -> list[str]:
    if command in ("train", "evaluate"):
        cfg = config_dir / "ok-out.toml"
        cfg.write_text(_BASE_TOML)
        return [command, str(cfg), "--out", str(target)]
    argv = command_argv(command, BASE_CSV, target.parent)
    i = argv.index("--out")
    argv[i + 1] = str(target)
    return argv


@pytest.mark.parametrize("place", list(OUTPUT_PLACES))
@pytest.mark.parametrize("command", OUTPUT_COMMANDS)
def test_unwritable_output(place, command, tmp_path, config_dir):
    make, expect = OUTPUT_PLACES[place]
    target = make(tmp_path)
    before = files_in(tmp_path)
    argv = _out_argv(command, target, config_dir)
    code, stdout, stderr = run_cli(argv)
    stderr = "\n".join(ln for ln in stderr.replace("\r", "\n").split("\n") if ln.strip() and "/it]" not in ln and "it/s]" not in ln)
    check_contract(argv, code, stdout, stderr + "\n", expect, tmp_path, before=before)
    if place == "existing-folder-of-other-files" or command in ("steps", "features", "pdr"):
        assert files_in(tmp_path) == before


@contextlib.contextmanager
def _disk_full(limit_bytes: int = 2000):
    """Simulate a full disk in this process: files cannot grow past ``limit_bytes`` (EFBIG)."""
    old = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, old[1]))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, old)
        signal.signal(signal.SIGXFSZ, old_handler)


@pytest.mark.parametrize("command", OUTPUT_COMMANDS)
def test_full_disk(command, tmp_path, config_dir):
    target = tmp_path / "out" / ("result" if command in ("train", "evaluate") else "result.csv")
    argv = _out_argv(command, target, config_dir)
    if command == "evaluate":
        argv.append("--json")
    with _disk_full():
        code, stdout, stderr = run_cli(argv)
    stderr = "\n".join(ln for ln in stderr.replace("\r", "\n").split("\n") if ln.strip() and "/it]" not in ln and "it/s]" not in ln)
    check_contract(argv, code, stdout, stderr + "\n", r"File too large|No space left", tmp_path / "out")


def test_dev_full_and_dev_null(tmp_path):
    """A device as the output is written to, never replaced by a regular file (the tests run as root)."""
    argv = command_argv("steps", BASE_CSV, tmp_path)
    i = argv.index("--out")
    argv[i + 1] = "/dev/full"
    code, stdout, stderr = run_cli(argv)
    check_contract(argv, code, stdout, stderr, r"No space left on device", tmp_path)
    argv[i + 1] = "/dev/null"
    code, stdout, stderr = run_cli(argv)
    check_contract(argv, code, stdout, stderr, OK, tmp_path)
    for dev in ("/dev/full", "/dev/null"):
        assert stat.S_ISCHR(os.stat(dev).st_mode), f"{dev} is no longer a device"


def test_full_disk_real_entry_point(tmp_path):
    """The full-disk refusal through ``python -m gaitml.cli`` (RLIMIT_FSIZE set in the child)."""

    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (2000, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))

    out = tmp_path / "out"
    argv = command_argv("features", BASE_CSV, out)
    code, stdout, stderr = run_subprocess(argv, preexec_fn=limit)
    check_contract(argv, code, stdout, stderr, r"File too large", out)
