"""Output paths checked against input paths before a command reads anything (DESIGN sec. 5).

Every command declares which of its arguments it reads (:data:`INPUTS`) and
which it writes (:data:`OUTPUTS`). :func:`check_outputs` refuses, with one line
naming both paths, an output that

- is one of the inputs (the same path, a symbolic link to it or a hard link of it),
- lies inside a model folder the command reads (a model is a folder of files that
  must stay consistent: ``model.json``, ``arrays.npz``, the card),
- is a folder the command replaces while an input lies inside it,
- ends with a path separator although the command writes a file there
  (``--out newdir/`` would otherwise write a file named ``newdir``),
- is the standard output while ``--json`` prints its object there (a table and a
  JSON object mixed on one stream can be read as neither).

It runs in :func:`gaitml.cli.main` after the arguments are parsed and before a
command's handler, so that no file is read or written when an output is refused.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from gaitml.errors import InputError

__all__ = ["INPUTS", "OUTPUTS", "MODEL_INPUTS", "check_outputs", "same_file"]

#: The arguments each command reads (files or folders): ``{command: (dest, ...)}``.
INPUTS: dict[str, tuple[str, ...]] = {
    "info": ("input",),
    "split": ("input",),
    "steps": ("input",),
    "zupt": ("input",),
    "features": ("input",),
    "train": ("config",),
    "evaluate": ("config", "data"),
    "predict": ("model_dir", "input"),
    "pdr": ("input", "model", "step_length", "truth"),
    "label": ("input", "intervals"),
    "segment": ("input",),
    "model convert": ("old_dir",),
    "model export": ("model_dir",),
    "model card": ("model_dir",),
}
#: Inputs that are model folders: no output may be written inside them.
MODEL_INPUTS = ("model_dir", "model", "old_dir")
#: The arguments each command writes, with the kind of path: ``"file"`` or ``"dir"`` (a folder it creates or replaces).
OUTPUTS: dict[str, tuple[tuple[str, str], ...]] = {
    "split": (("out", "dir"),),
    "simulate": (("out_dir", "dir"),),
    "steps": (("out", "file"),),
    "zupt": (("out", "file"),),
    "features": (("out", "file"),),
    "train": (("out", "dir"),),
    "evaluate": (("out", "dir"),),
    "predict": (("out", "file"),),
    "pdr": (("out", "file"), ("plot", "file")),
    "label": (("out", "file"), ("report", "file")),
    "segment": (("out", "file"),),
    "model convert": (("new_dir", "dir"),),
    "model export": (("out", "file"),),
    "model card": (("out", "file"),),
    "demo": (("out", "dir"),),
    "bench": (("out", "dir"),),
}
#: Flags as the user types them, for the messages.
_FLAG = {"out": "--out", "plot": "--plot", "report": "--report", "out_dir": "OUT_DIR", "new_dir": "NEW_DIR"}


def command_name(args) -> str:
    """``args.command``, with the subcommand for ``gaitml model``."""
    sub = getattr(args, "model_command", None)
    return f"{args.command} {sub}" if args.command == "model" and sub else str(args.command)


def same_file(a: Path, b: Path) -> bool:
    """Whether two paths name the same file or folder (resolved links, hard links)."""
    try:
        if a.resolve() == b.resolve():
            return True
    except (OSError, RuntimeError):
        pass
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _inside(child: Path, folder: Path) -> bool:
    """Whether ``child`` is ``folder`` or lies below it (after resolving links)."""
    try:
        c, f = child.resolve(), folder.resolve()
    except (OSError, RuntimeError):
        return False
    return c == f or f in c.parents


def _is_stdout(path: Path) -> bool:
    """Whether ``path`` is the process's standard output (``/dev/stdout``, ``/dev/fd/1``, or the file stdout writes to)."""
    if str(path) in ("-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"):
        return True
    try:
        st = os.stat(path)
        out = os.fstat(sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        return False
    return (st.st_dev, st.st_ino) == (out.st_dev, out.st_ino)


def _extra_outputs(command: str, args) -> list[tuple[str, Path]]:
    """Files a command writes beside its named output (``label``: ``OUT.step-labels.csv``)."""
    if command == "label" and getattr(args, "out", None):
        from gaitml.commands.label import step_labels_path

        return [("--out's step table", step_labels_path(args.out))]
    return []


def check_outputs(args) -> None:
    """Refuse (InputError, one line) an output path that would replace or corrupt an input; see the module docstring."""
    command = command_name(args)
    # `--truth self` names no file: the truth is read from the input itself
    inputs = [
        (dest, Path(v)) for dest in INPUTS.get(command, ()) if (v := getattr(args, dest, None)) and not (dest == "truth" and v == "self")
    ]
    outputs: list[tuple[str, Path, str]] = []
    for dest, kind in OUTPUTS.get(command, ()):
        value = getattr(args, dest, None)
        if not value:
            continue
        flag = _FLAG.get(dest, f"--{dest.replace('_', '-')}")
        if kind == "file" and str(value).endswith((os.sep, "/")) and not _is_stdout(Path(value)):
            raise InputError(
                f"{flag} {value} ends with '/', a folder, but {command} writes a file there; give a file path such as {value.rstrip('/')}/out.csv."
            )
        if kind == "file" and getattr(args, "json", False) and _is_stdout(Path(value)):
            raise InputError(
                f"{flag} {value} is the standard output, where --json prints its object; write the table to a file or drop --json."
            )
        outputs.append((flag, Path(value), kind))
        outputs.extend((f2, p2, "file") for f2, p2 in _extra_outputs(command, args) if dest == "out")
    for flag, out, kind in outputs:
        for dest, inp in inputs:
            what = f"the input {inp}" if dest == "input" else f"{dest.replace('_', '-')} {inp}"
            if same_file(out, inp):
                raise InputError(f"{flag} {out} is {what}: writing would destroy it; choose another output path.")
            if dest in MODEL_INPUTS and _inside(out, inp):
                raise InputError(f"{flag} {out} is inside the model folder {inp} that {command} reads; write outside the model folder.")
            if kind == "dir" and _inside(inp, out):
                raise InputError(f"{flag} {out} would be replaced but holds {what}; choose an output folder that holds no input.")
    for i, (f1, p1, _) in enumerate(outputs):
        for f2, p2, _ in outputs[i + 1 :]:
            if same_file(p1, p2):
                raise InputError(f"{f1} and {f2} are the same file {p1}; give them different paths.")
