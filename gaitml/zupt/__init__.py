"""gaitml.zupt (see DESIGN sec. 1)."""
