"""Lab scripts and experiment configs of the repository (not part of the installed package)."""
