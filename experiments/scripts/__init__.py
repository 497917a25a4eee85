"""Report and lab scripts: run from the repository root, ``python -m experiments.scripts.<name> --help``."""
