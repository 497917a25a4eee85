"""gaitml: smartphone gait and motion-mode recognition and pedestrian dead reckoning.

Start with :func:`gaitml.io.read_recording` (or the simulator in
:mod:`gaitml.simulate`), then the step detectors in :mod:`gaitml.steps`, the
zero-velocity detectors in :mod:`gaitml.zupt`, the features and models for
motion-mode recognition, and :mod:`gaitml.pdr` for trajectories.
"""

from gaitml.errors import ConfigError, GaitmlError, InputError, ModelError
from gaitml.recording import Recording

__version__ = "0.1.0"

__all__ = ["ConfigError", "GaitmlError", "InputError", "ModelError", "Recording", "__version__"]
