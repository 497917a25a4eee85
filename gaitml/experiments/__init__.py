"""gaitml.experiments (see DESIGN sec. 1)."""
