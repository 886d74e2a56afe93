"""The adversarial command lines of issues 48 and 49, in one table.

Issue 49's "Done when": "the adversarial cases above give one line each with the right exit
status"; issue 48's: "every refusal takes under 1 s". Each row is one command line a user might
type (with the small files it needs, built here), the exit status it must end with (1 for an
input error; 0 where a warning is the right answer, with exactly one ``warning:`` line) and the
words the line must hold: the option, file or row it is about. Every row also checks that no
traceback and no "internal error" reaches the screen, and measures the time: a refusal of a size
(checked with the options, before the numerical library is loaded) must take under 1 s in
process; any other refusal reads its files first, but starts no work.
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from rocking.cli import main
from rocking.motions.records import example_record_path
from rocking.motions.synthesis import generate

#: Standard gravity [m/s²] (CGPM 1901), to write accelerations in other units.
G = 9.80665
#: A refusal of a size must take less than this [s] in process (issue 48).
SIZE_S = 1.0
#: Any other case: it loads the numerical library and reads its files (one to three seconds on
#: a busy 2-core machine), and starts no work; a fast run of a few motions is allowed too.
OTHER_S = 15.0
#: A PNG file's first bytes (binary, not UTF-8), given where a text file is read (issue 49).
PNG = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\xff\xfe"


@dataclass(frozen=True)
class Case:
    """One command line: ``args(f)`` with ``f`` the files of :func:`files` and ``f.tmp`` a fresh
    folder; the exit ``status``, the ``words`` its (last) line holds, whether it is a warning,
    the longest it may take, and whether a command that succeeds prints one line only."""

    name: str
    args: Callable[[SimpleNamespace], list]
    words: tuple[str, ...]
    status: int = 1
    warns: bool = False
    within: float = OTHER_S
    one_line: bool = True


def _accelerations(path: Path, unit: str | None, peak: float, dt: float = 0.01) -> Path:
    """A two-column text record (t [s], a) of a 2 Hz sine of ``peak`` in ``unit``; no header
    when ``unit`` is None."""
    t = np.arange(400) * dt
    rows = [f"{ti:.4f},{peak * np.sin(4 * np.pi * ti):.6g}" for ti in t]
    head = [] if unit is None else [f"time [s],acc [{unit}]"]
    path.write_text("\n".join([*head, *rows]) + "\n")
    return path


def _changed(path: Path, out: Path, acc=None, **attrs) -> Path:
    """The ensemble file ``path`` copied to ``out`` with its accelerations or attributes changed,
    as another program might write it."""
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    if acc is not None:
        ds["acc"].values[...] = acc
    ds.attrs.update(attrs)
    ds.to_netcdf(out)
    return out


def _invoke(args) -> tuple[int, str, float]:
    start = time.perf_counter()
    result = CliRunner().invoke(main, [str(a) for a in args])
    return result.exit_code, result.output, time.perf_counter() - start


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The inputs of the cases: records, spectra, ensembles and two completed runs."""
    d = tmp_path_factory.mktemp("adversarial")
    f = SimpleNamespace(dir=d)
    # records whose units are understood (a peak of 0.3 g in each) and one in furlongs
    f.mm = _accelerations(d / "mm.csv", "mm/s2", 0.3 * G * 1000)
    f.inch = _accelerations(d / "in.csv", "in/s2", 0.3 * G / 0.0254)
    f.ft = _accelerations(d / "ft.csv", "ft/s2", 0.3 * G / 0.3048)
    f.furlongs = _accelerations(d / "furlongs.csv", "furlongs", 0.3)
    f.gal = _accelerations(d / "gal.csv", None, 312.7)  # a record in gal, no header (issue 48)
    f.huge = _accelerations(d / "huge.csv", "g", 1e30)
    f.one_a = d / "one-a.txt"  # one-column files: 100 Hz and 200 Hz in truth
    f.one_a.write_text("\n".join(f"{0.1 * np.sin(i / 10):.5f}" for i in range(300)) + "\n")
    f.one_b = d / "one-b.txt"
    f.one_b.write_text(f.one_a.read_text())
    f.unknown = d / "record.dat"  # a format that is not read: four values a line
    f.unknown.write_text("# station X\n1 2 3 4\n5 6 7 8\n9 10 11\n")
    at2 = example_record_path().read_text()
    assert "The units are (g)" in at2
    f.at2_furlongs = d / "furlongs.AT2"
    f.at2_furlongs.write_text(at2.replace("The units are (g)", "The units are (furlongs)"))
    texts = {
        # spectra: in furlongs, and a table of 5-20 Hz only (the band is 0.04-0.6 Hz)
        "spec_furlongs": ("spec-furlongs.csv", "freq [Hz],PSA [furlongs]\n0.01,0.1\n1,0.5\n"),
        "spec_high": ("spec-high.csv", "freq [Hz],PSA [g]\n5,0.5\n10,0.8\n20,0.4\n"),
        # inventories: one rack on the ground, one on "floor 0", one with two height columns
        "inv": ("inv.csv", "name,height,width,location\nrack,2.0,0.5,ground\n"),
        "inv_floor0": ("inv-floor0.csv", "name,height,width,location,frame\n"
                       "rack,2.0,0.5,floor 0,paper-2.0\n"),
        "inv_twice": ("inv-twice.csv", "name,height,width,location,h\nrack,2.0,0.5,ground,3.0\n"),
        # bodies: H and B swapped, a very slender one (gamma 200), a plain one
        "swapped": ("swapped.csv", "name,H,B\nslab,0.6,2.0\n"),
        "slender": ("slender.csv", "name,R,gamma\nneedle,1.0,200\n"),
        "bodies": ("bodies.csv", "name,R,gamma\nslim,0.5,5\n"),
        # bodies with friction: the second row's kinetic coefficient above its static one
        "bodies_mu": ("bodies-mu.csv", "name,R,gamma,mu,mu_k\nslim,0.5,5,0.4,\nbox,1,2,0.3,0.5\n"),
    }  # fmt: skip
    for key, (name, text) in texts.items():
        setattr(f, key, d / name)
        (d / name).write_text(text)
    for key, name in (("binary", "binary.csv"), ("binary_toml", "binary.toml")):
        setattr(f, key, d / name)
        (d / name).write_bytes(PNG)
    # ensembles: good ones (200 Hz), all zeros, a sample of 1e30 g, dt disagreeing with the axis
    f.ens = generate(4, duration=4.0, dt=0.005, seed=1).save(d / "ens.nc")
    f.ens2 = generate(4, duration=4.0, dt=0.005, seed=2).save(d / "ens2.nc")
    f.zero = _changed(f.ens, d / "zero.nc", acc=0.0)
    with xr.open_dataset(f.ens) as ds:
        acc = ds["acc"].values.copy()
    acc[0, 100] = 1e30 * G
    f.huge_nc = _changed(f.ens, d / "huge.nc", acc=acc)
    f.dt_nc = _changed(f.ens, d / "dt.nc", dt=0.02)
    # two completed runs: a fragility against PGV (read by risk) and an A_gx50 search
    f.frag = d / "frag"
    f.frag_args = ["fragility", "--bodies", f.bodies, "--motions", f.ens, "--im", "pgv"]
    f.frag_args += ["--levels", "0.2:1.4:0.4", "--n-boot", 20, "--quiet", "--out", f.frag]
    status, output, _ = _invoke(f.frag_args)
    assert status == 0, output
    f.agx50 = d / "agx50"
    agx50 = ["agx50", "--bodies", f.bodies, "--motions", f.ens, "--resolution", 0.1]
    status, output, _ = _invoke([*agx50, "--out", f.agx50, "--quiet"])
    assert status == 0, output
    return f


def _frag_with(f, *extra):
    return ["fragility", "--bodies", "example", "--motions", f.ens, "--out", f.tmp / "o", *extra]


def _garbage_lognormal(f):
    folder = f.tmp / "frag"
    shutil.copytree(f.frag, folder)
    (folder / "lognormal.csv").write_text("garbage\n1,2\n")
    return ["risk", "--fragility", folder, "--hazard", "example", "--out", f.tmp / "r"]


def _overwrite_as_advised(f):
    folder = f.tmp / "frag"
    shutil.copytree(f.frag, folder)
    return [*f.frag_args[:4], f.ens2, *f.frag_args[5:-1], folder, "--overwrite"]


def _damaged_manifest(f):
    folder = f.tmp / "frag"
    shutil.copytree(f.frag, folder)
    next(folder.rglob("chunks.json")).write_text("{ not json")
    return [*f.frag_args[:-1], folder]


def _in_place(f):
    path = shutil.copy(f.ens, f.tmp / "in.nc")
    return ["motions", "import", path, "--out", path]


GEN = ["motions", "generate", "--out"]
IMPORT = ["motions", "import"]
ASSESS = ["assess", "--bodies", "example", "--spectrum"]
SCREEN = ["screen", "example", "--frame", "paper-2.0", "--spectrum"]
SIM = ["simulate", "--R", "1", "--gamma", "4", "--motion"]


CASES = [
    # ---- issue 49: units that are not understood were read as g
    Case("csv-mm/s2", lambda f: [*IMPORT, f.mm, "--out", f.tmp / "m.nc"], ("A_gx = 0.29",), 0),
    Case("csv-in/s2", lambda f: [*IMPORT, f.inch, "--out", f.tmp / "m.nc"], ("A_gx = 0.29",), 0),
    Case("csv-ft/s2", lambda f: [*IMPORT, f.ft, "--out", f.tmp / "m.nc"], ("A_gx = 0.29",), 0),
    Case("csv-furlongs", lambda f: [*IMPORT, f.furlongs, "--out", f.tmp / "m.nc"],
         ("furlongs.csv", "'furlongs'", "mm/s2")),
    Case("at2-furlongs", lambda f: [*IMPORT, f.at2_furlongs, "--out", f.tmp / "m.nc"],
         ("furlongs.AT2", "furlongs")),
    Case("assess-spectrum-furlongs", lambda f: [*ASSESS, f.spec_furlongs],
         ("spec-furlongs.csv", "furlongs")),
    Case("screen-spectrum-furlongs",
         lambda f: [*SCREEN, f.spec_furlongs, "--out", f.tmp / "s"],
         ("spec-furlongs.csv", "furlongs")),
    # ---- issue 49: a spectrum that does not cover the band got a verdict
    Case("assess-spectrum-5-20-Hz", lambda f: [*ASSESS, f.spec_high],
         ("spec-high", "5–20 Hz", "cannot judge")),
    Case("screen-spectrum-5-20-Hz",
         lambda f: [*SCREEN, f.spec_high, "--out", f.tmp / "s"],
         ("spec-high", "cannot judge")),
    # ---- issue 49: an all-zero ensemble, a sample of 1e30 g, dt against the time axis
    Case("assess-all-zero", lambda f: [*ASSESS, f.zero], ("zero.nc",)),
    Case("fragility-all-zero",
         lambda f: ["fragility", "--bodies", "example", "--motions", f.zero, "--agx", "0.1:0.3:0.1",
                    "--out", f.tmp / "o"], ("zero.nc",)),
    Case("import-1e30-g", lambda f: [*IMPORT, f.huge, "--out", f.tmp / "m.nc"],
         ("huge.csv", "above 100 g: refused")),
    Case("fragility-1e30-g",
         lambda f: ["fragility", "--bodies", "example", "--motions", f.huge_nc,
                    "--agx", "0.1:0.3:0.1", "--out", f.tmp / "o"], ("huge.nc", "1e+30 g")),
    Case("screen-1e30-g",
         lambda f: ["screen", f.inv, "--spectrum", "rg160:0.3", "--motions", f.huge_nc,
                    "--out", f.tmp / "s"], ("huge.nc", "1e+30 g")),
    Case("simulate-1e30-g", lambda f: [*SIM, f.huge], ("huge.csv", "above 100 g: refused")),
    Case("show-dt-disagrees",
         lambda f: ["motions", "show", f.dt_nc, "--out", f.tmp / "show"],
         ("dt.nc", "disagrees with its time axis")),
    Case("fragility-dt-disagrees",
         lambda f: ["fragility", "--bodies", "example", "--motions", f.dt_nc,
                    "--agx", "0.1:0.3:0.1", "--out", f.tmp / "o"],
         ("dt.nc", "disagrees with its time axis")),
    Case("screen-dt-disagrees",
         lambda f: ["screen", f.inv, "--spectrum", "rg160:0.3", "--motions", f.dt_nc,
                    "--out", f.tmp / "s"], ("dt.nc", "disagrees with its time axis")),
    # ---- issue 49: the user's mistake reported as our bug (exit 70)
    Case("simulate-plot-xyz", lambda f: [*SIM, "example", "--plot", f.tmp / "out.xyz"],
         ("out.xyz", ".xyz")),
    Case("spectrum-plot-xyz", lambda f: ["spectrum", "example", "--plot", f.tmp / "out.xyz"],
         ("out.xyz", ".xyz")),
    Case("frame-show-plot-xyz",
         lambda f: ["frame", "show", "paper-2.0", "--plot", f.tmp / "out.xyz"],
         ("out.xyz", ".xyz")),
    Case("generate-target-binary",
         lambda f: ["motions", "generate", "--target", f.binary, "--out", f.tmp / "g.nc"],
         ("binary.csv", "not a text file")),
    Case("import-manifest-binary",
         lambda f: [*IMPORT, "--manifest", f.binary, "--out", f.tmp / "m.nc"],
         ("binary.csv", "not a text file")),
    Case("assess-spectrum-binary", lambda f: [*ASSESS, f.binary], ("binary.csv", "not a text")),
    Case("screen-spectrum-binary",
         lambda f: [*SCREEN, f.binary, "--out", f.tmp / "s"],
         ("binary.csv", "not a text file")),
    Case("frame-file-binary", lambda f: ["frame", "show", "--frame-file", f.binary_toml],
         ("binary.toml", "not a text file")),
    Case("reproduce-config-binary",
         lambda f: ["reproduce", "4", "--config", f.binary_toml, "--out", f.tmp / "r"],
         ("binary.toml", "not a text file")),
    Case("generate-seed-overflow",
         lambda f: [*GEN, f.tmp / "g.nc", "--seed", "99999999999999999999999"],
         ("--seed", "2147483647"), within=SIZE_S),
    Case("reproduce-set-bootstrap-1",
         lambda f: ["reproduce", "soundness", "--set", "soundness.bootstrap=-1", "--out",
                    f.tmp / "r"], ("soundness.bootstrap", "-1")),
    Case("risk-garbage-lognormal", _garbage_lognormal, ("lognormal.csv",)),
    # ---- issue 49: a command must never write into, or clear, the folder it reads
    Case("risk-out-is-its-fragility",
         lambda f: ["risk", "--fragility", f.frag, "--hazard", "example", "--out", f.frag],
         ("--out", str(Path("frag")))),
    # ---- issue 49: option errors were three lines with exit status 2
    Case("option-unknown", lambda f: ["fragility", "--bogus"], ("--bogus",), within=SIZE_S),
    Case("option-bad-value", lambda f: [*SIM[:-1], "--motion", "example", "--R", "x"],
         ("--R", "'x'"), within=SIZE_S),
    Case("command-unknown", lambda f: ["no-such-command"], ("no-such-command",), within=SIZE_S),
    # ---- issue 48: nonsense accepted silently
    Case("import-gal-without-units", lambda f: [*IMPORT, f.gal, "--out", f.tmp / "m.nc"],
         ("gal.csv", "likely in cm/s2", "refused")),
    Case("import-record-dt-two-files",
         lambda f: [*IMPORT, f.one_a, f.one_b, "--record-dt", 0.01, "--out", f.tmp / "m.nc"],
         ("one-a", "one-b", "manifest")),
    Case("spectrum-dt-is-record-dt",
         lambda f: ["spectrum", f.one_a, "--dt", 0.01, "--csv", f.tmp / "s.csv"],
         ("--dt", "renamed --record-dt"), 0, True),
    Case("bodies-H-B-swapped", lambda f: ["assess", "--bodies", f.swapped, "--spectrum",
                                           "rg160:0.3"], ("H = 0.6 m", "B = 2 m"), 0, True),
    Case("fragility-agx-100-g", lambda f: _frag_with(f, "--agx", "100:200:50"),
         ("--agx", "200 g", "above 10 g")),
    Case("simulate-scale-g-1e200", lambda f: [*SIM, "example", "--scale-g", "1e200"],
         ("--scale-g", "1e+200 g")),
    # ---- issue 45: friction options, refused before any work
    Case("simulate-mu-negative", lambda f: [*SIM, "example", "--mu", "-1"],
         ("--mu", "> 0", "-1")),
    Case("fragility-mu-k-without-mu", lambda f: _frag_with(f, "--mu-k", "0.5"),
         ("--mu-k needs --mu",)),
    Case("agx50-bodies-mu-k-above-mu",
         lambda f: ["agx50", "--bodies", f.bodies_mu, "--motions", f.ens, "--out", f.tmp / "o"],
         ("bodies-mu.csv", "row 2", "mu_k = 0.5")),
    Case("agx50-mu-k-above-mu",
         lambda f: ["agx50", "--bodies", "example", "--motions", f.ens, "--mu", "0.3",
                    "--mu-k", "0.4", "--out", f.tmp / "o"], ("--mu-k = 0.4", "--mu = 0.3")),
    Case("agx50-agx-max-1e9",
         lambda f: ["agx50", "--bodies", "example", "--motions", f.ens, "--agx-max", "1e9",
                    "--out", f.tmp / "o"], ("--agx-max", "1e+09 g")),
    Case("agx50-limit-states-unknown-quantity",
         lambda f: ["agx50", "--bodies", "example", "--motions", f.ens, "--limit-states",
                    "uplift, slide", "--out", f.tmp / "o"],
         ("limit states", "unknown quantity 'slide'"), within=SIZE_S),
    Case("agx50-band-above-nyquist",
         lambda f: ["agx50", "--bodies", "example", "--motions", f.ens, "--band", "0.04:1000",
                    "--out", f.tmp / "o"], ("--band 0.04:1000", "Nyquist")),
    Case("assess-rg160-1e6", lambda f: [*ASSESS, "rg160:1e6"], ("rg160:1e6", "1e+06 g")),
    Case("import-dt-5-s", lambda f: [*IMPORT, "example", "--dt", 5, "--out", f.tmp / "m.nc"],
         ("dt = 5 s", "0.05 s"), within=SIZE_S),
    Case("import-at2-units-against-header",
         lambda f: [*IMPORT, "example", "--units", "cm/s2", "--out", f.tmp / "m.nc"],
         ("ElCentro1940_NS.AT2", "units cm/s2 given", "states g")),
    Case("import-out-is-its-input", _in_place, ("in.nc", "--out")),
    Case("import-location-roof-garden",
         lambda f: [*IMPORT, "example", "--location", "roof garden", "--out", f.tmp / "m.nc"],
         ("location 'roof garden'",)),
    Case("screen-inventory-floor-0",
         lambda f: ["screen", f.inv_floor0, "--spectrum", "rg160:0.3", "--n", 4, "--duration",
                    4, "--resolution", 0.2, "--out", f.tmp / "s", "--quiet"],
         ("inv-floor0.csv", "row 2", "floor 0"), 0, True),
    Case("screen-inventory-height-twice",
         lambda f: ["screen", f.inv_twice, "--spectrum", "rg160:0.3", "--out", f.tmp / "s"],
         ("inv-twice.csv", "row 1", "height")),
    Case("generate-out-txt", lambda f: [*GEN, f.tmp / "m.txt", "--n", 2], ("m.txt", ".nc")),
    Case("fragility-out-is-an-agx50-folder",
         lambda f: ["fragility", "--bodies", f.bodies, "--motions", f.ens, "--agx",
                    "0.1:0.3:0.1", "--out", f.agx50], ("agx50", "--overwrite")),
    Case("import-format-not-recognised", lambda f: [*IMPORT, f.unknown, "--out", f.tmp / "m.nc"],
         ("record.dat", "not recognised", "AT2")),
    # ---- issue 48: dead ends
    Case("fragility-occupied-by-another-run",
         lambda f: [*f.frag_args[:4], f.ens2, *f.frag_args[5:]],
         ("frag", "another run", "--overwrite")),
    Case("fragility-overwrite-as-advised", _overwrite_as_advised, ("wrote",), 0, one_line=False),
    Case("screen-out-is-a-fragility-folder",
         lambda f: ["screen", f.inv, "--spectrum", "rg160:0.3", "--out", f.frag],
         ("frag", "--overwrite")),
    Case("fragility-damaged-chunks-json", _damaged_manifest, ("chunks.json", "rebuilt"), 0,
         True),
    Case("bodies-gamma-200", lambda f: ["assess", "--bodies", f.slender, "--spectrum",
                                         "rg160:0.3"], ("gamma", "200"), 0, True),
    # ---- issue 48: sizes, bounded before any work
    Case("fragility-agx-1e-7", lambda f: _frag_with(f, "--agx", "0.1:1.0:1e-7"),
         ("--agx 0.1:1.0:1e-7", "limit"), within=SIZE_S),
    Case("fragility-agx-1e-9", lambda f: _frag_with(f, "--agx", "0.1:1.0:1e-9"),
         ("--agx 0.1:1.0:1e-9", "limit"), within=SIZE_S),
    Case("spectrum-n-1e8", lambda f: ["spectrum", "example", "--n", "100000000"],
         ("--n 100,000,000", "limit"), within=SIZE_S),
    Case("fit-per-decade-1e8",
         lambda f: ["motions", "fit", "--per-decade", "100000000", "--out", f.tmp / "fit"],
         ("--per-decade 100,000,000", "limit"), within=SIZE_S),
    Case("generate-iterations-1e5", lambda f: [*GEN, f.tmp / "g.nc", "--iterations", 100000],
         ("--iterations 100,000", "limit"), within=SIZE_S),
    Case("fragility-n-boot-1e4",
         lambda f: _frag_with(f, "--im", "pgv", "--levels", "0.1:1.5:0.1", "--n-boot", 10000),
         ("--n-boot 10,000", "limit"), within=SIZE_S),
    Case("fragility-scheduler-unreachable",
         lambda f: _frag_with(f, "--agx", "0.1:0.3:0.1", "--scheduler", "tcp://127.0.0.1:1",
                              "--connect-timeout", 1),
         ("tcp://127.0.0.1:1", "--connect-timeout")),
    Case("screen-scheduler-unreachable",
         lambda f: ["screen", f.inv, "--spectrum", "rg160:0.3", "--scheduler",
                    "tcp://127.0.0.1:1", "--connect-timeout", 1, "--out", f.tmp / "s"],
         ("tcp://127.0.0.1:1", "--connect-timeout")),
]  # fmt: skip


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_each_adversarial_case_gives_one_line_and_the_right_exit_status(files, tmp_path, case):
    f = SimpleNamespace(**vars(files), tmp=tmp_path)
    args = case.args(f)
    before = set(tmp_path.iterdir())
    status, output, elapsed = _invoke(args)
    assert status == case.status, (args, status, output)
    assert "Traceback" not in output and "internal error" not in output, output
    lines = output.strip().splitlines()
    warned = [line for line in lines if line.startswith("warning: ")]
    if case.warns:
        assert len(warned) == 1, output
        line = warned[0]
    else:
        assert not warned and "Warning" not in output, output
        assert len(lines) == 1 or not case.one_line, output
        line = lines[-1]
        assert line.startswith("Error: ") == (status != 0), line
    if status != 0:  # refused before any work: nothing written
        assert set(tmp_path.iterdir()) == before, sorted(set(tmp_path.iterdir()) - before)
    for word in case.words:
        assert word in line, (word, line)
    assert elapsed < case.within, (args, elapsed)
    print(f"{case.name}: {elapsed:.2f} s")


def _lines(output: str) -> list[str]:
    return [line for line in output.strip().splitlines() if line]


def test_a_full_disk_is_one_line_naming_the_file(tmp_path, monkeypatch):
    # issue 49: "When the disk is full the error is 'No space left on device', without the file
    # or folder". The disk fills while the file is written (its fsync fails with ENOSPC).
    import errno
    import os

    import rocking.core.files

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(rocking.core.files.os, "fsync", full)
    out = tmp_path / "m.nc"
    status, output, _ = _invoke([*IMPORT, "example", "--out", out])
    assert status == 1, output
    assert "Traceback" not in output and "internal error" not in output
    [line] = _lines(output)
    assert "No space left on device" in line and str(out) in line, line
    assert not out.exists()


def test_a_cache_folder_that_cannot_be_written_is_one_warning_line(tmp_path):
    # issue 49: with ROCKING_CACHE_DIR on a path where nothing can be written, the kernels were
    # compiled again in every run, with no word. A command run so warns once, in one line, and
    # works (the kernels are kept in the user's cache folder instead; this command loads the
    # kernels' settings but compiles none, so the test takes half a second).
    import os
    import subprocess
    import sys

    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    env = {**os.environ, "ROCKING_CACHE_DIR": str(blocker / "cache")}
    env.pop("NUMBA_CACHE_DIR", None)
    args = [*IMPORT, "example", "--out", tmp_path / "m.nc"]
    proc = subprocess.run(
        [sys.executable, "-m", "rocking", *map(str, args)], env=env, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    output = proc.stdout + proc.stderr
    assert "Traceback" not in output
    warned = [line for line in _lines(output) if line.startswith("warning: ")]
    assert len(warned) == 1 and "ROCKING_CACHE_DIR" in warned[0], output
    assert output.count("cannot hold the compiled kernels") == 1, output
