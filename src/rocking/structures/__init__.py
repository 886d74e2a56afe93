"""Buildings whose floors carry the bodies (paper Section 7).

* :mod:`~rocking.structures.frames` — uniform and general shear frames, floor accelerations.
"""
