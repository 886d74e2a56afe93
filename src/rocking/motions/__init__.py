"""Ground and floor motions and their spectra (paper Sections 3–4).

* :mod:`~rocking.motions.targets` — target spectra: RG 1.60, tables;
* :mod:`~rocking.motions.design` — design spectra: ASCE 7, Eurocode 8, specifications;
* :mod:`~rocking.motions.response` — response spectra of motions (SDOF recurrence);
* :mod:`~rocking.motions.psd` — power spectra compatible with a target (Eqs. 4–8);
* :mod:`~rocking.motions.envelopes` — intensity functions (Fig. 2, Eq. 7);
* :mod:`~rocking.motions.synthesis` — simulated motions (Eq. 9), the iterative correction, the fit;
* :mod:`~rocking.motions.baseline` — quadratic baseline correction (Section 4);
* :mod:`~rocking.motions.records` — reading recorded accelerations (PEER .AT2, text, networks);
* :mod:`~rocking.motions.formats` — K-NET/KiK-net, ESM/ITACA, COSMOS, SAC and miniSEED files;
* :mod:`~rocking.motions.units` — units of acceleration, plausible peaks;
* :mod:`~rocking.motions.ensemble` — :class:`Ensemble`, motions with labels and metadata;
* :mod:`~rocking.motions.intensity` — intensity measures of motions (PGA, PGV, Sa, …);
* :mod:`~rocking.motions.pulses` — idealised near-fault pulses (:func:`pulse`);
* :mod:`~rocking.motions.wavelets` — pulse-like records and their pulse period
  (:func:`~rocking.motions.wavelets.pulse_period`, Shahi & Baker 2014).
"""

from ..core.exports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, globals())
