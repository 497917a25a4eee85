"""gaitml.simulate (see DESIGN sec. 1)."""
