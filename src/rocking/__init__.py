"""rocking: rocking and overturning of free-standing rigid blocks under earthquakes.

SI units throughout (m, s, m/s², rad); intensities such as A_gx are in g.
"""

from .body import G, Block, housner_sv
from .errors import InputError, RockingError

__all__ = ["G", "Block", "housner_sv", "InputError", "RockingError"]

try:
    from importlib.metadata import version as _version

    __version__ = _version("rocking")
except Exception:  # pragma: no cover - not installed (running from a source tree)
    __version__ = "0+unknown"
