"""`gaitml model convert|export|card`: model folders in the data-only format, portable exports, model cards.

- ``gaitml model convert OLD_DIR NEW_DIR``: an old pickle model (``model.joblib``)
  to the data-only format. It UNPICKLES the old model: run it only on a model
  from a source you trust.
- ``gaitml model export MODEL_DIR --format json|onnx --out FILE``: the
  self-describing JSON (linear OVO SVM) or an ONNX file (optional extra ``onnx``).
- ``gaitml model card MODEL_DIR [--out FILE]``: the model card (markdown) from
  ``model.json``, to stdout or a file; the model's data files are hash-checked
  but not opened.
"""

from __future__ import annotations

import argparse

from gaitml.commands._args import Parser
from gaitml.commands._util import log

#: The command's one-line description in ``gaitml --help``.
HELP = "convert, export or describe a saved model"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml model`` on its parser ``p``."""
    msub = p.add_subparsers(dest="model_command", metavar="SUBCOMMAND", parser_class=Parser, required=True)
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


def _convert(args) -> int:
    from gaitml.models import convert_model

    new = convert_model(args.old_dir, args.new_dir)
    log(
        f"gaitml model convert: {args.old_dir} -> {new.path} (data-only: {', '.join(sorted(new.info['files']))}, MODEL.md); predictions checked equal"
    )
    return 0


def _export(args) -> int:
    from gaitml.io import write_text
    from gaitml.models import export_json, export_onnx, load_model

    model = load_model(args.model_dir)
    if args.format == "json":
        import json

        write_text(args.out, json.dumps(export_json(model), indent=1) + "\n")
    else:
        export_onnx(model, args.out)
    log(f"gaitml model export: {args.format} of {args.model_dir} written to {args.out}")
    return 0


def _card(args) -> int:
    import sys

    from gaitml.io import write_text
    from gaitml.models import model_card, read_model_json

    _, info = read_model_json(args.model_dir)
    text = model_card(info)
    if args.out:
        write_text(args.out, text)
        log(f"gaitml model card: written to {args.out}")
    else:
        sys.stdout.write(text)
    return 0


def run(args) -> int:
    """Dispatch ``gaitml model SUBCOMMAND``."""
    return {"convert": _convert, "export": _export, "card": _card}[args.model_command](args)
