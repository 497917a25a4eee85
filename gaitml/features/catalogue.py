"""Print or write the feature catalogue: ``python -m gaitml.features.catalogue [--out FILE]``.

The catalogue itself (entries, subsets, markdown) lives in
:mod:`gaitml.features._catalogue` and is re-exported by :mod:`gaitml.features`;
the committed ``features/catalogue.md`` is ``catalogue_markdown()`` (a test checks it).
"""

from __future__ import annotations

import sys

from gaitml.features._catalogue import *  # noqa: F403  (the public catalogue names)
from gaitml.features._catalogue import __all__, main  # noqa: F401

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
