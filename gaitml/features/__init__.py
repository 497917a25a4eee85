"""gaitml.features (see DESIGN sec. 1)."""
