"""``python -m gaitml ...``: the same command line as the ``gaitml`` entry point."""

import sys

from gaitml.cli import main

if __name__ == "__main__":
    sys.exit(main())
