"""One module per CLI subcommand: ``run(args) -> int`` (see :mod:`gaitml.cli`)."""
