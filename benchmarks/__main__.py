"""``python -m benchmarks``: every benchmark, as ``gaitml bench``."""

import sys

from benchmarks import main

sys.exit(main())
