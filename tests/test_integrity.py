"""Results that cannot lie: chunk fingerprints, claimed folders, integer A_gx levels, memory
estimates, a lost Dask cluster, file modes, and the CLI telling a user's mistake from a bug.

Each test reproduces a defect found in issue 14 and checks that it is gone.
"""

from __future__ import annotations

import json
import os
import shutil
import stat
import struct
import subprocess
import sys
import threading
import zipfile
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from rocking.core.files import atomic_write
from rocking.core.runs import RunFolder
from rocking.dynamics.body import Block, BodyWarning, housner_sv
from rocking.errors import BackendError, InputError
from rocking.montecarlo import store
from rocking.montecarlo.engine import level_agx, level_key
from rocking.montecarlo.probability import overturning_probability
from rocking.motions.synthesis import generate

BLOCKS = [Block(0.6, 3.0), Block(1.22, 4.0)]
AGX = [0.3, 0.6, 0.9]
SCIENCE = ("probability", "count", "n", "ci_low", "ci_high")


@pytest.fixture(scope="module")
def motions():
    """Two ensembles of the same size and sampling that overturn the blocks differently."""
    return generate(8, duration=6.0, dt=1 / 200, seed=9), generate(
        8, duration=6.0, dt=1 / 200, seed=10
    )


def _science(ds):
    """The results without the counts of chunks computed and loaded."""
    out = ds[list(SCIENCE)]
    out.attrs = {k: v for k, v in ds.attrs.items() if not k.startswith("chunks_")}
    return out


def test_chunks_of_another_run_in_the_folder_are_never_loaded(motions, tmp_path):
    # The defect: two runs started together into one folder with different motions both wrote
    # their chunks (same file names: same bodies and levels); a rerun of the first then loaded
    # the second's results as its own. Here the second run's chunks are put in the first run's
    # folder, as that race left them.
    a, b = motions
    ref_a = overturning_probability(BLOCKS, a, AGX)
    ref_b = overturning_probability(BLOCKS, b, AGX)
    assert not ref_a["count"].equals(ref_b["count"])  # the mix-up would be visible
    run_a, run_b = tmp_path / "a", tmp_path / "b"
    overturning_probability(BLOCKS, a, AGX, out=run_a, chunk_size=8)
    overturning_probability(BLOCKS, b, AGX, out=run_b, chunk_size=8)
    names = sorted(p.name for p in run_b.glob("chunk-*.npz"))
    assert names == sorted(p.name for p in run_a.glob("chunk-*.npz"))  # the same file names
    for name in names:
        shutil.copy(run_b / name, run_a / name)
    again = overturning_probability(BLOCKS, a, AGX, out=run_a, chunk_size=8)
    assert again.attrs["chunks_loaded"] == 0  # none of b's chunks is taken for a's
    xr.testing.assert_identical(_science(again), _science(ref_a))


def test_chunks_of_another_version_are_computed_again(motions, tmp_path, monkeypatch):
    a, _ = motions
    first = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    assert first.attrs["chunks_computed"] > 0
    same = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    assert same.attrs["chunks_loaded"] == first.attrs["chunks_computed"]
    # an upgrade changes the kernel source: the old chunks must not be mixed with new results
    monkeypatch.setattr(
        store, "code_version", lambda: {"version": "9.9", "kernel_sha256": "0" * 64}
    )
    upgraded = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    assert upgraded.attrs["chunks_loaded"] == 0
    assert upgraded.attrs["chunks_computed"] == first.attrs["chunks_computed"]
    xr.testing.assert_identical(_science(upgraded), _science(first))


HOLD_SCRIPT = """
import sys
from rocking.montecarlo.store import ChunkStore
with ChunkStore(sys.argv[1], {"run": "first"}):
    print("claimed", flush=True)
    sys.stdin.readline()   # hold the folder until the test says so
"""


def test_a_folder_in_use_by_another_run_is_refused(tmp_path):
    # The defect: two runs into one folder at the same instant both succeeded. The claim is an
    # OS lock held by the first process; the second stops at once, whatever its parameters.
    proc = subprocess.Popen(
        [sys.executable, "-c", HOLD_SCRIPT, str(tmp_path)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout.readline().strip() == "claimed"  # an observable event, not a sleep
        for params in ({"run": "first"}, {"run": "second"}):
            with pytest.raises(InputError, match="in use"), store.ChunkStore(tmp_path, params):
                pass
        with (
            pytest.raises(InputError, match="in use"),
            RunFolder(tmp_path, command="test", params={}),
        ):
            pass
    finally:
        proc.stdin.write("\n")
        proc.stdin.close()
        proc.wait(timeout=60)
    with store.ChunkStore(tmp_path, {"run": "first"}):  # free again once the first has ended
        pass


def test_levels_are_keyed_by_integers(motions, tmp_path):
    a, _ = motions
    assert level_key(0.1 + 0.2) == level_key(0.3) == 300_000_000
    assert level_agx(level_key(0.23000000000046314)) == 0.23  # no float noise in the result
    first = overturning_probability(BLOCKS, a, [0.3], out=tmp_path)
    again = overturning_probability(BLOCKS, a, [0.1 + 0.2], out=tmp_path)
    assert again.attrs["chunks_computed"] == 0  # one level, found by its integer key
    assert again["agx"].values.tolist() == [0.3]
    xr.testing.assert_identical(_science(again), _science(first))


def test_work_too_large_for_memory_is_refused_before_it_starts(motions):
    # The defect: --agx 0.1:1.0:1e-7 (9 million levels) ran until the OS killed it at 23 GB.
    a, _ = motions
    agx = np.arange(9_000_001) * 1e-7 + 0.1
    with pytest.raises(InputError, match=r"agx: .* would need about .* of memory"):
        overturning_probability([Block(1.0, 4.0)] * 72, a, agx)
    with pytest.raises(InputError, match=r"n 1,000,000,000 is above the limit of 100,000"):
        generate(1_000_000_000)
    with pytest.raises(InputError, match=r"n: .* would need about .* of memory"):
        generate(50_000, duration=10_000.0)


def _close_cluster_when_first_chunk_is_written(backend, folder, done):
    while not done.is_set():
        if list(folder.glob("chunk-*.npz")):
            backend.client.cluster.close()  # every worker lost at once
            return
        done.wait(0.005)


def test_losing_every_dask_worker_is_a_clear_error_and_the_folder_resumes(motions, tmp_path):
    from rocking.montecarlo.backends import DaskBackend

    a, _ = motions
    agx = np.round(np.arange(0.1, 8.0, 0.05), 12)
    backend = DaskBackend(n_workers=2)
    done = threading.Event()
    watcher = threading.Thread(
        target=_close_cluster_when_first_chunk_is_written,
        args=(backend, tmp_path, done),
        daemon=True,
    )
    assert backend.workers == 2  # (connects: the cluster starts before the watching)
    watcher.start()
    try:
        with pytest.raises(BackendError, match="Dask"):
            overturning_probability(BLOCKS, a, agx, out=tmp_path, backend=backend, chunk_size=8)
    finally:
        done.set()
        watcher.join()
        backend.close()
    saved = len(list(tmp_path.glob("chunk-*.npz")))
    assert saved > 0
    resumed = overturning_probability(BLOCKS, a, agx, out=tmp_path, chunk_size=8)
    assert resumed.attrs["chunks_loaded"] == saved
    xr.testing.assert_identical(
        _science(resumed), _science(overturning_probability(BLOCKS, a, agx))
    )


def test_chunks_a_system_crash_damaged_are_computed_again(motions, tmp_path):
    # Chunks are not flushed to the disk one by one (ChunkStore.save, durable=False): after a
    # power loss a chunk may hold zeros or another file's blocks. Each kind of damage must make
    # the chunk count as missing and be computed again, never be loaded as results.
    a, _ = motions
    ref = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    chunks = sorted(tmp_path.glob("chunk-*.npz"))
    assert len(chunks) >= 3
    raw = chunks[0].read_bytes()
    chunks[0].write_bytes(bytes(len(raw)))  # zeros
    raw = bytearray(chunks[1].read_bytes())  # the last byte of one array's data flipped
    with zipfile.ZipFile(chunks[1]) as z:
        member = z.infolist()[-1]
    start = member.header_offset  # local header: 30 bytes, then the name and the extra field
    name_len, extra_len = struct.unpack("<HH", raw[start + 26 : start + 30])
    raw[start + 30 + name_len + extra_len + member.compress_size - 1] ^= 0xFF
    chunks[1].write_bytes(bytes(raw))
    chunks[2].write_bytes(b"")  # nothing
    resumed = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    assert resumed.attrs["chunks_loaded"] == len(chunks) - 3
    assert resumed.attrs["chunks_computed"] == 3
    xr.testing.assert_identical(_science(resumed), _science(ref))


def test_files_follow_the_umask(tmp_path):
    # The defect: report files were created mode 0600 whatever the umask (tempfile.mkstemp).
    old = os.umask(0o022)
    try:
        path = atomic_write(tmp_path / "a.txt", "text")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
    assert path.read_text() == "text"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]  # no temporary file left


def test_run_folder_records_status_and_removes_the_previous_runs_outputs(tmp_path):
    with RunFolder(tmp_path, command="test", params={"x": 1}) as run:
        run.write("tables/a.csv", "a\n1\n")
        assert json.loads((tmp_path / "run.json").read_text())["status"] == "running"
    info = json.loads((tmp_path / "run.json").read_text())
    assert info["status"] == "completed" and info["outputs"] == ["tables/a.csv"]
    (tmp_path / "notes.txt").write_text("the user's own file")
    # the defect: an interrupted rerun left the previous run's tables looking complete
    with pytest.raises(KeyboardInterrupt), RunFolder(tmp_path, command="test", params={"x": 1}):
        assert not (tmp_path / "tables" / "a.csv").exists()
        raise KeyboardInterrupt
    info = json.loads((tmp_path / "run.json").read_text())
    assert info["status"] == "failed" and info["outputs"] == []
    assert (tmp_path / "notes.txt").exists()  # never a file the run did not write


def test_cli_tells_a_bug_from_a_users_mistake(monkeypatch, tmp_path):
    from rocking.cli import main

    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path))
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    runner = CliRunner()
    user = runner.invoke(main, ["simulate", "--R", "-1", "--gamma", "4", "--motion", "example"])
    assert user.exit_code == 1 and "Error: R must be" in user.output
    assert "Traceback" not in user.output and len(user.output.strip().splitlines()) == 1

    import rocking.dynamics.simulate

    def broken(*args, **kw):
        raise KeyError("a bug")

    monkeypatch.setattr(rocking.dynamics.simulate, "simulate", broken)
    bug = runner.invoke(main, ["simulate", "--R", "1", "--gamma", "4", "--motion", "example"])
    assert bug.exit_code == 70
    assert "internal error" in bug.output and "a bug, not a problem with your input" in bug.output
    saved = bug.output.split("traceback is in ")[1].split("; please")[0]
    assert "KeyError" in Path(saved).read_text()


def test_motions_above_the_nyquist_frequency_are_refused():
    # The defect: RG 1.60 motions at dt = 1 s were generated (the components reach 50 Hz, the
    # target 33 Hz; a 1 s step resolves 0.5 Hz).
    with pytest.raises(InputError, match=r"dt = 1 s samples frequencies up to 0.5 Hz"):
        generate(2, dt=1.0)


def test_generate_checks_its_output_file_before_the_work(tmp_path):
    # The defect: `rocking motions generate` found that --out could not be written only after
    # simulating every motion. 100,000 motions would take minutes: the answer must be at once.
    import time

    from rocking.cli import main

    start = time.perf_counter()
    result = CliRunner().invoke(
        main,
        ["motions", "generate", "--n", "100000", "--out", str(tmp_path / "missing" / "ens.nc")],
    )
    assert result.exit_code == 1 and "--out" in result.output and "does not exist" in result.output
    assert time.perf_counter() - start < 10.0


def test_show_config_refuses_invalid_values():
    # The defect: --show-config printed a configuration that the run would then refuse.
    from rocking.cli import main

    result = CliRunner().invoke(
        main, ["reproduce", "all", "--show-config", "--set", 'sec7.frames=["paper-3.0"]']
    )
    assert result.exit_code == 1
    assert "sec7.frames: unknown frame preset 'paper-3.0'" in result.output


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Block(1e308, 4.0), r"R = 1e\+308 m is larger than the Earth"),
        (lambda: Block(1.0, 4.0, r_g=1e300), r"r_g = 1e\+300 m is larger than the Earth"),
        (lambda: Block(1.0, float("nan")), r"gamma must be a finite number > 0"),
    ],
)
def test_nonsense_bodies_are_refused(make, message):
    # The defect: R = 1e308 m was accepted and reported "safe" (Eq. 11 overflowed to inf).
    # Issue 48 asks to refuse only what is not physical: a body larger than the Earth is none,
    # and a gamma that is not a number; gamma = 1e-9 (a plate) or 2000 (a needle) only warn.
    with pytest.raises(InputError, match=message):
        make()


@pytest.mark.parametrize(
    "make", [lambda: Block(1.0, 1e-9), lambda: Block.from_dimensions(2000.0, 1.0)]
)
def test_unusual_bodies_warn(make):
    with pytest.warns(BodyWarning, match="outside the usual range"):
        assert np.isfinite(housner_sv(make()))


def test_nonsense_tables_and_specifications_are_refused(tmp_path):
    from rocking.assessment.bodies import read_bodies
    from rocking.assessment.screen import screen
    from rocking.motions.design import parse_spectrum

    # a spectrum specification that gives a key twice: which one would be used?
    with pytest.raises(InputError, match="SDS is given twice"):
        parse_spectrum("asce7:SDS=1,SDS=2,SD1=0.6,TL=8")
    # a CSV row with more cells than the header has columns (a shifted row)
    path = tmp_path / "bodies.csv"
    path.write_text("R,gamma\n1.2,4\n1.5,3,7\n")
    with pytest.raises(InputError, match=r"row 2 \(line 3\): 3 value\(s\) for 2 columns"):
        read_bodies(path)
    # nothing to screen: a clear error, not a TypeError
    with pytest.raises(InputError, match="inventory is empty"):
        screen([], "rg160:0.3")


def test_fragility_and_agx50_folders_record_their_run(motions, tmp_path):
    # The defect: `fragility` and `agx50` wrote no run.json.
    from rocking.cli import main

    a, _ = motions
    path = tmp_path / "m.nc"
    a.save(path)
    bodies = tmp_path / "b.csv"
    bodies.write_text("R,gamma\n0.6,3\n1.22,4\n")
    for command, extra, table in (
        ("fragility", ["--agx", "0.3:0.9:0.3"], "probabilities.csv"),
        ("agx50", ["--resolution", "0.1"], "agx50.csv"),
    ):
        out = tmp_path / command
        result = CliRunner().invoke(
            main,
            [
                command,
                "--bodies",
                str(bodies),
                "--motions",
                str(path),
                "--out",
                str(out),
                "--quiet",
                *extra,
            ],
        )
        assert result.exit_code == 0, result.output
        info = json.loads((out / "run.json").read_text())
        assert info["status"] == "completed" and info["command"] == command
        assert table in info["outputs"] and all((out / f).is_file() for f in info["outputs"])
        assert info["n_motions"] == a.n and info["motions"] == str(path)


def test_an_interrupted_screen_rerun_leaves_no_old_tables(tmp_path, monkeypatch):
    # The defect: an interrupted rerun of `screen` left the previous run's tables beside it,
    # looking complete.
    import rocking.assessment.screen
    from rocking.cli import main

    args = [
        "screen",
        "example",
        "--spectrum",
        "asce7:SDS=1.0,SD1=0.6,TL=8",
        "--frame",
        "paper-2.0",
        "--n",
        "4",
        "--duration",
        "4",
        "--resolution",
        "0.2",
        "--out",
        str(tmp_path),
        "--quiet",
    ]
    assert CliRunner().invoke(main, args).exit_code == 0
    assert (tmp_path / "tables" / "screen.csv").is_file()

    def interrupted(*a, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(rocking.assessment.screen, "screen", interrupted)
    assert CliRunner().invoke(main, args).exit_code != 0
    assert not (tmp_path / "tables" / "screen.csv").exists()
    assert not (tmp_path / "report.html").exists()
    assert json.loads((tmp_path / "run.json").read_text())["status"] == "failed"


def test_compiled_kernels_are_cached_in_the_user_cache_folder(tmp_path):
    # A read-only install must keep its compiled kernels: they go to the user's cache folder
    # (here ROCKING_CACHE_DIR), never next to the sources. Numba fixes a function's cache
    # folder when it is decorated; every kernel of the package is asked where it is.
    env = {**os.environ, "ROCKING_CACHE_DIR": str(tmp_path)}
    code = (
        "import importlib, pkgutil, rocking\n"
        "from numba.core.registry import CPUDispatcher\n"
        "for m in pkgutil.walk_packages(rocking.__path__, 'rocking.'):\n"
        "    if m.name.endswith('__main__'):\n"
        "        continue\n"
        "    mod = importlib.import_module(m.name)\n"
        "    for obj in vars(mod).values():\n"
        "        if isinstance(obj, CPUDispatcher) and obj.__module__ == mod.__name__:\n"
        "            print(obj._cache._cache_path)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, check=True, text=True, capture_output=True
    ).stdout.split()
    assert len(out) >= 10  # the kernels of dynamics, batch, spectra, frames, motions
    assert all(path.startswith(str(tmp_path / "numba")) for path in out), out


def test_a_full_disk_names_the_file_it_could_not_write(tmp_path, monkeypatch):
    # The defect (issue 49): a full disk ended a run with "No space left on device", naming no
    # file. The atomic writer names the file it was writing, and leaves no temporary file.
    import errno

    import rocking.core.files
    from rocking.cli import main

    def full(fh):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    target = tmp_path / "a.npz"
    with pytest.raises(OSError) as caught:
        atomic_write(target, full)
    assert caught.value.errno == errno.ENOSPC and caught.value.filename == str(target)
    assert list(tmp_path.iterdir()) == []

    def fsync(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with (
        pytest.raises(OSError) as caught,
        RunFolder(tmp_path / "run", command="t", params={}) as run,
    ):
        monkeypatch.setattr(rocking.core.files.os, "fsync", fsync)  # the disk is full from now
        run.write("table.csv", "a\n1\n")
    assert caught.value.filename == str(tmp_path / "run" / "table.csv")  # not run.json's failure
    csv = tmp_path / "table1.csv"
    result = CliRunner().invoke(main, ["table1", "--csv", str(csv)])
    assert result.exit_code == 1
    assert result.output.splitlines()[-1] == f"Error: {csv}: No space left on device"


def _cli(*args: str):
    """``rocking ARGS`` in this process: (exit status, output lines)."""
    from rocking.cli import main

    result = CliRunner().invoke(main, [str(a) for a in args])
    return result.exit_code, result.output.strip().splitlines()


def _files(folder: Path) -> dict[str, bytes]:
    """Every file of ``folder`` but run.json (which records times) and the lock, by path."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.name not in ("run.json", ".rocking.lock")
    }


def test_another_run_is_refused_at_once_and_overwrite_replaces_it(motions, tmp_path):
    # The defect (issue 48): `fragility --out F` with other motions than F's run deleted F's
    # results, then refused ("holds results of a different run"), and the advice printed led
    # nowhere. Now the folder is refused before anything in it is touched, the advice
    # (--overwrite) works, and the same run still resumes.
    a, b = motions
    paths = {}
    for name, ens in (("a", a), ("b", b)):
        paths[name] = tmp_path / f"{name}.nc"
        ens.save(paths[name])
    out = tmp_path / "frag"
    common = ["--bodies", "example", "--agx", "0.3:0.9:0.3", "--out", out, "--quiet"]
    assert _cli("fragility", "--motions", paths["a"], *common)[0] == 0
    before = _files(out)
    assert "probabilities.csv" in before and any(n.startswith("chunks/") for n in before)
    status, lines = _cli("fragility", "--motions", paths["b"], *common)
    assert status == 1 and len(lines) == 1, lines
    assert "holds the results of another run" in lines[0] and "motions" in lines[0]
    assert "--overwrite" in lines[0]
    assert _files(out) == before  # nothing deleted, nothing added
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "completed" and info["motions"] == str(paths["a"])
    # into a folder of another command: refused the same way
    status, lines = _cli("agx50", "--bodies", "example", "--motions", paths["a"], "--out", out)
    assert status == 1 and "a run of 'rocking fragility'" in lines[0], lines
    assert _files(out) == before
    # the advice works: the other run replaces the first, whose chunks go too
    assert _cli("fragility", "--motions", paths["b"], *common, "--overwrite")[0] == 0
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "completed" and info["motions"] == str(paths["b"])
    replaced = _files(out)
    assert replaced["probabilities.csv"] != before["probabilities.csv"]
    # the same run again resumes from its chunks, to the same bytes
    assert _cli("fragility", "--motions", paths["b"], *common)[0] == 0
    assert _files(out) == replaced
    info = json.loads((out / "run.json").read_text())
    assert info["bookkeeping"]["probabilities.nc"]["chunks_computed"] == 0


def test_a_command_never_writes_into_the_folder_it_reads(motions, tmp_path):
    # The defect (issue 49): `risk --fragility F --out F` deleted the fragility's results and
    # left only the risk files. Refused, naming both, with or without --overwrite.
    a, _ = motions
    path = tmp_path / "a.nc"
    a.save(path)
    frag = tmp_path / "frag"
    args = ["--bodies", "example", "--motions", path, "--im", "pgv", "--levels", "0.2:0.6:0.2"]
    assert _cli("fragility", *args, "--n-boot", "0", "--out", frag, "--quiet")[0] == 0
    before = _files(frag)
    for out in (frag, frag / "risk"):
        for extra in ([], ["--overwrite"]):
            status, lines = _cli(
                "risk", "--fragility", frag, "--hazard", "example", "--out", out, *extra
            )
            assert status == 1 and len(lines) == 1, lines
            assert f"out {out}: the run reads the folder --fragility {frag}" in lines[0]
    assert _files(frag) == before and not (frag / "risk").exists()
    # a file the run reads, written by the folder's previous run, is not deleted by --overwrite
    folder = tmp_path / "gen"
    with RunFolder(folder, command="first", params={}) as run:
        made = run.write("m.nc", b"motions")
    again = RunFolder(
        folder, command="second", params={}, overwrite=True, reads={"--motions": made}
    )
    with pytest.raises(InputError, match=f"the run reads --motions {made}, a file of the"), again:
        pass
    assert made.read_bytes() == b"motions"


def test_every_command_that_writes_a_folder_can_overwrite(tmp_path):
    # The rule is the same for every command with an output folder (`screen` silently replaced
    # another run's results): --overwrite exists on each.
    import click

    from rocking.cli import COMMAND_MODULES, main

    ctx = click.Context(main)
    folders = []
    stack = [(name, main.get_command(ctx, name)) for name in COMMAND_MODULES]
    while stack:
        name, command = stack.pop()
        if isinstance(command, click.Group):
            stack += [(f"{name} {n}", c) for n, c in command.commands.items()]
            continue
        for param in command.params:
            if "--out" in getattr(param, "opts", ()) and not param.type.file_okay:
                folders.append(name)
                assert any("--overwrite" in p.opts for p in command.params), name
    assert sorted(folders) == [
        "agx50",
        "fragility",
        "motions fit",
        "motions show",
        "pulse-spectrum",
        "reproduce",
        "risk",
        "screen",
    ]
    # screen: the same run again is accepted, another refused before it starts
    args = ["screen", "example", "--spectrum", "asce7:SDS=1.0,SD1=0.6,TL=8", "--n", "4"]
    args += ["--frame", "paper-2.0"]
    args += ["--duration", "4", "--resolution", "0.2", "--out", tmp_path, "--quiet"]
    assert _cli(*args)[0] == 0
    before = _files(tmp_path)
    status, lines = _cli(*args[:-1], "--seed", "1", "--quiet")
    assert status == 1 and "other seed" in lines[-1] and "--overwrite" in lines[-1], lines
    assert _files(tmp_path) == before


def test_a_chunk_rewritten_with_other_values_is_computed_again(motions, tmp_path):
    # The defect (issue 48): a chunk file rewritten with a valid structure, its fingerprint and
    # other values (a disk error, a stray script) was loaded as it was: the rerun reported other
    # probabilities. Its SHA-256 no longer matches the one recorded in chunks.json.
    a, _ = motions
    ref = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    chunks = sorted(tmp_path.glob("chunk-*.npz"))
    sums = json.loads((tmp_path / store.MANIFEST).read_text())["chunks"]
    assert len(sums) == len(chunks) > 1 and not (tmp_path / store.JOURNAL).exists()
    with np.load(chunks[0]) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["overturned"] = ~arrays["overturned"]  # every outcome the other way
    np.savez(chunks[0], **arrays)
    resumed = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    assert resumed.attrs["chunks_loaded"] == len(chunks) - 1
    assert resumed.attrs["chunks_computed"] == 1
    xr.testing.assert_identical(_science(resumed), _science(ref))


def test_a_damaged_chunk_manifest_is_rebuilt_from_the_chunks(motions, tmp_path):
    # The defect (issue 48): a damaged chunks.json stopped every rerun ("cannot read
    # .../chunks.json (Expecting value ...)") with no way out. It is rebuilt from the chunk files
    # of this run (their fingerprints), with a warning, and the run resumes.
    a, b = motions
    ref = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    n = len(list(tmp_path.glob("chunk-*.npz")))
    (tmp_path / store.MANIFEST).write_text("")
    with pytest.warns(UserWarning, match="chunks.json is damaged .*rebuilt from the chunk"):
        resumed = overturning_probability(BLOCKS, a, AGX, out=tmp_path, chunk_size=8)
    assert resumed.attrs["chunks_loaded"] == n and resumed.attrs["chunks_computed"] == 0
    xr.testing.assert_identical(_science(resumed), _science(ref))
    assert len(json.loads((tmp_path / store.MANIFEST).read_text())["chunks"]) == n
    # the rebuilt manifest still tells another run
    with pytest.raises(InputError, match="different run"):
        overturning_probability(BLOCKS, b, AGX, out=tmp_path, chunk_size=8)
