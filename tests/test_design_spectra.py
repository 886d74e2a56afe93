"""Design spectra (ASCE 7, Eurocode 8) against values worked out by hand from the codes' formulas,
and the spectrum specification syntax."""

import math

import numpy as np
import pytest

from rocking.assessment.energy import available_sv
from rocking.dynamics.body import G
from rocking.errors import InputError
from rocking.motions.design import ASCE7, EC8, design_pga, parse_spectrum
from rocking.motions.targets import RG160, TabulatedSpectrum

# Values below are exact arithmetic on the code formulas; 1e-12 only absorbs float rounding.
TIGHT = 1e-12


def test_asce7_every_branch_by_hand():
    # ASCE 7-16 §11.4.6 with S_DS = 1.0 g, S_D1 = 0.6 g, T_L = 8 s:
    # T0 = 0.2·0.6/1.0 = 0.12 s, Ts = 0.6/1.0 = 0.6 s.
    s = ASCE7(SDS=1.0, SD1=0.6, TL=8.0)
    assert pytest.approx(0.12, rel=TIGHT) == s.T0 and s.Ts == pytest.approx(0.6, rel=TIGHT)
    hand = {
        0.012: 1.0 * (0.4 + 0.6 * 0.1),  # Eq. 11.4-5, T/T0 = 0.1 -> 0.46
        0.06: 1.0 * (0.4 + 0.6 * 0.5),  # Eq. 11.4-5, T/T0 = 0.5 -> 0.70
        0.3: 1.0,  # plateau S_DS
        1.0: 0.6 / 1.0,  # Eq. 11.4-7 -> 0.6
        2.0: 0.6 / 2.0,  # -> 0.3
        10.0: 0.6 * 8.0 / 100.0,  # Eq. 11.4-8 -> 0.048
        20.0: 0.6 * 8.0 / 400.0,  # -> 0.012
    }
    periods = np.array(list(hand))
    np.testing.assert_allclose(s.sa(periods), list(hand.values()), rtol=TIGHT)
    np.testing.assert_allclose(s.psa(1.0 / periods), list(hand.values()), rtol=TIGHT)
    # PSV = S_a·g·T/(2π): at T = 2 s, 0.3·9.80665·2/(2π) = 0.936466 m/s
    assert s.psv(0.5) == pytest.approx(0.3 * G * 2.0 / (2 * math.pi), rel=TIGHT)
    assert s.pga == pytest.approx(0.4, rel=TIGHT)  # S_a(T -> 0) = 0.4·S_DS


def test_asce7_is_continuous_at_the_corners():
    # the four branches meet at T0, Ts and TL (the code's figure 11.4-1 is one curve)
    s = ASCE7(SDS=1.2, SD1=0.5, TL=6.0)
    for t in (s.T0, s.Ts, s.TL):
        below, above = s.sa(np.array([t * (1 - 1e-9), t * (1 + 1e-9)]))
        assert below == pytest.approx(above, rel=1e-8)


def test_ec8_type1_ground_b_by_hand():
    # EN 1998-1 §3.2.2.2, Type 1, ground B (Table 3.2: S = 1.2, TB = 0.15, TC = 0.5, TD = 2.0),
    # a_g = 0.25 g, 5 % damping (η = 1): a_g·S = 0.3 g, plateau 2.5·0.3 = 0.75 g.
    s = EC8(ag=0.25, ground="B", type=1)
    hand = {
        0.075: 0.3 * (1 + 0.5 * (2.5 - 1)),  # Eq. 3.2, T/TB = 0.5 -> 0.525
        0.3: 0.75,  # Eq. 3.3
        1.0: 0.75 * 0.5 / 1.0,  # Eq. 3.4 -> 0.375
        3.0: 0.75 * 0.5 * 2.0 / 9.0,  # Eq. 3.5 -> 0.083333
        10.0: 0.75 * 0.5 * 2.0 / 100.0,  # Eq. 3.5 continued beyond 4 s -> 0.0075
    }
    np.testing.assert_allclose(s.sa(np.array(list(hand))), list(hand.values()), rtol=TIGHT)
    assert s.pga == pytest.approx(0.3, rel=TIGHT)


def test_ec8_type2_with_importance_factor_by_hand():
    # Type 2, ground D (Table 3.3: S = 1.8, TB = 0.1, TC = 0.3, TD = 1.2), a_gR = 0.1 g,
    # γ_I = 1.4: a_g = 0.14 g, a_g·S = 0.252 g, plateau 2.5·0.252 = 0.63 g.
    s = EC8(ag=0.1, ground="d", type=2, importance=1.4)
    hand = {
        0.05: 0.252 * (1 + 0.5 * 1.5),  # Eq. 3.2 -> 0.441
        0.2: 0.63,  # Eq. 3.3
        0.6: 0.63 * 0.3 / 0.6,  # Eq. 3.4 -> 0.315
        2.4: 0.63 * 0.3 * 1.2 / 2.4**2,  # Eq. 3.5 -> 0.039375
    }
    np.testing.assert_allclose(s.sa(np.array(list(hand))), list(hand.values()), rtol=TIGHT)
    assert s.pga == pytest.approx(0.252, rel=TIGHT)


def test_ec8_damping_correction():
    # Eq. 3.6: η = sqrt(10/(5 + ξ)); ξ = 10 % -> sqrt(10/15) = 0.8165; ξ = 50 % -> 0.426,
    # below the floor 0.55.
    assert EC8(0.2, damping=0.10).eta == pytest.approx(math.sqrt(10 / 15), rel=TIGHT)
    assert EC8(0.2, damping=0.50).eta == 0.55
    s = EC8(0.2, ground="A", damping=0.10)  # plateau 2.5·0.2·1.0·0.8165 = 0.40825 g
    assert s.sa(0.3) == pytest.approx(2.5 * 0.2 * math.sqrt(10 / 15), rel=TIGHT)
    assert s.sa(0.01) < s.sa(0.1)  # with η < 1 the first branch still rises to the plateau


def test_scaled_spectra_scale_every_ordinate():
    f = np.geomspace(0.05, 40.0, 30)
    for s in (ASCE7(0.9, 0.5, 8.0), EC8(0.3, "C", 1)):
        np.testing.assert_allclose(s.scaled(1.7).psa(f), 1.7 * s.psa(f), rtol=1e-12)


def test_available_sv_of_asce7_is_its_velocity_plateau():
    # In 0.04–0.6 Hz (T = 1.67–25 s) with Ts = 0.6 s < 1.67 s ≤ T_L = 8 s the PSV is
    # S_D1·g/(2π) from 1.67 s to T_L and falls beyond: 0.6·9.80665/(2π) = 0.93647 m/s.
    assert available_sv(ASCE7(1.0, 0.6, 8.0)) == pytest.approx(0.6 * G / (2 * math.pi), rel=1e-9)


def test_parse_spectrum_kinds():
    assert parse_spectrum("rg160:0.3") == RG160(0.05, 0.3)
    assert parse_spectrum("rg160:pga=0.4,damping=0.02") == RG160(0.02, 0.4)
    assert parse_spectrum("asce7:SDS=1.0,SD1=0.6,TL=8") == ASCE7(1.0, 0.6, 8.0)
    assert parse_spectrum("ec8:type=2,ground=C,ag=0.15,importance=1.2") == EC8(0.15, "C", 2, 1.2)


def test_parse_spectrum_reads_a_csv(tmp_path):
    path = tmp_path / "floor.csv"
    path.write_text("period [s],PSA [g]\n0.02,0.5\n0.2,1.2\n2.0,0.3\n")
    s = parse_spectrum(path.name, base_dir=tmp_path)
    assert isinstance(s, TabulatedSpectrum)
    assert s.psa(1.0 / 0.2) == pytest.approx(1.2)
    assert design_pga(s) == pytest.approx(0.5)  # flat above the highest frequency (50 Hz)


@pytest.mark.parametrize(
    "text, words",
    [
        ("asce7:SDS=1", "missing SD1, TL"),
        ("asce7:SDS=1,SD1=2,TL=1", "TL"),
        ("ec8:ag=x", "ag must be a number"),
        ("ec8:ground=F,ag=0.2", "ground must be one of"),
        ("ec8:type=3,ag=0.2", "type must be 1 or 2"),
        ("rg160:pga=0.3,zeta=0.05", "unknown key 'zeta'"),
        ("nosuchfile.csv", "neither a known kind"),
    ],
)
def test_parse_spectrum_errors_name_the_problem(text, words):
    with pytest.raises(InputError, match=words):
        parse_spectrum(text)


def test_parse_spectrum_refuses_binary_files_and_units_not_understood(tmp_path):
    # Issue 49: a binary file raised UnicodeDecodeError, and a spectrum headed PSA [furlongs]
    # was read as PSA in g (assess and screen gave verdicts on it).
    binary = tmp_path / "spectrum.csv"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\xff")
    with pytest.raises(InputError, match=r"spectrum\.csv: the spectrum file is not a text file"):
        parse_spectrum(str(binary))
    latin = tmp_path / "latin.csv"
    latin.write_bytes("freq,PSA [g]\n1,0.5\n2,0.6 \xb5\n".encode("latin-1"))
    with pytest.raises(
        InputError, match=r"latin\.csv: the spectrum file is not a text file \(byte 25 is not UTF-8"
    ):
        parse_spectrum(str(latin))
    furlongs = tmp_path / "furlongs.csv"
    furlongs.write_text("freq,PSA [furlongs]\n1,0.5\n2,0.6\n")
    with pytest.raises(InputError, match=r"column 'PSA \[furlongs\]': unit 'furlongs' is not"):
        parse_spectrum(str(furlongs))


def test_design_pga():
    assert design_pga(RG160(pga=0.3)) == 0.3
    assert design_pga(ASCE7(1.0, 0.6, 8.0)) == pytest.approx(0.4)
    assert design_pga(EC8(0.25, "B")) == pytest.approx(0.3)
