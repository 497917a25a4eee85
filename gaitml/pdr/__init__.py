"""gaitml.pdr (see DESIGN sec. 1)."""
