"""Which library code a job runs, found from the imports, and its fingerprint for the rule's params.

Snakemake reruns a job when its params change, but it does not look into imported library
code: an edited metric under src/simpick would silently keep serving results computed by the
old code. Each rule therefore carries, as a param, a hash of the source files its job runs
(:meth:`simpick.plan.Plan.script_code`: ``job_code``). Those files are computed, not listed: starting from the
functions the job's script calls (``"simpick.simulate.jobs:simulate_job"``) or a whole module (an
engine adapter, which the registry imports by name), the source is read with :mod:`ast` and
followed through every name a function uses: a function or class of its own module, an
import at the top of a module or inside a function, ``module.attribute``. A module that is
imported at all brings what its top level imports (it runs when the module is loaded); a
function brings only what it names. So editing ``real/segments.py``, which the segments' code
imports, reruns the segment jobs and not the lab simulations, and editing the report reruns
no simulation.

Limits, on purpose: a name is followed wherever it occurs (a local variable that shadows a
function counts as the function: a few files too many, never too few); a whole file is
hashed, not the functions in it; code reached through ``importlib`` (the engine registry) or
a dispatch table that the caller resolves itself (``opaque``) must be named as a root.
Templates a module reads (a non-package folder beside it whose name the module's source
states) count as part of it.

The same parse gives :func:`import_graph` (every import between simpick modules, at the top
or inside functions), which ``tests/test_imports.py`` keeps free of cycles.
"""

from __future__ import annotations

import ast
import functools
import hashlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent
PACKAGE = ROOT.name  # "simpick"


@functools.lru_cache(maxsize=None)
def modules(root: Path = ROOT) -> dict[str, Path]:
    """Dotted module name -> source file, for every module of the package at ``root``."""
    found = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        if "__pycache__" in parts:
            continue
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


class _Module:
    """One parsed module: its top-level names (definitions and imports) and what loading it imports."""

    def __init__(self, name: str, path: Path, known: dict[str, Path]):
        self.name, self.path, self.known = name, path, known
        self.is_package = path.name == "__init__.py"
        self.tree = ast.parse(path.read_bytes(), filename=str(path))
        self.definitions: dict[str, ast.AST] = {}
        self.imports: dict[str, tuple] = {}  # local name -> ("module", dotted) or ("name", module, name)
        self.load_time: set[str] = set()  # simpick modules the top level imports
        self.statements: list[ast.stmt] = []  # top-level statements that run on import and define nothing
        self.text = path.read_text()
        self.lines = self.text.splitlines(keepends=True)
        self._names: dict[int, tuple] = {}
        for node in self.tree.body:
            self._top_level(node)
        self.load_text = "\n".join(self.load_time_code(node) for node in self.tree.body)

    def source(self, node: ast.AST) -> str:
        """A top-level statement's source lines (decorators included)."""
        first = min([node.lineno] + [d.lineno for d in getattr(node, "decorator_list", [])])
        return "".join(self.lines[first - 1:node.end_lineno])

    def names(self, node: ast.AST) -> tuple[tuple, ...]:
        """What ``node`` uses, computed once per node: ("load", module) for each simpick import in
        it, ("attr", module, name) for ``module.name``, and ("module", m) / ("name", m, n) for each
        other name, resolved by its own imports first, then the module's, then its definitions."""
        key = id(node)
        if key in self._names:
            return self._names[key]
        local, found, nodes = {}, [], list(ast.walk(node))
        for child in nodes:
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                for bound, target in self.bindings(child):
                    local[bound] = target
                    found.append(("load", target[1]))
        as_base = set()
        for child in nodes:
            if isinstance(child, ast.Attribute) and isinstance(child.value, ast.Name):
                target = local.get(child.value.id) or self.imports.get(child.value.id)
                if target and target[0] == "module":
                    as_base.add(id(child.value))
                    found.append(("attr", target[1], child.attr))
        for child in nodes:
            if isinstance(child, ast.Name) and id(child) not in as_base:
                target = local.get(child.id) or self.imports.get(child.id)
                if target:
                    found.append(target)
                elif child.id in self.definitions:
                    found.append(("name", self.name, child.id))
        self._names[key] = tuple(dict.fromkeys(found))
        return self._names[key]

    def load_time_code(self, node: ast.stmt) -> str:
        """The code of a top-level statement that runs when the module is imported: all of it but
        a function's body (its decorators, defaults and annotations do run)."""
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            parts = [*node.decorator_list, node.args] + ([node.returns] if node.returns else [])
            return f"def {node.name}: " + " ".join(ast.unparse(p) for p in parts)
        return self.source(node)

    def _top_level(self, node: ast.AST) -> None:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            self.definitions[node.name] = node
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                for name in ast.walk(target):
                    if isinstance(name, ast.Name):
                        self.definitions[name.id] = node
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            for local, target in self.bindings(node):
                self.imports[local] = target
                self.load_time.add(target[1])
        elif isinstance(node, (ast.If, ast.Try, ast.With)):  # guarded imports and definitions
            self.statements.append(node)
            for child in ast.iter_child_nodes(node):
                if isinstance(child, ast.stmt):
                    self._top_level(child)
                elif isinstance(child, ast.ExceptHandler):
                    for stmt in child.body:
                        self._top_level(stmt)
        elif not isinstance(node, ast.Expr) or not isinstance(node.value, ast.Constant):  # not a docstring
            self.statements.append(node)

    def absolute(self, node: ast.ImportFrom) -> str:
        if not node.level:
            return node.module or ""
        base = self.name.split(".") if self.is_package else self.name.split(".")[:-1]
        base = base[: len(base) - node.level + 1]
        return ".".join(base + ([node.module] if node.module else []))

    def bindings(self, node: ast.Import | ast.ImportFrom) -> list[tuple[str, tuple]]:
        """(local name, target) of each name an import statement binds to a simpick module or
        one of its attributes; imports of other packages bind nothing here."""
        out = []
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] != PACKAGE:
                    continue
                if alias.asname:
                    out.append((alias.asname, ("module", alias.name)))
                else:  # "import simpick.x" binds "simpick", and loads simpick.x
                    out.append((PACKAGE, ("module", alias.name)))
            return out
        module = self.absolute(node)
        if module.split(".")[0] != PACKAGE:
            return out
        for alias in node.names:
            if alias.name == "*":
                continue
            submodule = f"{module}.{alias.name}"
            target = ("module", submodule) if submodule in self.known else ("name", module, alias.name)
            out.append((alias.asname or alias.name, target))
        return out

    def imported_modules(self) -> set[str]:
        """Every simpick module any import statement of this module names, wherever it stands."""
        found = set()
        for node in ast.walk(self.tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                found.update(target[1] for _, target in self.bindings(node))
        return {m for m in found if m in self.known}


@functools.lru_cache(maxsize=None)
def _parse(name: str, root: Path = ROOT) -> _Module:
    known = modules(root)
    return _Module(name, known[name], known)


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """module -> the simpick modules it imports (top level and inside functions alike)."""
    return {name: _parse(name, root).imported_modules() - {name} for name in modules(root)}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import cycles of ``graph``: per strongly connected component of more than one module,
    one cycle through it (``[a, b, ..., a]``), so a failure can name the imports to cut."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []

    def visit(node):  # Tarjan's algorithm
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = set()
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.add(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(component)

    for node in sorted(graph):
        if node not in index:
            visit(node)
    found = []
    for component in components:
        start = min(component)
        path, seen = [start], {start}
        while True:  # walk inside the component until the start (or a repeat) closes the loop
            nxt = min(graph[path[-1]] & component, key=lambda m: (m != start and m in seen, m))
            path.append(nxt)
            if nxt == start or nxt in seen:
                found.append(path[path.index(nxt):])
                break
            seen.add(nxt)
    return found


class _Closure:
    """The code reached from the roots, following names (see the module docstring): the modules
    loaded and, of each, the definitions used."""

    def __init__(self, root: Path, opaque: frozenset[str]):
        self.root, self.opaque = root, opaque
        self.known = modules(root)
        self.loaded: set[str] = set()
        self.reached: set[tuple[str, str]] = set()  # (module, top-level name) whose code runs

    def load(self, module: str) -> None:
        """``module`` is imported: its parent packages, what its top level imports, and what its
        top-level statements other than definitions (a registration call, say) name."""
        if module in self.loaded or module not in self.known:
            return
        self.loaded.add(module)
        parts = module.split(".")
        for i in range(1, len(parts)):
            self.load(".".join(parts[:i]))
        parsed = _parse(module, self.root)
        for target in parsed.load_time:
            self.load(target)
        for node in parsed.statements:
            self.uses(parsed, node)

    def follow(self, target: tuple) -> None:
        if target[0] == "module":
            self.whole(target[1])
        else:
            self.name(target[1], target[2])

    def whole(self, module: str) -> None:
        """A module used as a whole (a root, or passed around as an object): all its definitions."""
        self.load(module)
        if module in self.known:
            for name in _parse(module, self.root).definitions:
                self.name(module, name)

    def name(self, module: str, name: str) -> None:
        """``module.name`` is used: the module is loaded and, for a definition, what it names."""
        if module not in self.known or (module, name) in self.reached:
            return
        self.load(module)
        if f"{module}:{name}" in self.opaque:
            return
        parsed = _parse(module, self.root)
        if name in parsed.definitions:
            self.reached.add((module, name))
            self.uses(parsed, parsed.definitions[name])
        elif name in parsed.imports:  # re-exported
            self.follow(parsed.imports[name])
        elif f"{module}.{name}" in self.known:
            self.whole(f"{module}.{name}")

    def uses(self, parsed: _Module, node: ast.AST) -> None:
        """Everything ``node`` names (:meth:`_Module.names`)."""
        for action, *target in parsed.names(node):
            if action == "load":
                self.load(target[0])
            elif action == "attr":
                self.attribute(*target)
            else:
                self.follow((action, *target))

    def attribute(self, module: str, attr: str) -> None:
        """``module.attr``: a submodule, or a name of the module."""
        if f"{module}.{attr}" in self.known:
            self.load(module)
            self.whole(f"{module}.{attr}")
        else:
            self.name(module, attr)


@functools.lru_cache(maxsize=None)
def data_files(module: str, root: Path = ROOT) -> frozenset[Path]:
    """The templates and other non-Python files a module reads: those in a folder beside it that
    is not a package, where the module's source names the folder or the file as a string
    (simpick.report.build: ``"templates"``)."""
    parsed = _parse(module, root)
    found = set()
    for folder in parsed.path.parent.iterdir():
        if not folder.is_dir() or folder.name == "__pycache__" or (folder / "__init__.py").exists():
            continue
        for path in folder.rglob("*"):
            if path.is_file() and path.suffix not in (".py", ".pyc") and any(
                    f"{quote}{name}{quote}" in parsed.text for name in (folder.name, path.name) for quote in "\"'"):
                found.add(path)
    return frozenset(found)


@functools.lru_cache(maxsize=None)
def _reach(entry: str, opaque: frozenset[str], root: Path) -> tuple[frozenset[str], frozenset[tuple[str, str]]]:
    """(modules loaded, definitions reached) from one root; a job's code is the union over its
    roots (an engine adapter's closure is computed once, not once per script that steps it)."""
    known = modules(root)
    module, _, name = entry.partition(":")
    if module not in known:
        raise KeyError(f"code version: no module {module!r} under {root}")
    parsed = _parse(module, root)
    if name and not (name in parsed.definitions or name in parsed.imports or f"{module}.{name}" in known):
        raise KeyError(f"code version: {module} defines no {name!r}")
    closure = _Closure(root, opaque)
    if name:
        closure.name(module, name)
    else:
        closure.whole(module)
    return frozenset(closure.loaded), frozenset(closure.reached)


@functools.lru_cache(maxsize=None)
def _closure(roots: tuple[str, ...], opaque: frozenset[str], root: Path) -> tuple[list[str], list[tuple[str, str]]]:
    """(modules loaded, definitions reached), sorted, from every root."""
    loaded, reached = set(), set()
    for entry in roots:
        more_loaded, more_reached = _reach(entry, opaque, root)
        loaded |= more_loaded
        reached |= more_reached
    return sorted(loaded), sorted(reached)


def job_files(*roots: str, opaque: tuple[str, ...] = (), root: Path | str = ROOT) -> list[Path]:
    """The source files (and templates) a job runs code of, from ``roots``: ``"module:function"``
    (or a class or constant) or ``"module"`` (all of it). A root that does not exist is an error,
    so a renamed job function cannot silently drop out of the fingerprint."""
    root = Path(root)
    loaded, _ = _closure(tuple(sorted(set(roots))), frozenset(opaque), root)
    files = {_parse(m, root).path for m in loaded}
    for module in loaded:
        files |= data_files(module, root)
    return sorted(files)


@functools.lru_cache(maxsize=None)
def _text(module: str, name: str | None, root: Path) -> bytes:
    """What is hashed of a module: its load-time code (``name`` None) or one definition's source."""
    parsed = _parse(module, root)
    text = parsed.load_text if name is None else parsed.source(parsed.definitions[name])
    return f"{module}:{name or ''}".encode() + b"\0" + text.encode() + b"\0"


@functools.lru_cache(maxsize=None)
def _data(path: Path, root: Path) -> bytes:
    return path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0"


def job_code(*roots: str, opaque: tuple[str, ...] = (), root: Path | str = ROOT) -> str:
    """sha256 (16 hex digits) of the code a job runs (:func:`_job_code`); computed once per set of
    roots in a process (the planning of 1000 jobs asks for the same few versions again and again)."""
    return _job_code(tuple(sorted(set(roots))), tuple(sorted(set(opaque))), Path(root))


def clear_cache() -> None:
    """Forget every parsed module and version (for a process that edits the sources it reads)."""
    for cached in (modules, _parse, _reach, _closure, _text, _data, data_files, script_roots, dispatch_entry,
                   _job_code):
        cached.cache_clear()


@functools.lru_cache(maxsize=None)
def _job_code(roots: tuple[str, ...], opaque: tuple[str, ...], root: Path) -> str:
    """sha256 (16 hex digits) of the code a job runs: of every module it loads, the code that runs
    on import (imports, constants, class bodies, decorators; not function bodies), and the source
    of every function it reaches (:class:`_Closure`), plus the templates beside those modules.
    Editing a function that no job of a rule reaches leaves that rule's version as it is."""
    loaded, reached = _closure(roots, frozenset(opaque), root)
    digest = hashlib.sha256()
    for module in loaded:
        digest.update(_text(module, None, root))
    for module, name in reached:
        digest.update(_text(module, name, root))
    for module in loaded:
        for path in sorted(data_files(module, root)):  # templates
            digest.update(_data(path, root))
    return digest.hexdigest()[:16]


@functools.lru_cache(maxsize=None)
def script_roots(script: Path | str) -> tuple[str, ...]:
    """The functions a workflow script calls: its ``from simpick.x import f`` imports, as roots."""
    tree = ast.parse(Path(script).read_bytes(), filename=str(script))
    roots = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == PACKAGE:
            roots += [f"{node.module}:{alias.name}" for alias in node.names]
        elif isinstance(node, ast.Import):
            roots += [alias.name for alias in node.names if alias.name.split(".")[0] == PACKAGE]
    return tuple(roots)


@functools.lru_cache(maxsize=None)
def dispatch_entry(module: str, table: str, key: str, root: Path | str = ROOT) -> str:
    """``"module:function"`` of the function that the dispatch table ``module.table`` (a dict
    literal) holds under ``key`` (the first name of the entry), read from the source: a job that
    takes one entry names it as a root and the table as opaque."""
    root = Path(root)
    parsed = _parse(module, root)
    node = parsed.definitions.get(table)
    value = getattr(node, "value", None)
    if not isinstance(value, ast.Dict):
        raise KeyError(f"code version: {module}.{table} is not a dict literal")
    for k, v in zip(value.keys, value.values):
        if isinstance(k, ast.Constant) and k.value == key:
            name = next((n.id for n in ast.walk(v) if isinstance(n, ast.Name)), None)
            if name is None:
                break
            target = parsed.imports.get(name)
            return f"{target[1]}:{target[2]}" if target and target[0] == "name" else f"{module}:{name}"
    raise KeyError(f"code version: {module}.{table} has no function under {key!r}")
