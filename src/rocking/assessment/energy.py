"""Housner's energy-balance check (paper Section 8): required against available pseudo-velocity.

* Required S_v (Eq. 11, :func:`rocking.dynamics.body.housner_sv`): the pseudo-velocity that
  overturns a body with about 50 % probability.
* Available S_v (:func:`available_sv`): the largest value of a 5 %-damped pseudo-velocity spectrum
  (the mean spectrum of an ensemble) in a low-frequency band, 0.04–0.6 Hz in the paper, because a
  rocking body about to overturn oscillates slowly and floor spectra have spikes at higher
  frequencies. For an ensemble scaled to a body's A_gx at 50 % probability this is the paper's
  S_v1 (Tables 2 and 3, Fig. 14).
* :func:`energy_balance` — Tables 1–3 for a set of bodies and their A_gx at 50 %;
  :func:`grid_table` lays a column out as the paper's R × γ grid.
* :func:`assess` — the engineer's use (end of Section 8): with a ground or floor spectrum, which
  bodies are expected to be safe and which to overturn with more than 50 % probability.

Units: S_v in m/s inside (tables in cm/s), A_gx in g, frequencies in Hz.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr
from numpy.typing import ArrayLike

from ..core import portable
from ..core.checks import in_range, positive
from ..defaults import BAND_HZ
from ..dynamics.batch import block_list
from ..dynamics.body import Block, G, housner_sv
from ..errors import InputError
from ..motions.ensemble import Ensemble
from ..motions.response import ResponseSpectrum, check_nyquist, response_spectrum
from ..motions.targets import RG160, TabulatedSpectrum, TargetSpectrum

#: Default number of log-spaced oscillator frequencies in the band [-].
N_FREQS = 200
#: Verdicts of :func:`assess`.
SAFE = "safe"
OVERTURN = "overturn>50%"

_SV_UNITS = "m s-1"


def band_frequencies(band_hz: Sequence[float] = BAND_HZ, n_freqs: int = N_FREQS) -> np.ndarray:
    """``n_freqs`` log-spaced frequencies [Hz] from the band's lower to its upper edge (both in).

    Parameters
    ----------
    band_hz : (float, float)
        Lower and upper edge [Hz], 0 < lower < upper.
    n_freqs : int
        Number of frequencies [-], ≥ 2.
    """
    lo, hi = _band(band_hz)
    if isinstance(n_freqs, bool) or not isinstance(n_freqs, (int, np.integer)) or n_freqs < 2:
        raise InputError(f"n_freqs must be an integer ≥ 2, got {n_freqs!r}")
    return portable.geomspace(lo, hi, int(n_freqs))


def mean_psv(ensemble: Ensemble, freqs_hz: ArrayLike, damping: float = 0.05) -> np.ndarray:
    """Ensemble-mean pseudo-velocity spectrum [m/s] of ``ensemble`` as it is (not rescaled).

    Parameters
    ----------
    ensemble : Ensemble
        Accelerations [m/s²].
    freqs_hz : array_like
        Oscillator frequencies [Hz].
    damping : float
        Damping ratio [-].
    """
    return response_spectrum(ensemble.acc, ensemble.dt, freqs_hz, damping).mean().psv


def available_sv(
    source: Ensemble | ResponseSpectrum | TargetSpectrum,
    *,
    band_hz: Sequence[float] = BAND_HZ,
    damping: float = 0.05,
    agx: float | None = None,
    n_freqs: int = N_FREQS,
) -> float:
    """Largest pseudo-velocity of a spectrum inside a frequency band [m/s] (paper Section 8).

    Parameters
    ----------
    source : Ensemble, ResponseSpectrum or TargetSpectrum
        * :class:`~rocking.motions.ensemble.Ensemble`: the maximum over ``n_freqs`` log-spaced
          frequencies of the band of the ensemble-mean PSV (``damping``), after scaling the
          ensemble to mean PGA ``agx`` if given. With ``agx`` = a body's A_gx at 50 % this is S_v1.
        * :class:`~rocking.motions.response.ResponseSpectrum`: the maximum of its (mean) PSV at
          its own frequencies inside the band; its damping must equal ``damping``.
        * :class:`~rocking.motions.targets.TargetSpectrum`: the maximum of its PSV on the
          log-spaced grid plus its table frequencies inside the band (PSV is monotonic between
          the knots of a log-log-linear table, so the maximum of a tabulated or RG 1.60
          spectrum is exact).

        A table (tabulated target, response spectrum) must hold the frequency where the band's
        largest PSV lies, and hold the band beyond it when that is one of its ends: a table of
        5–20 Hz says nothing of 0.04–0.6 Hz (a tabulated target would be extrapolated there), and
        one that rises towards its lowest frequency 0.1 Hz may have its band maximum below it.
        Such a spectrum is refused (:class:`InputError`), as is a band above the Nyquist
        frequency of an ensemble.  The check reads the spectrum at that one frequency for every
        body: the available S_v does not depend on the body.
    band_hz : (float, float)
        Band [Hz], 0 < lower < upper; default the paper's 0.04–0.6 Hz.
    damping : float
        Damping ratio [-] of the spectrum.
    agx : float, optional
        Ensemble A_gx (mean PGA) to scale to [g], > 0; only for an Ensemble source.
    n_freqs : int
        Number of log-spaced frequencies in the band [-].

    Returns
    -------
    float
        Available S_v [m/s].
    """
    lo, hi = _band(band_hz)
    damping = in_range("damping", damping, 0.0, 1.0, hi_open=True, unit="-")
    if agx is not None and not isinstance(source, Ensemble):
        raise InputError(
            f"agx scales an ensemble; it cannot be given with a {type(source).__name__}"
        )
    if isinstance(source, Ensemble):
        check_nyquist(hi, source.dt, "band_hz")
        freqs = band_frequencies((lo, hi), n_freqs)
        sv = _judging(float(mean_psv(source, freqs, damping).max()), "the ensemble's", (lo, hi))
        return sv if agx is None else sv * positive("agx", agx, "g") / _agx_of(source)
    if isinstance(source, ResponseSpectrum):
        if not math.isclose(source.damping, damping, rel_tol=1e-9):
            raise InputError(
                f"the response spectrum has damping {source.damping:g}, but "
                f"damping={damping:g} was asked"
            )
        inside = (source.freqs_hz >= lo) & (source.freqs_hz <= hi)
        if not inside.any():
            raise InputError(
                f"the response spectrum has no frequency in the band {lo:g}–{hi:g} Hz of the "
                f"available S_v (it has {source.freqs_hz.size} from "
                f"{source.freqs_hz.min():g} to {source.freqs_hz.max():g} Hz): it cannot judge "
                "the bodies"
            )
        sv = _band_maximum(
            source.freqs_hz[inside], source.mean().psv[inside], source.freqs_hz, (lo, hi)
        )
        return _judging(sv, "the response spectrum's", (lo, hi))
    if isinstance(source, TargetSpectrum):
        if not math.isclose(source.damping, damping, rel_tol=1e-9):
            raise InputError(
                f"the spectrum {source.name!r} is for damping {source.damping:g}, "
                f"but damping={damping:g} was asked"
            )
        knots = _knots(source)
        freqs = np.union1d(band_frequencies((lo, hi), n_freqs), knots[(knots > lo) & (knots < hi)])
        table = source.freqs_hz if isinstance(source, TabulatedSpectrum) else None
        name = f"the spectrum {source.name!r}"
        sv = _band_maximum(freqs, source.psv(freqs), table, (lo, hi), name)
        return _judging(sv, f"{name}'s", (lo, hi))
    raise InputError(
        "source must be an Ensemble, a ResponseSpectrum or a TargetSpectrum, got "
        f"{type(source).__name__}"
    )


def _judging(sv: float, whose: str, band: tuple[float, float]) -> float:
    """``sv`` [m/s], the largest PSV in ``band`` [Hz], if it can judge a body: finite and > 0
    (a spectrum of all-zero motions would call every body safe with an infinite margin)."""
    if not (math.isfinite(sv) and sv > 0.0):
        raise InputError(
            f"{whose} largest PSV in the band {band[0]:g}–{band[1]:g} Hz is {sv:g} m/s: a "
            "spectrum without motion there (all-zero motions or table) cannot judge the bodies"
        )
    return sv


def energy_balance(
    blocks: Block | Sequence[Block],
    ensemble: Ensemble,
    agx50: ArrayLike,
    *,
    band_hz: Sequence[float] = BAND_HZ,
    damping: float = 0.05,
    n_freqs: int = N_FREQS,
    g: float = G,
) -> xr.Dataset:
    """Required S_v (Eq. 11) against the available S_v1 at each body's A_gx of 50 % (Tables 1–3).

    The response spectra scale linearly with the motions, so the mean PSV of ``ensemble`` is
    computed once and S_v1 = (A_gx50 / A_gx of ``ensemble``) · max of that spectrum in the band.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies (one Block: a list of one).
    ensemble : Ensemble
        The motions the A_gx50 were found with (ground or floor), at any scale [m/s²].
    agx50 : array_like, xarray.DataArray or xarray.Dataset
        A_gx at 50 % overturning probability of each body [g], in the order of ``blocks``
        (NaN where not reached): an array, or the result of
        :func:`rocking.montecarlo.probability.agx_50`
        (its ``agx50`` variable).
    band_hz : (float, float)
        Band of the available S_v [Hz].
    damping : float
        Damping ratio of the spectra [-].
    n_freqs : int
        Number of log-spaced frequencies in the band [-].
    g : float
        Gravity [m/s²] for Eq. (11).

    Returns
    -------
    xarray.Dataset
        Dimension ``body`` (coordinates ``body`` = Block labels, ``R`` [m], ``gamma`` [-]) with
        ``sv_required`` [m/s] (Table 1), ``agx50`` [g], ``sv1`` [m/s] (Table 2) and ``ratio`` =
        sv1/sv_required [-] (Table 3). Attribute ``sv1_per_g`` is the band maximum of the mean
        PSV for A_gx = 1 g [m/s per g]; ``band_hz`` and ``damping`` record the settings.
    """
    blocks = block_list(blocks)
    a50 = _agx50_values(agx50, len(blocks))
    freqs = band_frequencies(band_hz, n_freqs)
    sv1_per_g = float(mean_psv(ensemble, freqs, damping).max()) / _agx_of(ensemble)
    sv_req = np.array([housner_sv(b, g) for b in blocks])  # Eq. (11)
    sv1 = sv1_per_g * a50
    ds = _body_dataset(
        blocks,
        {
            "sv_required": (sv_req, _SV_UNITS, "required pseudo-velocity, Eq. (11)"),
            "agx50": (a50, "g", "A_gx at 50 % overturning probability"),
            "sv1": (sv1, _SV_UNITS, "max of the mean PSV in the band at A_gx50 (S_v1)"),
            "ratio": (sv1 / sv_req, "1", "S_v1 / S_v"),
        },
    )
    ds.attrs.update(
        band_hz=list(freqs[[0, -1]]),
        damping=damping,
        sv1_per_g=sv1_per_g,
        ensemble_location=str(ensemble.meta.get("location", "")),
        n_motions=ensemble.n,
    )
    return ds


def assess(
    blocks: Block | Sequence[Block],
    source: Ensemble | ResponseSpectrum | TargetSpectrum,
    *,
    band_hz: Sequence[float] = BAND_HZ,
    damping: float = 0.05,
    names: Sequence[str] | None = None,
    agx: float | None = None,
    g: float = G,
) -> xr.Dataset:
    """Screen bodies against a ground or floor spectrum with Eq. (11) (paper Section 8 examples).

    A body whose required S_v exceeds the available S_v of the spectrum is expected to be safe
    (overturning probability below 50 %); otherwise it is expected to overturn with a
    probability of 50 % or more.

    Parameters
    ----------
    blocks : Block or sequence of Block
        The bodies (one Block: a list of one).
    source : Ensemble, ResponseSpectrum or TargetSpectrum
        The spectrum at the body's location (see :func:`available_sv`).
    band_hz : (float, float)
        Band of the available S_v [Hz].
    damping : float
        Damping ratio of the spectrum [-].
    names : sequence of str, optional
        One name per body (default: the Block labels).
    agx : float, optional
        Scale an Ensemble source to this A_gx [g] first.
    g : float
        Gravity [m/s²] for Eq. (11).

    Returns
    -------
    xarray.Dataset
        Dimension ``body`` (coordinates ``body`` = names, ``R`` [m], ``gamma`` [-]) with
        ``sv_required`` [m/s], ``sv_available`` [m/s] (the same for every body),
        ``margin`` = sv_required / sv_available − 1 [-] (> 0: safe; e.g. 0.79 means the body
        needs 79 % more pseudo-velocity than the spectrum offers) and ``verdict``
        (``"safe"`` if margin > 0, else ``"overturn>50%"``).
    """
    blocks = block_list(blocks)
    if names is None:
        names = [b.label for b in blocks]
    names = [str(n) for n in names]
    if len(names) != len(blocks):
        raise InputError(f"names has {len(names)} entries for {len(blocks)} bodies")
    available = available_sv(source, band_hz=band_hz, damping=damping, agx=agx)
    sv_req = np.array([housner_sv(b, g) for b in blocks])  # Eq. (11)
    margin = sv_req / available - 1.0
    ds = _body_dataset(
        blocks,
        {
            "sv_required": (sv_req, _SV_UNITS, "required pseudo-velocity, Eq. (11)"),
            "sv_available": (
                np.full(len(blocks), available),
                _SV_UNITS,
                "max of the PSV in the band",
            ),
            "margin": (margin, "1", "sv_required / sv_available - 1 (> 0: safe)"),
            "verdict": (np.where(margin > 0.0, SAFE, OVERTURN), "", "Housner's screening verdict"),
        },
        labels=names,
    )
    lo, hi = _band(band_hz)
    ds.attrs.update(band_hz=[lo, hi], damping=damping)
    return ds


def forms_grid(ds: xr.Dataset) -> bool:
    """True if the bodies of ``ds`` are every (R, γ) pair of some R and γ values, once each."""
    pairs = set(zip(_round(ds["R"].values), _round(ds["gamma"].values)))
    n_r = len(set(_round(ds["R"].values)))
    n_g = len(set(_round(ds["gamma"].values)))
    return len(pairs) == ds.sizes["body"] == n_r * n_g


def grid_table(ds: xr.Dataset, name: str) -> pd.DataFrame:
    """One per-body variable of ``ds`` as the paper's table: rows R [m], columns γ [-].

    Velocities (units m/s) are given in cm/s as in the paper's Tables 1 and 2; other variables
    as they are. The bodies must form a full R × γ grid (:func:`forms_grid`).

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`energy_balance` or :func:`assess` (or any dataset with dimension
        ``body`` and coordinates ``R``, ``gamma``).
    name : str
        Variable name, e.g. ``"sv_required"``, ``"sv1"``, ``"ratio"``.
    """
    if name not in ds.data_vars:
        raise InputError(
            f"no variable {name!r}; the dataset has {', '.join(map(str, ds.data_vars))}"
        )
    if not forms_grid(ds):
        raise InputError("the bodies do not form an R × gamma grid (each pair once)")
    values = ds[name].values
    unit = ds[name].attrs.get("units", "")
    if unit == _SV_UNITS:
        values, unit = 100.0 * values, "cm/s"
    table = pd.DataFrame(
        {"R": _round(ds["R"].values), "gamma": _round(ds["gamma"].values), "value": values}
    ).pivot(index="R", columns="gamma", values="value")
    table.index.name = "R [m]"
    table.columns.name = "gamma [-]"
    table.attrs["units"] = unit
    return table


# --------------------------------------------------------------------------- helpers


def _band(band_hz) -> tuple[float, float]:
    try:
        lo, hi = (float(x) for x in band_hz)
    except (TypeError, ValueError):
        raise InputError(f"band_hz must be two frequencies [Hz], got {band_hz!r}") from None
    positive("band_hz lower edge", lo, "Hz")
    positive("band_hz upper edge", hi, "Hz")
    if not lo < hi:
        raise InputError(f"band_hz lower edge ({lo:g} Hz) must be below the upper ({hi:g} Hz)")
    return lo, hi


def _band_maximum(
    freqs: np.ndarray,
    psv: np.ndarray,
    table: np.ndarray | None,
    band: tuple[float, float],
    name: str = "the response spectrum",
) -> float:
    """The largest ``psv`` [m/s] at ``freqs`` [Hz] in ``band``, when the spectrum's ``table``
    frequencies (None: a formula, defined everywhere) cover where it lies; else InputError."""
    k = int(np.argmax(psv))
    if table is None:
        return float(psv[k])
    lo, hi = band
    f, first, last = float(freqs[k]), float(table.min()), float(table.max())
    tol = 1e-9
    covers = f"{name} covers {first:g}–{last:g} Hz"
    if not first * (1 - tol) <= f <= last * (1 + tol):
        problem = f"{covers}, none of the band {lo:g}–{hi:g} Hz of the available S_v"
    elif f <= first * (1 + tol) and first > lo * (1 + tol):
        problem = (
            f"{covers}, and its PSV rises towards {first:g} Hz, so the largest PSV of the band "
            f"{lo:g}–{hi:g} Hz of the available S_v may lie below, where it gives none"
        )
    elif f >= last * (1 - tol) and last < hi * (1 - tol):
        problem = (
            f"{covers}, and its PSV rises towards {last:g} Hz, so the largest PSV of the band "
            f"{lo:g}–{hi:g} Hz of the available S_v may lie above, where it gives none"
        )
    else:
        return float(psv[k])
    raise InputError(
        f"{problem}: it cannot judge the bodies; give a spectrum that covers the band (e.g. "
        f"'rocking spectrum --fmin {lo:g}') or a band inside {first:g}–{last:g} Hz"
    )


def _knots(spectrum: TargetSpectrum) -> np.ndarray:
    """Frequencies [Hz] where a log-log-linear target spectrum changes slope (none if unknown)."""
    if isinstance(spectrum, TabulatedSpectrum):
        return spectrum.freqs_hz
    if isinstance(spectrum, RG160):
        return spectrum.control_points()[0]
    return np.empty(0)


def _agx_of(ensemble: Ensemble) -> float:
    if ensemble.agx == 0.0:
        raise InputError("the ensemble's motions are all zero: its spectrum cannot be scaled")
    return ensemble.agx


def _agx50_values(agx50, n: int) -> np.ndarray:
    if isinstance(agx50, xr.Dataset):
        if "agx50" not in agx50:
            raise InputError("agx50 dataset has no variable 'agx50'")
        agx50 = agx50["agx50"]
    a = np.asarray(agx50, dtype=np.float64).ravel()
    if a.size != n:
        raise InputError(f"agx50 has {a.size} values for {n} bodies")
    bad = np.isinf(a) | (a <= 0.0)  # NaN (not reached by the search) is allowed
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(f"agx50[{i}] must be > 0 [g] or NaN, got {a[i]!r}")
    return a


def _body_dataset(blocks, variables: dict, labels=None) -> xr.Dataset:
    coords = {
        "body": [b.label for b in blocks] if labels is None else list(labels),
        "R": ("body", [b.R for b in blocks], {"units": "m"}),
        "gamma": ("body", [b.gamma for b in blocks], {"units": "1"}),
    }
    data = {
        k: ("body", v, {"units": u, "long_name": ln} if u else {"long_name": ln})
        for k, (v, u, ln) in variables.items()
    }
    return xr.Dataset(data, coords=coords)


def _round(x) -> np.ndarray:
    """Body sizes rounded to 0.1 µm (and γ to 1e-7) so that float noise does not split a row."""
    return np.round(np.asarray(x, dtype=np.float64), 7)
