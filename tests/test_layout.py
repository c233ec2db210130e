"""The package layout: the old import paths of moved modules still work, warn naming the new path
and are the very new modules; importing the package and every module of it warns about nothing
(so nothing in the project imports an old path)."""

import importlib
import importlib.util
import re
import subprocess
import sys

import pytest

import geofeas

#: old path -> (new path, third-party modules the new one needs)
MOVED = {
    "geofeas.decisions": ("geofeas.association.decisions", []),
    "geofeas.ais": ("geofeas.io.ais", ["pandas"]),
    "geofeas.arrow": ("geofeas.io.arrow", []),
    "geofeas.dask": ("geofeas.integrations.dask", ["pandas", "dask.dataframe"]),
    "geofeas.stonesoup": ("geofeas.integrations.stonesoup", ["pandas", "stonesoup"]),
    "geofeas.scenario": ("geofeas.demo.scenario", ["pandas"]),
    "geofeas.evaluate": ("geofeas.demo.evaluate", ["pandas"]),
}


def _forget(monkeypatch, old):
    """Make the next import of ``old`` run its module again (it is cached once imported)."""
    monkeypatch.delitem(sys.modules, old, raising=False)
    monkeypatch.delattr(geofeas, old.rpartition(".")[2], raising=False)


def _public(module):
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in vars(module) if not n.startswith("__")]
    return list(names)


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_path_warns_and_is_the_new_module(old, monkeypatch):
    new, needs = MOVED[old]
    for name in needs:
        pytest.importorskip(name)
    moved = importlib.import_module(new)
    _forget(monkeypatch, old)
    with pytest.warns(DeprecationWarning, match=rf"{re.escape(old)} moved to {re.escape(new)}$"):
        shim = importlib.import_module(old)
    assert shim is moved
    assert sys.modules[old] is moved
    # `import geofeas.x; geofeas.x.name` reaches the new module too
    assert getattr(geofeas, old.rpartition(".")[2]) is moved
    names = [n for n in vars(moved) if not n.startswith("__")]
    assert names
    for name in names:
        assert getattr(shim, name) is getattr(moved, name), name


@pytest.mark.parametrize("old", sorted(MOVED))
def test_old_path_import_forms(old, monkeypatch):
    """``from geofeas.x import name`` and ``import geofeas.x as m`` give the new objects."""
    new, needs = MOVED[old]
    for name in needs:
        pytest.importorskip(name)
    moved = importlib.import_module(new)
    public = _public(moved)
    assert public
    _forget(monkeypatch, old)
    ns: dict = {}
    with pytest.warns(DeprecationWarning, match=re.escape(new)):
        exec(f"import {old} as m\nfrom {old} import {', '.join(public)}", ns)
    assert ns["m"] is moved
    for name in public:
        assert ns[name] is getattr(moved, name), name


def test_old_paths_warn_in_a_fresh_interpreter():
    """The same without anything imported before: each old path, first imported, warns (and
    its names are those of the new module)."""
    code = "\n".join(
        [
            "import importlib, sys, warnings",
            "old, new = sys.argv[1], sys.argv[2]",
            "with warnings.catch_warnings(record=True) as caught:",
            "    warnings.simplefilter('always')",
            "    shim = importlib.import_module(old)",
            "messages = [str(w.message) for w in caught if w.category is DeprecationWarning]",
            "assert f'{old} moved to {new}' in messages, messages",
            "moved = importlib.import_module(new)",
            "assert shim is moved",
            "assert all(getattr(shim, n) is getattr(moved, n) for n in vars(moved))",
        ]
    )
    for old, (new, needs) in MOVED.items():
        if any(importlib.util.find_spec(n.partition(".")[0]) is None for n in needs):
            continue
        run = subprocess.run(
            [sys.executable, "-c", code, old, new], capture_output=True, text=True, timeout=300
        )
        assert run.returncode == 0, (old, run.stderr)


def _python_without_deprecations(code: str) -> None:
    """Runs ``code`` in a fresh interpreter where a DeprecationWarning is an error; fails with its
    stderr unless it exits 0."""
    run = subprocess.run(
        [sys.executable, "-W", "error::DeprecationWarning", "-c", code],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr


def test_the_package_imports_no_old_path():
    """``geofeas``, its subpackages and every module of them import without a single
    DeprecationWarning: nothing in the project itself uses a moved path."""
    old = sorted(MOVED)
    code = "\n".join(
        [
            "import importlib, pkgutil, sys",
            "import geofeas",
            f"old = set({old!r})",
            "names = [m.name for m in pkgutil.walk_packages(geofeas.__path__, 'geofeas.')",
            "         if m.name not in old and not m.name.endswith('__main__')]",
            "for n in ['geofeas.association', 'geofeas.io', 'geofeas.integrations']:",
            "    assert n in names, n",
            "for n in names:",
            "    importlib.import_module(n)",
            "assert not old & set(sys.modules), old & set(sys.modules)",
        ]
    )
    _python_without_deprecations(code)


def test_new_subpackages_import_nothing_optional():
    """The ``io`` and ``integrations`` packages import none of their modules: each module needs
    its own extra, so importing the package must not fail when one is missing."""
    code = "\n".join(
        [
            "import sys",
            "import geofeas.io, geofeas.integrations",
            "loaded = [m for m in ('geofeas.io.ais', 'geofeas.io.arrow',",
            "          'geofeas.integrations.dask', 'geofeas.integrations.stonesoup')",
            "          if m in sys.modules]",
            "assert not loaded, loaded",
            "assert 'dask' not in sys.modules and 'stonesoup' not in sys.modules",
        ]
    )
    _python_without_deprecations(code)


#: the layers of ARCHITECTURE.md, each with the layers it must not import
CORE = ["geofeas", "geofeas.scores", "geofeas.association"]
LIBRARY = ["geofeas.io", "geofeas.integrations", "geofeas.tracking"]
APPLICATION = ["geofeas.cli", "geofeas.demo", "geofeas.review"]


@pytest.mark.parametrize(
    "layer, forbidden",
    [(CORE, LIBRARY[:2] + APPLICATION), (CORE + LIBRARY, APPLICATION)],
    ids=["core", "library"],
)
def test_imports_point_down_the_layers(layer, forbidden):
    """Every module of a layer, imported in a fresh interpreter, loads nothing of the layers
    above it: the core no io or integrations, no library module the application."""
    code = "\n".join(
        [
            "import importlib, pkgutil, sys",
            f"layer, forbidden = {layer!r}, {forbidden!r}",
            "old = {" + ", ".join(repr(o) for o in MOVED) + "}",
            "names = []",
            "for top in layer:",
            "    package = importlib.import_module(top)",
            "    names.append(top)",
            "    if top != 'geofeas' and hasattr(package, '__path__'):",
            "        names += [m.name for m in pkgutil.walk_packages(package.__path__, top + '.')]",
            "for name in names:",
            "    if name not in old:",
            "        importlib.import_module(name)",
            "bad = sorted(m for m in sys.modules for f in forbidden",
            "             if m == f or m.startswith(f + '.'))",
            "assert not bad, bad",
        ]
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
