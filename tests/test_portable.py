"""rocking.core.portable: numerics whose bits do not depend on the CPU.

Two kinds of proof.  Each function against an independent reference: the C library through
Python's ``math`` module (exactly: the same functions are called), SciPy/NumPy's LAPACK
routines and closed forms (to round-off; tolerances say why).  And the property itself: the
motions, floor motions, response spectra, intensity measures and resampled records computed in
child processes that make NumPy use only its baseline loops (``NPY_DISABLE_CPU_FEATURES``) or
OpenBLAS use the kernels of another CPU (``OPENBLAS_CORETYPE``) have the same bits as in this
process.  Before the portable functions, the OpenBLAS change alone altered every generated
motion.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg

from rocking.core import portable

RNG = np.random.default_rng(20261126)


def _avx512_numpy() -> bool:
    """Whether NumPy runs its AVX-512 loops here (vectorised approximations, not libm)."""
    from numpy._core import _multiarray_umath as m

    return bool(m.__cpu_features__.get("AVX512F"))


@pytest.mark.parametrize(
    ("func", "ref", "lo", "hi"),
    [
        (portable.sin, math.sin, -1e3, 1e3),
        (portable.cos, math.cos, -1e3, 1e3),
        (portable.exp, math.exp, -700.0, 700.0),
        (portable.expm1, math.expm1, -30.0, 30.0),
        (portable.log, math.log, 1e-300, 1e300),
        (portable.log10, math.log10, 1e-300, 1e300),
    ],
)
def test_elementary_functions_are_the_c_library_s(func, ref, lo, hi):
    x = RNG.uniform(lo, hi, 20_000) if func is not portable.log else RNG.uniform(0.0, 50.0, 20_000)
    got = func(x.reshape(100, 200))
    assert got.shape == (100, 200)
    # exactly: Python's math module calls the same C library functions
    assert np.array_equal(got.ravel(), np.array([ref(v) for v in x]))
    if not _avx512_numpy():  # NumPy's non-AVX-512 loops are the C library's too
        npf = {"sin": np.sin, "cos": np.cos, "exp": np.exp, "expm1": np.expm1, "log": np.log}
        npf["log10"] = np.log10
        assert np.array_equal(got.ravel(), npf[func.__name__](x))


def test_shapes_are_kept():
    # 0-d in, 0-d out (as NumPy's ufuncs): a scalar result must convert with float()
    for value in (2.0, np.float64(2.0), np.array(2.0)):
        assert portable.exp(value).shape == ()
        assert float(portable.expm1(value)) == math.expm1(2.0)
        assert portable.power(value, 3.0).shape == ()
    assert portable.log(np.ones((2, 0, 3))).shape == (2, 0, 3)
    assert portable.sin(np.ones((4, 3)).T).shape == (3, 4)  # not contiguous in


def test_log_outside_its_domain_and_arctan2_broadcasting():
    assert np.array_equal(portable.log(np.array([0.0, -1.0])), [-np.inf, np.nan], equal_nan=True)
    y, x = RNG.uniform(-5, 5, (30, 1)), RNG.uniform(-5, 5, (1, 40))
    got = portable.arctan2(y, x)
    assert got.shape == (30, 40)
    assert np.array_equal(got, [[math.atan2(a, b) for b in x[0]] for a in y[:, 0]])


def test_power_follows_numpy_for_constant_exponents():
    x = RNG.uniform(0.0, 3.0, 5_000)
    # NumPy computes x ** 2, x ** 0.5 and x ** -1 as x·x, sqrt and 1/x (exact on every CPU),
    # other constant exponents by the C library's pow
    shortcut = {2.0: lambda v: v * v, 0.5: math.sqrt, -1.0: lambda v: 1.0 / v}
    for c in (2.0, 0.5, -1.0, 1.0, 3.0, 1.0 / 3.0, 1.5):
        ref = shortcut.get(c, lambda v, c=c: math.pow(v, c))
        got = portable.power(x, c)
        assert np.array_equal(got, [ref(v) for v in x]), c
        if not _avx512_numpy():
            assert np.array_equal(got, x**c), c


def test_geomspace():
    for lo, hi, n in [(0.15, 50.0, 100), (0.04, 0.6, 37), (1e-3, 7.3, 1000), (2.0, 2.0, 3)]:
        got = portable.geomspace(lo, hi, n)
        assert got[0] == lo and got[-1] == hi and got.size == n
        # evenly spaced logarithms, to round-off of the logarithm of the ends (few ulp)
        np.testing.assert_allclose(np.diff(np.log(got)), math.log(hi / lo) / (n - 1), atol=1e-13)
        if not _avx512_numpy():
            assert np.array_equal(got, np.geomspace(lo, hi, n))


def test_expm_against_scipy_and_closed_forms():
    # random 2x2 … 5x5 matrices of 1-norm from 1e-3 to ~30: scipy.linalg.expm (Padé 13) agrees
    # to round-off amplified by the squarings (relative 1e-12 of the largest entry)
    for n in (2, 4, 5):
        m = RNG.standard_normal((40, n, n)) * RNG.uniform(1e-3, 6.0, (40, 1, 1))
        got, ref = portable.expm(m), scipy.linalg.expm(m)
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    # rotation: exp([[0, θ], [−θ, 0]]) = [[cos θ, sin θ], [−sin θ, cos θ]] (2 ulp after squarings)
    for theta in (1e-6, 0.3, 2.0, 10.0):
        r = portable.expm(np.array([[0.0, theta], [-theta, 0.0]]))
        np.testing.assert_allclose(
            r,
            [[math.cos(theta), math.sin(theta)], [-math.sin(theta), math.cos(theta)]],
            rtol=0,
            atol=1e-14 * max(1.0, theta),
        )
    # diagonal: e^d exactly up to the Taylor series' rounding (a few ulp)
    d = np.array([-3.0, -0.1, 0.0, 0.7])
    np.testing.assert_allclose(np.diag(portable.expm(np.diag(d))), np.exp(d), rtol=4e-15)


def test_lstsq_against_lapack():
    a, b = RNG.standard_normal((120, 30)), RNG.standard_normal((120, 3))
    ref = np.linalg.lstsq(a, b, rcond=None)[0]
    np.testing.assert_allclose(portable.lstsq(a, b), ref, rtol=0, atol=1e-13)  # κ(a) ≈ 3
    sq = RNG.standard_normal((6, 6)) + 6.0 * np.eye(6)
    rhs = RNG.standard_normal(6)
    np.testing.assert_allclose(sq @ portable.lstsq(sq, rhs), rhs, rtol=0, atol=1e-13)
    with pytest.raises(np.linalg.LinAlgError):
        portable.lstsq(np.ones((5, 2)), np.ones(5))


def test_eigh_and_pinv():
    s = RNG.standard_normal((60, 60))
    s = s + s.T
    w, v = portable.eigh(s)
    w_ref = np.linalg.eigh(s)[0]
    np.testing.assert_allclose(w, w_ref, rtol=0, atol=1e-12)  # ‖s‖ ≈ 15: 100 ulp of it
    np.testing.assert_allclose(v.T @ v, np.eye(60), rtol=0, atol=1e-13)
    np.testing.assert_allclose(s @ v, v * w, rtol=0, atol=1e-12)
    assert (v[-1] > 0).all()  # the sign convention: last entry positive
    # a rank-deficient positive semi-definite matrix: NumPy's pinv (SVD) to round-off
    b = RNG.standard_normal((40, 25))
    g = b @ b.T  # rank 25 of 40
    np.testing.assert_allclose(
        portable.pinv_symmetric(g), np.linalg.pinv(g, hermitian=True), rtol=0, atol=1e-12
    )


_DIGESTS = r"""
import hashlib, json, numpy as np
from rocking import ShearFrame, generate, intensity_measures, response_spectrum
def d(*a):
    return hashlib.sha256(b"".join(np.ascontiguousarray(x).tobytes() for x in a)).hexdigest()
ens = generate(6, duration=8.0, seed=5)
it = generate(3, duration=6.0, seed=6, iterations=1, pilot=4)
frame = ShearFrame.preset("paper-2.0")
floors = frame.floor_accelerations(ens.acc[:2], ens.dt)
from rocking.assessment.energy import band_frequencies
from rocking.core.portable import geomspace
rs = response_spectrum(ens.acc[:2], ens.dt, geomspace(0.1, 50.0, 30))
im = intensity_measures(ens, ["pga", "pgv", "sa(1.0)", "saavg(0.2:2.0)", "arias", "cav"])
from rocking.motions.records import resample
resampled = [resample(ens.acc[0], ens.dt, new) for new in (ens.dt * 2 / 5, ens.dt * 3)]
from rocking import annual_rate, fit_lognormal
from rocking.assessment.risk import HazardCurve, example_hazard_path
x = np.linspace(0.1, 1.5, 15)
k = np.round(40 * np.clip((x - 0.1) / 1.2, 0, 1) ** 1.3).astype(int)
fit = fit_lognormal(x, k, np.full(15, 40))
risk = annual_rate(fit, HazardCurve.from_csv(example_hazard_path()), im="pgv")
fitted = np.array([fit.median, fit.beta, risk.annual_rate, *risk.probability_in([1.0, 50.0])])
print(json.dumps({"resampled": d(*resampled), "risk": d(fitted),
                  "generate": d(ens.acc), "iterated": d(it.acc),
                  "frame": d(frame.omegas, frame.mode_shapes, frame.participation_factors),
                  "floors": d(floors), "spectra": d(rs.psa), "ims": d(im.to_numpy()),
                  "band": d(band_frequencies())}))
"""


def _digests(**env) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", _DIGESTS],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_antialias_filter_is_scipys_default():
    from scipy.signal import firwin

    from rocking.motions.records import antialias_filter

    for up, down in [(1, 2), (5, 2), (2, 5), (1, 8), (3, 1)]:
        rate = max(up, down)
        ref = firwin(20 * rate + 1, 1.0 / rate, window=("kaiser", 5.0))  # resample_poly's design
        got = antialias_filter(up, down)
        # the same operations; only the sine may differ from NumPy's on AVX-512 (an ulp or so)
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-15)
        if not _avx512_numpy():
            assert np.array_equal(got, ref)


def test_motions_do_not_depend_on_numpy_loops_or_blas_kernels():
    from numpy._core import _multiarray_umath as m

    here = _digests()
    dispatched = [f for f in m.__cpu_dispatch__ if m.__cpu_features__.get(f)]
    variants = [{"OPENBLAS_CORETYPE": "Prescott"}]  # OpenBLAS's oldest x86-64 kernels
    if dispatched:  # NumPy's baseline loops only
        variants.append({"NPY_DISABLE_CPU_FEATURES": " ".join(dispatched)})
    for env in variants:
        assert _digests(**env) == here, env
