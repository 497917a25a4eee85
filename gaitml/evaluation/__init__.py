"""gaitml.evaluation (see DESIGN sec. 1)."""
