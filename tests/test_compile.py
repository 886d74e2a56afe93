"""The compiled helpers of rocking.core.compile agree with their plain-Python definitions."""

from __future__ import annotations

import math

import numba
import numpy as np

from rocking.core.compile import fma, maxnum


@numba.njit
def _maxnum_compiled(a, b):
    return maxnum(a, b)


@numba.njit
def _fma_compiled(a, b, c):
    return fma(a, b, c)


def test_maxnum_is_the_larger_number_and_ignores_a_nan():
    # The batched kernel keeps each lane's peak with maxnum (a vector maximum, no masked store);
    # it must be the larger of two numbers, and the number when the other is NaN (IEEE
    # maxNum), in compiled code and in Python alike.
    values = [0.0, 1.5, -2.0, 1e-300, math.inf, 3.0]
    for a in values:
        for b in values:
            assert _maxnum_compiled(a, b) == maxnum(a, b) == max(a, b)
    for x in values:
        assert _maxnum_compiled(math.nan, x) == maxnum(math.nan, x) == x
        assert _maxnum_compiled(x, math.nan) == maxnum(x, math.nan) == x


def test_fma_rounds_once_in_kernels_and_in_python():
    # a·b + c rounded once: (1 + 2⁻³⁰)² − 1 keeps the 2⁻⁶⁰ term that a multiply then add loses
    # (exact arithmetic: 2⁻²⁹ + 2⁻⁶⁰); compiled and Python results must be the same bits.
    x = 1.0 + 2.0**-30
    exact = 2.0**-29 + 2.0**-60
    assert fma(x, x, -1.0) == exact == _fma_compiled(x, x, -1.0)
    assert x * x - 1.0 != exact
    rng = np.random.default_rng(5)
    for a, b, c in rng.normal(size=(200, 3)) * 1e3:
        assert _fma_compiled(a, b, c) == fma(a, b, c)
