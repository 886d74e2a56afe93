"""The batched kernel before and after a change: two checkouts, timed in alternated processes.

Run from the repository root, with the project's environment, after checking out the commit
"before" in a second worktree (``git worktree add ../before COMMIT``):

    python benchmarks/before_after.py --before ../before --after . --key NAME

Each checkout is measured by its own ``benchmarks/run.py`` (its workload, kernel arguments, plain
loop and interleaved pairs: ``rocking_workload``, ``kernel_args``, ``plain_calls``, ``paired``),
in a child process that imports that checkout's package (``PYTHONPATH`` its ``src``; the same
dependencies) with a cache of compiled code of its own per checkout and instruction set.  The
processes alternate, before, after, before, after, ``--processes`` times each per instruction
set; in each, the kernel on all Numba threads and the parallel plain loop are timed in
``--pairs`` interleaved pairs.  The plain loop is the same code in both checkouts, so the ratio of
the kernel's time to the plain loop's in the same process cancels most of the load of a shared
host; that ratio's medians are compared (after / before: 1 is unchanged).  Each process also
gives the SHA-256 of the kernel's flags and peaks (``results_sha256``, as in ``run.py``): equal
digests, bit-identical results.  The entry goes to ``--out`` (default ``benchmarks/results.json``)
under ``--key``, beside the entries of ``run.py``; ``--add`` adds another round's processes to
those of the entry (same commits and settings) and gives the medians over all.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def child(tree: Path, n_motions: int, pairs: int) -> dict:
    """In this process: ``tree``'s package and benchmark functions; the digests and ``pairs``
    interleaved pairs of the kernel (all threads) and the parallel plain loop."""
    sys.path.insert(0, str(tree / "benchmarks"))
    import numba

    import rocking
    import run

    if not Path(rocking.__file__).resolve().is_relative_to(tree.resolve()):
        raise SystemExit(f"rocking imported from {rocking.__file__}, not from {tree}")
    w = run.rocking_workload(n_motions)
    args = run.kernel_args(w)
    table, acc, amax = args[:3]
    n = w["body"].size
    plain = run.plain_calls(w)
    run.run_cases(table, acc, amax, run.DT, w["body"][:200], w["motion"][:200], w["scale"][:200])
    plain("parallel", 50)  # compile / load
    out = run.run_cases(*args)
    # the kernel's outcome: an Outcome record since issue 44, a tuple before
    overturned, peak = (
        (out.overturned, out.peak_theta_ratio) if hasattr(out, "overturned") else out[:2]
    )
    p = run.paired(lambda: run.run_cases(*args), lambda: plain("parallel", n), pairs)
    kernel_vs_plain = [f / s for f, s in zip(p["fast_s"], p["slow_s"])]
    return {
        "vector_registers": run.vector_registers(),
        "threads": numba.get_num_threads(),
        "cases": int(n),
        "motions_sha256": run.digest(acc),
        "results_sha256": run.digest(overturned, peak),
        "kernel_s": p["fast_s"],
        "plain_loop_s": p["slow_s"],
        "kernel_vs_plain_loop": kernel_vs_plain,
        "median_kernel_vs_plain_loop": statistics.median(kernel_vs_plain),
    }


def commit(tree: Path) -> str:
    return subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=tree, capture_output=True, text=True
    ).stdout.strip()


def measure(a, isa: str, machine: dict, cache_root: Path) -> tuple[dict | str, dict]:
    """Alternated processes of the two checkouts on ``isa``: what Numba compiled for and, per
    checkout, the processes' results."""
    sys.path.insert(0, str(HERE))
    import run

    settings = run.ISAS[isa]
    if isa == "native" and "avx512f" in machine["simd"]:
        settings = run.FULL_WIDTH
    trees = {"before": Path(a.before).resolve(), "after": Path(a.after).resolve()}
    per: dict = {label: [] for label in trees}
    for i in range(a.processes):
        for label, tree in trees.items():
            cache = cache_root / f"{label}-{isa}"
            env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CPU_")}
            env.update(settings)
            env.update(PYTHONPATH=str(tree / "src"))
            env.update(ROCKING_CACHE_DIR=str(cache), NUMBA_CACHE_DIR=str(cache))
            with tempfile.NamedTemporaryFile(suffix=".json") as part:
                cmd = [sys.executable, __file__, "--child", str(tree), "--out", part.name]
                cmd += ["--motions", str(a.motions), "--pairs", str(a.pairs)]
                load_before = run.load()
                subprocess.run(cmd, env=env, check=True)
                res = json.loads(Path(part.name).read_text())
            res["load_at_start"] = load_before
            per[label].append(res)
            print(
                f"{isa} {label} {i + 1}/{a.processes}: kernel / plain loop "
                f"{res['median_kernel_vs_plain_loop']:.4f}, load {load_before}",
                flush=True,
            )
    return settings or "host", per


def summary(numba_cpu: dict | str, per: dict) -> dict:
    """The processes ``per`` checkout and their medians: of each process's median kernel /
    plain loop ratio, and of all its pairs (pooled)."""
    medians = {
        label: statistics.median(r["median_kernel_vs_plain_loop"] for r in runs)
        for label, runs in per.items()
    }
    pooled = {
        label: statistics.median(x for r in runs for x in r["kernel_vs_plain_loop"])
        for label, runs in per.items()
    }
    digests = {r["results_sha256"] for runs in per.values() for r in runs}
    return {
        "numba_cpu": numba_cpu,
        "processes": per,
        "median_kernel_vs_plain_loop": medians,
        "pooled_median_kernel_vs_plain_loop": pooled,
        "median_kernel_s": {
            label: statistics.median(t for r in runs for t in r["kernel_s"])
            for label, runs in per.items()
        },
        "after_vs_before": medians["after"] / medians["before"],
        "pooled_after_vs_before": pooled["after"] / pooled["before"],
        "bit_identical": len(digests) == 1,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", help="checkout of the commit before the change")
    ap.add_argument("--after", default=".", help="checkout after the change (default: here)")
    ap.add_argument("--key", help="key of the entry in --out")
    ap.add_argument("--isa", default="native,avx2", help="instruction sets, as run.py's --isa")
    ap.add_argument("--processes", type=int, default=4, help="processes per checkout and ISA")
    ap.add_argument("--pairs", type=int, default=5, help="kernel / plain loop pairs per process")
    ap.add_argument("--motions", type=int, default=100, help="motions of the workload (run.py's)")
    ap.add_argument("--out", default=str(HERE / "results.json"))
    ap.add_argument(
        "--add",
        action="store_true",
        help="add the processes to those of --key (same commits and settings): another round",
    )
    ap.add_argument("--child", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        Path(a.out).write_text(json.dumps(child(Path(a.child), a.motions, a.pairs)) + "\n")
        return 0
    if not (a.before and a.key):
        ap.error("--before and --key are needed")
    sys.path.insert(0, str(HERE))
    import run

    machine = run.machine_info()
    # the checkout this script runs from; the commits measured are those of --before and --after
    machine["driver_commit"] = machine.pop("rocking_commit")
    isas = [x.strip() for x in a.isa.split(",") if x.strip()]
    if "avx512f" not in machine["simd"] and "native" in isas and "avx2" in isas:
        isas.remove("avx2")  # the native run is the AVX2 run on this machine
    commits = {"before": commit(Path(a.before)), "after": commit(Path(a.after))}
    settings = {"motions": a.motions, "pairs": a.pairs}
    out = Path(a.out)
    old = run.read_previous(out)
    entry = old.get(a.key, {}) if a.add else {}
    if entry and (entry["commits"] != commits or entry["settings"] != settings):
        raise SystemExit(f"--add: {a.key} in {out} holds other commits or settings")
    entry = entry or {"commits": commits, "settings": settings, "rounds": [], "isas": {}}
    this = {"machine": machine, "processes": a.processes, "load_at_start": run.load()}
    with tempfile.TemporaryDirectory(prefix="rocking-before-after-") as tmp:
        measured = {isa: measure(a, isa, machine, Path(tmp)) for isa in isas}
    this["load_at_end"] = run.load()
    entry["rounds"].append(this)
    for isa, (numba_cpu, per) in measured.items():
        kept = entry["isas"].get(isa, {}).get("processes", {label: [] for label in per})
        entry["isas"][isa] = summary(numba_cpu, {k: kept[k] + v for k, v in per.items()})
    old[a.key] = entry
    out.write_text(json.dumps(old, indent=2, default=float) + "\n")
    for isa, r in entry["isas"].items():
        m = r["median_kernel_vs_plain_loop"]
        print(
            f"{isa}: kernel / plain loop, median before {m['before']:.4f}, after "
            f"{m['after']:.4f}: after / before {r['after_vs_before']:.3f}; bit-identical "
            f"{r['bit_identical']}"
        )
    print(f"written {out} [{a.key}]")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
