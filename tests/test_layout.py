"""The layout shows the design (issue 15): no module takes a private name from outside its own
subpackage, and the layers import downwards only (kernels ← models ← studies/CLI)."""

from __future__ import annotations

import ast
from pathlib import Path

import rocking

ROOT = Path(rocking.__file__).parent
#: Layers, lowest first: a module may import from its own layer and the layers below it.
LAYERS = [
    {"defaults", "errors", "core"},
    {"dynamics"},
    {"motions"},
    {"structures"},
    {"montecarlo"},
    {"assessment"},
    {"plots", "report"},
    {"studies"},
    {"cli"},
]


def _modules():
    for path in sorted(ROOT.rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        yield path, ("rocking", *parts)


def _imports(path: Path, module: tuple[str, ...]):
    """(imported module, imported names) of every import in ``path``, modules as tuples."""
    is_pkg = path.name == "__init__.py"
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = module if is_pkg else module[:-1]
                base = base[: len(base) - (node.level - 1)]
                target = base + (tuple(node.module.split(".")) if node.module else ())
            else:
                target = tuple(node.module.split("."))
            yield target, [a.name for a in node.names], node.lineno
        elif isinstance(node, ast.Import):
            for a in node.names:
                yield tuple(a.name.split(".")), [], node.lineno


def _unit(module: tuple[str, ...]) -> str:
    """The subpackage (or top-level module) a module of the package belongs to."""
    return module[1] if len(module) > 1 else ""


def test_no_private_name_crosses_a_subpackage():
    bad = []
    for path, module in _modules():
        for target, names, line in _imports(path, module):
            if target[0] != "rocking" or _unit(target) == _unit(module):
                continue
            private = [p for p in target[1:] if p.startswith("_") and p != "__init__"]
            private += [n for n in names if n.startswith("_")]
            if private:
                bad.append(
                    f"{path.relative_to(ROOT)}:{line} imports {', '.join(private)} "
                    f"from {'.'.join(target)}"
                )
    assert not bad, "\n".join(bad)


def test_layers_import_downwards():
    layer = {name: i for i, names in enumerate(LAYERS) for name in names}
    bad = []
    for path, module in _modules():
        here = layer.get(_unit(module))
        if here is None:
            continue  # the package's own __init__ (the lazy public API)
        for target, _names, line in _imports(path, module):
            if target[0] != "rocking" or len(target) < 2:
                continue
            there = layer.get(target[1])
            if there is not None and there > here:
                bad.append(
                    f"{path.relative_to(ROOT)}:{line} ({LAYERS[here]}) imports "
                    f"{'.'.join(target)} ({LAYERS[there]})"
                )
    assert not bad, "\n".join(bad)


def test_no_module_imports_the_package_root():
    # Issue 44: `from .. import __version__` in core/runs.py and montecarlo/store.py was an
    # arrow back up to the package root (which serves the whole public API): modules import
    # the module that defines a name (the version: rocking.core.version)
    bad = []
    for path, module in _modules():
        if module == ("rocking",):
            continue
        for target, names, line in _imports(path, module):
            if target == ("rocking",):
                bad.append(
                    f"{path.relative_to(ROOT)}:{line} imports {', '.join(names)} from rocking"
                )
    assert not bad, "\n".join(bad)


def test_subpackages_re_export_their_public_names():
    # The codebase's rule: `from rocking.motions import generate` works as `from rocking import
    # generate` does, and gives the same object, for every public name of every subpackage.
    import importlib

    from rocking.core.exports import PUBLIC

    served = set()
    for name, module in PUBLIC.items():
        package = importlib.import_module("rocking." + module.split(".")[0])
        if not hasattr(package, "__path__"):  # rocking.errors, rocking.report: modules
            continue
        if module.split(".")[1:] == [name]:  # rocking.dynamics.simulate is the module
            assert name not in package.__all__
            continue
        assert getattr(package, name) is getattr(rocking, name), name
        assert module == "studies" or name in package.__all__  # studies defines reproduce
        served.add(name)
    assert {"generate", "Block", "overturning_probability", "provenance"} <= served
    assert sorted(rocking.__all__) == sorted(PUBLIC)


#: Import circles inside a subpackage still to be broken, listed so that a new circle fails the
#: test below (issue 44's ``motions/ensemble.py`` ↔ ``motions/synthesis.py`` is broken:
#: ``regenerate`` lives in synthesis.py).
KNOWN_CIRCLES: set[frozenset[str]] = set()


def _circles(edges: dict[str, set[str]]) -> list[frozenset[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[frozenset[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                part.append(w)
                if w == v:
                    break
            if len(part) > 1:
                found.append(frozenset(part))

    for v in list(edges):
        if v not in index:
            visit(v)
    return found


def _edges() -> dict[str, set[str]]:
    """Imports between modules of the same subpackage (its ``__init__`` left out)."""
    modules = {".".join(m) for _p, m in _modules()}
    edges: dict[str, set[str]] = {}
    for path, module in _modules():
        if path.name == "__init__.py" or len(module) < 3:
            continue
        for target, names, _line in _imports(path, module):
            if target[0] != "rocking" or len(target) < 2 or _unit(target) != _unit(module):
                continue
            candidates = [".".join((*target, n)) for n in names] + [".".join(target)]
            for name in candidates:
                if name in modules and name != ".".join(module) and name.count(".") >= 2:
                    edges.setdefault(".".join(module), set()).add(name)
                    break
    return edges


def test_no_new_import_circle_inside_a_subpackage():
    assert set(_circles(_edges())) <= KNOWN_CIRCLES, _circles(_edges())


def test_the_circle_check_can_fail():
    assert _circles({"a.b.c": {"a.b.d"}, "a.b.d": {"a.b.c"}, "a.b.e": {"a.b.c"}}) == [
        frozenset({"a.b.c", "a.b.d"})
    ]
    # the known ones are seen (a circle broken leaves KNOWN_CIRCLES: remove it there)
    assert set(_circles(_edges())) == KNOWN_CIRCLES


def test_the_architecture_lists_every_module():
    # docs/architecture.md names every module of the package (by its file name in the section
    # of its subpackage, or with its folder)
    text = (ROOT.parent.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    missing = [
        str(path.relative_to(ROOT))
        for path, _module in _modules()
        if f"`{path.name}`" not in text and f"{path.relative_to(ROOT)}" not in text
    ]
    assert not missing, missing


#: Public functions allowed more than MAX_PARAMETERS parameters, each with its reason (a
#: function listed here that comes down to the limit fails the test below: remove it here).
MANY_PARAMETERS: dict[str, str] = {}
#: Issue 44, part 4: with the records (Physics, Compute, Agx50Search, Synthesis, SpectrumScan;
#: the option groups of the command line) no public function needs more.
MAX_PARAMETERS = 10


def _parameter_counts(source: str, where: str) -> dict[str, int]:
    """Parameters of every public function of ``source`` (module-level functions, click
    command callbacks included, and the methods and constructors of public classes; ``self``
    and ``cls`` not counted, ``*args`` and ``**kwargs`` one each), by ``where:name``."""
    counts: dict[str, int] = {}

    def visit(body, owner: str = "") -> None:
        for node in body:
            if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                visit(node.body, f"{owner}{node.name}.")
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if node.name.startswith("_") and not (owner and node.name == "__init__"):
                    continue
                a = node.args
                names = [p.arg for p in (*a.posonlyargs, *a.args, *a.kwonlyargs)]
                if owner and names[:1] in (["self"], ["cls"]):
                    names = names[1:]
                counts[f"{where}:{owner}{node.name}"] = (
                    len(names) + (a.vararg is not None) + (a.kwarg is not None)
                )

    visit(ast.parse(source).body)
    return counts


def test_no_public_function_takes_more_than_ten_parameters():
    counts: dict[str, int] = {}
    for path, _module in _modules():
        counts.update(_parameter_counts(path.read_text(), str(path.relative_to(ROOT))))
    assert len(counts) > 500  # every module was read
    over = {name: n for name, n in counts.items() if n > MAX_PARAMETERS}
    assert set(over) <= set(MANY_PARAMETERS), {k: over[k] for k in set(over) - set(MANY_PARAMETERS)}
    assert set(MANY_PARAMETERS) <= set(over), set(MANY_PARAMETERS) - set(over)  # none stale


def test_the_parameter_count_can_fail():
    source = (
        "def f(a, b=1, *c, d, **e): pass\n"
        "def _private(a, b, c, d, e, f, g, h, i, j, k): pass\n"
        "class C:\n"
        "    def __init__(self, a, b): pass\n"
        "    @classmethod\n"
        "    def make(cls, a): pass\n"
        "    def _hidden(self, a): pass\n"
        "class _D:\n"
        "    def method(self, a): pass\n"
    )
    assert _parameter_counts(source, "m.py") == {
        "m.py:f": 5,
        "m.py:C.__init__": 2,
        "m.py:C.make": 1,
    }
