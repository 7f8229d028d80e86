"""The shape of the code (docs/architecture.md), checked from the source text.

* Python: the static imports of ``python/sandlight`` point one way along ``LAYERS``, and the
  subpackages' module-level imports form no cycle. An import inside a function may break the
  layer rule only if ``LAZY_UPWARD`` lists it with a reason.
* Python: no module uses another module's private name (``from x import _y``, or ``x._y`` on an
  imported module); ``sandlight._native`` is the one private module every layer may use.
* Rust: the ``crate::``/``super::`` paths of ``crates/sandlight-core/src`` (test modules left
  out) form no cycle between the crate's top-level modules.

The test fails on any violation. Run this file as a script to print the import graphs and
every violation.
"""

from __future__ import annotations

import ast
import re
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGE_DIR = REPO / "python" / "sandlight"
RUST_SRC = REPO / "crates" / "sandlight-core" / "src"

#: The layers of the Python package, lowest first (docs/architecture.md). A unit is a top-level
#: module or subpackage of ``sandlight``; it may import units of its own layer or below. Units
#: planned but not yet written are declared too, so that they land in their layer.
LAYERS: tuple[tuple[str, frozenset[str]], ...] = (
    ("foundation", frozenset({"_native", "errors", "checks", "io", "machine", "_runner", "progress", "jobs", "plots"})),
    ("data", frozenset({"sample", "optics", "measured"})),
    ("physics", frozenset({"physics"})),
    ("measurement", frozenset({"engine", "gonio", "validation", "calibration"})),
    ("test support", frozenset({"testing"})),
    ("predictors", frozenset({"predictor", "spatial"})),
    # Retrieval runs the predictors and the engine backwards: spectrum → sample parameters.
    ("retrieval", frozenset({"retrieval"})),
    ("appearance", frozenset({"appearance"})),
    ("colour/render", frozenset({"colour", "sky", "render", "mitsuba"})),
    # The command line and the web explorer are the top layer; `sandlight serve` (cli) starts the
    # web application inside the command's function, and the web layer never imports the cli.
    ("cli/web", frozenset({"cli", "__main__", "web"})),
)
LAYER_OF = {unit: rank for rank, (_, units) in enumerate(LAYERS) for unit in units}
#: What may be imported from the package root (``sandlight/__init__.py``, the public facade,
#: which itself sits above every layer): the version, defined there from the package metadata.
ROOT_NAMES = frozenset({"__version__"})
#: Private modules every layer may use: the compiled extension.
SHARED_PRIVATE = frozenset({"sandlight._native"})

#: Imports inside functions that may point up the layers: (importer, imported module) → reason.
LAZY_UPWARD: dict[tuple[str, str], str] = {}


# --- Python ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Import:
    importer: str  # dotted module name
    target: str  # dotted module imported (for `from m import name`, m.name if it is a module)
    names: tuple[str, ...]  # names taken from `target` by `from … import`; () for `import`
    lazy: bool  # inside a function
    line: int


def module_names(package_dir: Path = PACKAGE_DIR) -> dict[str, Path]:
    """Dotted name → file of every module of the package (packages by their ``__init__``)."""
    names = {}
    for path in sorted(package_dir.rglob("*.py")):
        parts = list(path.relative_to(package_dir.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        names[".".join(parts)] = path
    names["sandlight._native"] = package_dir / "_native.pyi"  # the extension, by its stub
    return names


def _function_imports(tree: ast.AST) -> set[int]:
    inside = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            inside |= {id(n) for n in ast.walk(node) if isinstance(n, (ast.Import, ast.ImportFrom))}
    return inside


def _source(node: ast.ImportFrom, name: str, path: Path) -> str:
    """The absolute module of ``from … import`` in module ``name`` (file ``path``)."""
    if not node.level:
        return node.module or ""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    base = package.split(".")[: len(package.split(".")) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


def facade_names(modules: dict[str, Path]) -> dict[str, str]:
    """Names the package root re-exports → the module they come from (``sandlight/__init__.py``:
    its module-level ``from sandlight.x import …`` and the lazily loaded ``_NATIVE_API`` table)."""
    tree = ast.parse(modules["sandlight"].read_text(encoding="utf-8"))
    names = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("sandlight."):
            names |= {alias.asname or alias.name: node.module for alias in node.names}
        elif isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "_NATIVE_API" for t in node.targets):
            names |= ast.literal_eval(node.value)
    return names


def imports_of(name: str, path: Path, modules: dict[str, Path]) -> list[Import]:
    """Static imports of sandlight modules in module ``name`` (relative imports resolved; after
    ``import sandlight``, the attributes read on it)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    lazy = _function_imports(tree)
    # Attributes read on the name `sandlight` (after `import sandlight`): what a plain import uses.
    on_root = sorted(
        {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute) and getattr(n.value, "id", "") == "sandlight"}
    )
    found = []

    def take(source: str, attribute: str, node: ast.stmt) -> None:
        is_lazy, line = id(node) in lazy, node.lineno
        if f"{source}.{attribute}" in modules:
            found.append(Import(name, f"{source}.{attribute}", (), is_lazy, line))
        else:
            found.append(Import(name, source, (attribute,), is_lazy, line))

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "sandlight" and name != "sandlight":
                    for attribute in on_root:
                        take("sandlight", attribute, node)
                elif alias.name.split(".")[0] == "sandlight":
                    found.append(Import(name, alias.name, (), id(node) in lazy, node.lineno))
        elif isinstance(node, ast.ImportFrom):
            source = _source(node, name, path)
            if source.split(".")[0] == "sandlight":
                for alias in node.names:
                    take(source, alias.name, node)
    return found


def unit_of(module: str) -> str:
    """``sandlight.physics.medium`` → ``physics``; the package root → ``sandlight``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "sandlight"


def _private_owner(path: list[str]) -> str | None:
    """The dotted owner of the first private component of ``path`` (None if none is private)."""
    for i, part in enumerate(path):
        if part.startswith("_") and not (part.startswith("__") and part.endswith("__")):
            return ".".join(path[:i]) if ".".join(path[: i + 1]) not in SHARED_PRIVATE else None
    return None


def _may_use(importer: str, owner: str) -> bool:
    return importer == owner or importer.startswith(owner + ".")


def private_uses(name: str, path: Path, modules: dict[str, Path], imports: list[Import]) -> set[str]:
    """Private names of other modules that module ``name`` imports or reads as attributes."""
    found = set()
    for imp in imports:
        for full in [imp.target] + [f"{imp.target}.{n}" for n in imp.names]:
            owner = _private_owner(full.split("."))
            if owner is not None and not _may_use(name, owner):
                found.add(f"private: {name} uses {full}")
    # Names bound to sandlight modules: `import sandlight.x[ as y]`, `from sandlight import x`.
    tree = ast.parse(path.read_text(encoding="utf-8"))
    bound = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "sandlight":
                    bound[alias.asname or "sandlight"] = alias.name if alias.asname else "sandlight"
        elif isinstance(node, ast.ImportFrom):
            source = _source(node, name, path)
            for alias in node.names:
                if f"{source}.{alias.name}" in modules:
                    bound[alias.asname or alias.name] = f"{source}.{alias.name}"
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        chain, value = [node.attr], node.value
        while isinstance(value, ast.Attribute):
            chain.append(value.attr)
            value = value.value
        if isinstance(value, ast.Name) and value.id in bound:
            full = bound[value.id].split(".") + chain[::-1]
            owner = _private_owner(full)
            if owner is not None and not _may_use(name, owner):
                found.add(f"private: {name} uses {'.'.join(full)}")
    return found


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Components of ``graph`` that hold a cycle (Tarjan), each sorted."""
    index, low, stack, on_stack, out = {}, {}, [], set(), []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1 or v in graph.get(v, ()):
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out)


def python_graph(package_dir: Path = PACKAGE_DIR) -> tuple[dict[str, list[Import]], set[str]]:
    """Every module's sandlight imports, and every violation of the Python rules."""
    modules = module_names(package_dir)
    facade = facade_names(modules)
    imports = {name: imports_of(name, path, modules) for name, path in modules.items() if path.suffix == ".py"}
    violations = set()
    units = defaultdict(set)
    lazy_used = set()
    for name, found in imports.items():
        violations |= private_uses(name, modules[name], modules, found)
        source = unit_of(name)
        if source not in LAYER_OF and source != "sandlight":
            violations.add(f"layer: unit {source!r} is in no layer of LAYERS")
        for imp in found:
            target = unit_of(imp.target)
            if target == source:
                continue
            if not imp.lazy:
                units[source].add(target)
            if source == "sandlight":  # the facade re-exports from every layer
                continue
            if target == "sandlight":
                for extra in sorted(set(imp.names) - ROOT_NAMES):
                    home = f" (import it from {facade[extra]})" if extra in facade else ""
                    violations.add(f"layer: {name} uses sandlight.{extra} of the package root{home}")
                continue
            if LAYER_OF.get(target, -1) > LAYER_OF.get(source, -1):
                key = (name, imp.target)
                if imp.lazy and key in LAZY_UPWARD:
                    lazy_used.add(key)
                else:
                    where = "inside a function" if imp.lazy else "at module level"
                    violations.add(f"layer: {name} imports {imp.target} {where}")
    for key in set(LAZY_UPWARD) - lazy_used:
        violations.add(f"stale LAZY_UPWARD entry: {key}")
    for component in strongly_connected({u: t - {"sandlight"} for u, t in units.items() if u != "sandlight"}):
        violations.add("cycle(python): " + ", ".join(component))
    return imports, violations


# --- Rust --------------------------------------------------------------------------------------

# Comments, string literals (raw ones included) and char literals: blanked before paths are read.
_NOT_CODE = re.compile(r"""//[^\n]*|/\*.*?\*/|\bb?r(#*)".*?"\1|b?"(?:\\.|[^"\\])*"|'(?:\\.|[^'\\])'""", re.S)
_IDENT = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*|\{)")
_SEP = re.compile(r"\s*::")
_GROUP = re.compile(r"\s*([,}])")
_PATH_START = re.compile(r"\b(crate|super|self)\s*::")
_REEXPORT = re.compile(r"pub\s+use\s+([a-z_][a-z0-9_]*)::([A-Za-z_][A-Za-z0-9_]*)\s*;")


def rust_code(source: str) -> str:
    """Rust source without comments, literals and ``#[cfg(test)]`` items (test modules)."""
    code = _NOT_CODE.sub(" ", source)
    while (start := code.find("#[cfg(test)]")) >= 0:
        i = start + len("#[cfg(test)]")
        while i < len(code) and code[i] not in "{;":
            i += 1
        depth = 0
        while i < len(code):
            depth += {"{": 1, "}": -1}.get(code[i], 0)
            if depth == 0:
                break
            i += 1
        code = code[:start] + code[i + 1 :]
    return code


def rust_paths(code: str, start: int) -> list[list[str]]:
    """The paths of the ``use`` tree or path expression at ``code[start:]``, groups expanded."""

    def tree(i: int) -> tuple[list[list[str]], int]:
        prefix = []
        while m := _IDENT.match(code, i):
            if m.group(1) == "{":
                paths, i = [], m.end()
                while True:
                    sub, i = tree(i)
                    paths += [prefix + p for p in sub]
                    end = _GROUP.match(code, i)
                    if not end or end.group(1) == "}":
                        return paths, end.end() if end else i
                    i = end.end()
            prefix.append(m.group(1))
            if not (sep := _SEP.match(code, m.end())):
                return [prefix], m.end()
            i = sep.end()
        return [prefix], i

    return tree(start)[0]


def rust_module_path(path: Path, src: Path = RUST_SRC) -> list[str]:
    """``gonio/hemisphere.rs`` → [gonio, hemisphere]; ``gonio/mod.rs`` → [gonio]; lib.rs → []."""
    parts = list(path.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts.pop()
    return parts


def rust_graph(src: Path = RUST_SRC) -> tuple[dict[str, set[str]], set[str]]:
    """Top-level module → the top-level modules it uses, and the cycles among them."""
    top = {p.stem for p in src.glob("*.rs") if p.stem != "lib"} | {p.name for p in src.iterdir() if p.is_dir()}
    # `pub use error::SandlightError;` in lib.rs: a name at the crate root → the module it is from.
    reexports = {m.group(2): m.group(1) for m in _REEXPORT.finditer(rust_code((src / "lib.rs").read_text()))}
    graph = defaultdict(set)
    for path in sorted(src.rglob("*.rs")):
        here = rust_module_path(path, src)
        if not here:
            continue
        code = rust_code(path.read_text(encoding="utf-8"))
        for m in _PATH_START.finditer(code):
            for head, *rest in rust_paths(code, m.start()):
                if head == "crate":
                    absolute = rest
                elif head == "self":
                    absolute = here + rest
                else:  # super, possibly repeated
                    up = 1
                    while rest and rest[0] == "super":
                        up, rest = up + 1, rest[1:]
                    absolute = here[: len(here) - up] + rest
                if absolute:
                    unit = reexports.get(absolute[0], absolute[0])
                    if unit in top and unit != here[0]:
                        graph[here[0]].add(unit)
    cycles = {"cycle(rust): " + ", ".join(c) for c in strongly_connected(graph)}
    return dict(graph), cycles


# --- The test ----------------------------------------------------------------------------------


def all_violations() -> set[str]:
    return python_graph()[1] | rust_graph()[1]


def test_layers_cycles_and_private_names():
    found = sorted(all_violations())
    assert not found, "architecture violations (docs/architecture.md):\n" + "\n".join(found)


def write_package(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / "sandlight" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root / "sandlight"


def test_python_checks_find_upward_imports_cycles_and_private_names(tmp_path):
    package = write_package(
        tmp_path,
        {
            "__init__.py": '__version__ = "0"\n_NATIVE_API = {"reflectance": "sandlight.engine"}\n',
            "errors.py": "",
            "sample.py": "from sandlight.engine import reflectance\n",  # data -> measurement: up
            "engine.py": "from sandlight import sample, _native\nimport sandlight\nV = sandlight.__version__\n",
            "gonio/__init__.py": "",
            "gonio/measure.py": (
                "from sandlight.engine import _trace\n"  # another module's private name
                "from sandlight import engine\n"
                "x = engine._check\n"  # the same by attribute
                "def f():\n    from sandlight.cli import app\n"  # lazy, upward, not allowed
                "def g():\n    import sandlight\n    return sandlight.reflectance, sandlight.__version__\n"
            ),
            "gonio/_table.py": "",
            "gonio/brdf.py": "from sandlight.gonio import _table\nfrom . import measure\n",  # own package: fine
            "gonio/plots.py": "from . import brdf as b\ny = b._z\n",  # private, by a relative import
            "cli/__init__.py": "app = 1\n",
            "newthing.py": "",
        },
    )
    imports, violations = python_graph(package)
    assert violations == {
        "layer: sandlight.sample imports sandlight.engine at module level",
        "cycle(python): engine, sample",
        "private: sandlight.gonio.measure uses sandlight.engine._trace",
        "private: sandlight.gonio.measure uses sandlight.engine._check",
        "layer: sandlight.gonio.measure imports sandlight.cli inside a function",
        "private: sandlight.gonio.plots uses sandlight.gonio.brdf._z",
        "layer: unit 'newthing' is in no layer of LAYERS",
        "layer: sandlight.gonio.measure uses sandlight.reflectance of the package root "
        "(import it from sandlight.engine)",
    }
    lazy = [i for i in imports["sandlight.gonio.measure"] if i.lazy]
    assert {(i.target, i.names) for i in lazy} == {
        ("sandlight.cli", ("app",)),
        ("sandlight", ("__version__",)),
        ("sandlight", ("reflectance",)),
    }
    assert {i.target for i in imports["sandlight.gonio.brdf"]} == {"sandlight.gonio._table", "sandlight.gonio.measure"}


def test_rust_check_reads_use_trees_and_leaves_tests_out(tmp_path):
    files = {
        "lib.rs": "pub mod a; pub mod b; pub mod c; pub mod d;\npub use a::Thing;\n",
        "a.rs": 'use crate::{b::{X, Y}, d};\n// use crate::c;\nconst S: &str = "crate::c";\n',
        "b.rs": "pub fn f() { crate::c::g() }\n#[cfg(test)]\nmod tests {\n    use crate::a::Z;\n    fn h() {}\n}\n",
        "c/mod.rs": "mod e;\n",
        "c/e.rs": "use super::super::Thing;\n",  # the re-exported a::Thing: c -> a
        "d.rs": "use self::inner::Q;\nmod inner {}\n",
    }
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    graph, cycles = rust_graph(tmp_path)
    assert graph == {"a": {"b", "d"}, "b": {"c"}, "c": {"a"}}
    assert cycles == {"cycle(rust): a, b, c"}


if __name__ == "__main__":
    imports, py_violations = python_graph()
    rust, rust_violations = rust_graph()
    edges = defaultdict(set)
    for found in imports.values():
        for imp in found:
            if unit_of(imp.importer) != unit_of(imp.target):
                edges[unit_of(imp.importer)].add(unit_of(imp.target) + (" (lazy)" if imp.lazy else ""))
    print("Python layers, lowest first, and what each unit imports:")
    for rank, (layer, units) in enumerate(LAYERS):
        print(f"{rank} {layer}")
        for unit in sorted(units):
            print(f"    {unit} -> {', '.join(sorted(edges.get(unit, ())))}")
    print("\nRust top-level modules:")
    for unit in sorted(rust):
        print(f"    {unit} -> {', '.join(sorted(rust[unit]))}")
    print("\nViolations:")
    for v in sorted(py_violations | rust_violations):
        print("    " + v)
