"""Buildings whose floors carry the bodies (paper Section 7).

* :mod:`~rocking.structures.frames` — uniform and general shear frames, floor accelerations.
"""

from ..core.exports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, globals())
