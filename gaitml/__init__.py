"""gaitml: smartphone gait and motion-mode recognition and pedestrian dead reckoning.

Start with :func:`gaitml.io.read_recording` (a :class:`gaitml.recording.Recording`;
or the simulator in :mod:`gaitml.simulate`), then the step detectors in
:mod:`gaitml.steps`, the zero-velocity detectors in :mod:`gaitml.zupt`, the
features and models for motion-mode recognition, and :mod:`gaitml.pdr` for
trajectories.

The package root holds only the version and the error classes (the lowest layer),
so importing any part of gaitml does not import the rest.
"""

from gaitml.errors import ConfigError, GaitmlError, InputError, ModelError

__version__ = "0.1.0"

__all__ = ["ConfigError", "GaitmlError", "InputError", "ModelError", "__version__"]
