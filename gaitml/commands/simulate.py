"""`gaitml simulate`: not built yet (exits 2 rather than pretending)."""

from gaitml.errors import NotAvailableError


def run(args) -> int:
    raise NotAvailableError("'gaitml simulate' is not available yet in this version; see the README for what works.")
