"""Rules about the repository itself: nothing names a path outside it, and the data the package
needs is installed with it."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: An absolute path into one of a machine's top-level folders (work, home, Users, tmp, ...), a
#: Windows user folder, or a relative path out of the repository to the sibling folder "shared".
#: Written as patterns (and the examples below in pieces) so that this file does not match itself.
_OUTSIDE = re.compile(
    r"(?<![\w.~-])/(work|home|Users|root|tmp|mnt|opt|srv|scratch|shared|data)/"
    r"|\.\./shared|\b[A-Za-z]:\\(Users|work|data)\b"
)


def _text_files(folder: Path):
    for path in sorted(folder.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and ".hypothesis" not in path.parts:
            data = path.read_bytes()
            if b"\0" not in data:  # text only (figures and other binaries cannot name paths)
                yield path, data.decode("utf-8", errors="replace")


def test_no_file_names_a_path_outside_the_repository():
    found = [
        f"{path.relative_to(ROOT)}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)}"
        for folder in (ROOT / "src", ROOT / "tests", ROOT / "examples", ROOT / "docs")
        for path, text in _text_files(folder)
        if not {"_build", "generated", "auto_examples"} & set(path.relative_to(folder).parts)
        for m in _OUTSIDE.finditer(text)
    ]
    assert not found, "paths outside the repository:\n" + "\n".join(found)


def test_outside_pattern_catches_what_it_must():
    # The guard above must be able to fail: each of these would break a fresh clone.
    s, b = "/", chr(92)  # the separators, so that these lines do not match the guard
    for bad in (
        f'RECORDS = "{s}work{s}shared{s}records"',
        f"open('{s}home{s}me{s}x.csv')",
        f'Path("..{s}shared{s}records")',
        f'"C:{b}Users{b}me{b}x.AT2"',
        f"{s}tmp{s}run{s}out.nc",
    ):
        assert _OUTSIDE.search(bad), bad
    for fine in (
        "src/rocking/data/records/x.AT2",
        "tests/data/x.AT2",
        "https://x.org/data/x",
        "m/s/s",
        "cm/s",
        "1/400 s",
    ):
        assert not _OUTSIDE.search(fine), fine


def test_package_data_globs_cover_every_data_file():
    # A non-editable install ships only what pyproject's package-data names: every file under
    # src/rocking/data (the example record, inventory, spectrum, bodies, the paper's values)
    # must be matched by one of its globs, or `pip install .` would leave it behind.
    globs = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"][
        "package-data"
    ]["rocking"]
    package = ROOT / "src" / "rocking"
    shipped = {p for pattern in globs for p in package.glob(pattern) if p.is_file()}
    data = {p for p in (package / "data").rglob("*") if p.is_file()}
    assert data and not data - shipped, sorted(str(p.relative_to(package)) for p in data - shipped)


def test_ci_runs_the_readme_test_command_as_printed():
    # .ci/run may check more before the tests (lint, types, documentation), never run less:
    # the README's test command must be in it verbatim, as a command line of its own
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("**Set up and run the tests**", 1)[1]
    command = section.split("```sh\n", 1)[1].split("\n```", 1)[0].strip()
    assert "pytest" in command, command
    lines = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    assert any(line == command or line.startswith(command + " ||") for line in lines), command
