"""gaitml.models (see DESIGN sec. 1)."""
