"""gaitml.bench (see DESIGN sec. 1)."""
