"""The README's commands run exactly as printed, top to bottom in one folder (issue 48): those
of the table ("What it does"), then those of its shell blocks (```sh; commands on the user's
own files, which the repository does not hold, are in ```text blocks).

They run in one empty folder, each after the commands printed above it that write a file it
reads (motions.nc, spectrum.csv, floors.csv), through the installed ``rocking`` entry point
(``python -m rocking.cli`` where it is not installed); each must exit with status 0 and leave
the files its options name.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: Commands that write a report say so in the README ("writes screen-out/report.html").
_REPORTS = {"screen", "reproduce", "pulse-spectrum"}


def readme_commands() -> list[str]:
    """Every `rocking ...` command in the command column of the table under "What it does",
    then every `rocking ...` line of the README's shell blocks (continued lines joined, a
    trailing comment dropped), in the order printed."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("\n## What it does\n", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| ")]
    commands = []
    for row in rows[1:]:  # the first row is the header
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]]
        commands += re.findall(r"`(rocking [^`]*)`", cells[1])
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        for line in block.replace("\\\n", " ").splitlines():
            if line.startswith("rocking "):
                commands.append(shlex.join(shlex.split(line, comments=True)))
    return commands


def _entry_point() -> list[str]:
    exe = shutil.which("rocking", path=os.path.dirname(sys.executable))
    return [exe] if exe else [sys.executable, "-m", "rocking.cli"]


def _outputs(args: list[str]) -> list[str]:
    """Paths named by --out, --plot and --csv."""
    return [args[i + 1] for i, a in enumerate(args[:-1]) if a in ("--out", "--plot", "--csv")]


def test_readme_table_lists_runnable_commands():
    commands = readme_commands()
    assert len(commands) >= 12, commands
    # as printed: no placeholders or alternatives a shell would not take literally
    for command in commands:
        assert not re.search(r"\\\||\.\.\.|[A-Z]{3,}(?![=:\w])", command), command


def _run(command: str, folder: Path) -> None:
    args = shlex.split(command)[1:]
    proc = subprocess.run(
        [*_entry_point(), *args],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=600,
        stdin=subprocess.DEVNULL,
    )
    assert proc.returncode == 0, f"{command}\n{proc.stdout}\n{proc.stderr}"
    for name in _outputs(args):
        path = folder / name
        if path.suffix:
            assert path.is_file() and path.stat().st_size > 0, f"{command}: no {name}"
        else:
            assert path.is_dir() and any(path.iterdir()), f"{command}: {name} is empty"
            if args[0] in _REPORTS:
                assert (path / "report.html").is_file(), f"{command}: no report.html"


def _run_after(futures, command: str, folder: Path) -> None:
    for future in futures:
        future.result()
    _run(command, folder)


def test_readme_commands_run_as_printed(tmp_path):
    # Two at a time (most of a command's time is Python starting and importing), each after
    # the earlier commands that write a file it reads (FILE or FILE:NAME among its arguments).
    commands = readme_commands()
    written = [_outputs(shlex.split(c)) for c in commands]
    with ThreadPoolExecutor(max_workers=2) as pool:
        done = []
        for i, command in enumerate(commands):
            args = shlex.split(command)
            needs = [
                done[j]
                for j in range(i)
                for out in written[j]
                if any(a == out or a.startswith(f"{out}:") for a in args)
            ]
            done.append(pool.submit(_run_after, needs, command, tmp_path))
        for future in done:
            future.result()
