"""The documentation names only what exists: every ``rocking.…`` name written in the README, the
documentation pages and the gallery, and every name their Python code imports from ``rocking``,
is a real module, function, class or attribute. A rename or a move in the package (as the
subpackages of issue 15 did to ``rocking.records``) then fails here instead of leaving a
tutorial that no longer runs. (The gallery scripts themselves are run by the documentation
build; the tutorials' snippets were run when written.)
"""

from __future__ import annotations

import ast
import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: Pages whose text and Python code blocks are checked.
PAGES = sorted(
    [ROOT / "README.md", *(ROOT / "docs").rglob("*.md"), *(ROOT / "docs").rglob("*.rst")]
)
PAGES = [p for p in PAGES if not {"_build", "generated", "auto_examples"} & set(p.parts)]
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))
#: A dotted name starting with the package, as prose and tables write it (`rocking.simulate`).
_NAME = re.compile(r"(?<![\w./-])rocking(?:\.[A-Za-z_]\w*)+")
_PYTHON_BLOCK = re.compile(r"```python\n(.*?)```", re.S)


def resolve(dotted: str) -> object:
    """The object a dotted name ``rocking.a.b.c`` stands for: the longest importable module
    prefix, then attributes. Raises ImportError or AttributeError if there is none."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(dotted)


def _code_names(code: str) -> set[str]:
    """Dotted names of ``rocking`` that Python code imports or uses as attributes."""
    names = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("rocking"):
            names |= {f"{node.module}.{a.name}" for a in node.names}
        elif isinstance(node, ast.Import):
            names |= {a.name for a in node.names if a.name.startswith("rocking")}
        elif isinstance(node, ast.Attribute):
            chain = []
            inner: ast.expr = node
            while isinstance(inner, ast.Attribute):
                chain.append(inner.attr)
                inner = inner.value
            if isinstance(inner, ast.Name) and inner.id == "rocking":
                names.add(".".join(["rocking", *reversed(chain)]))
    return names


def _names(path: Path) -> set[str]:
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".py":
        return _code_names(text)
    names = {m.group(0) for m in _NAME.finditer(text)}
    for block in _PYTHON_BLOCK.findall(text):
        names |= _code_names(block)
    return names


@pytest.mark.parametrize("path", PAGES + EXAMPLES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_rocking_name_in_the_documentation_exists(path):
    missing = []
    for name in sorted(_names(path)):
        try:
            resolve(name)
        except (ImportError, AttributeError) as exc:
            missing.append(f"{name} ({type(exc).__name__}: {exc})")
    assert not missing, f"{path.relative_to(ROOT)} names what does not exist:\n" + "\n".join(
        missing
    )


def test_the_name_check_can_fail():
    # the check above must see names in prose, in imports and in attribute chains, and must
    # refuse a name that does not exist (the README once named rocking.records, gone since the
    # subpackages of issue 15)
    found = _code_names(
        "import rocking\nfrom rocking.motions.records import read_record\n"
        "x = rocking.Block.from_dimensions(1, 2)\n"
    )
    assert found == {
        "rocking",
        "rocking.motions.records.read_record",
        "rocking.Block.from_dimensions",
        "rocking.Block",
    }
    prose = "see `rocking.records.example_record_path()` and rocking.simulate."
    assert {m.group(0) for m in _NAME.finditer(prose)} == {
        "rocking.records.example_record_path",
        "rocking.simulate",
    }
    with pytest.raises((ImportError, AttributeError)):
        resolve("rocking.records.example_record_path")
    assert resolve("rocking.motions.records.example_record_path").__name__ == (
        "example_record_path"
    )


def test_every_python_block_of_the_documentation_parses():
    bad = []
    for path in PAGES:
        for k, block in enumerate(_PYTHON_BLOCK.findall(path.read_text(encoding="utf-8"))):
            try:
                ast.parse(block)
            except SyntaxError as exc:
                bad.append(f"{path.relative_to(ROOT)} block {k + 1}: {exc}")
    assert not bad, "\n".join(bad)
