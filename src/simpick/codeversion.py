"""Which library code a job runs, found from the imports, and its fingerprint for the rule's params.

Snakemake reruns a job when its params change, but it does not look into imported library
code: an edited metric under src/simpick would silently keep serving results computed by the
old code. Each rule therefore carries, as a param, a hash of the source files its job runs
(``rules/common.smk``: ``job_code``). Those files are computed, not listed: starting from the
functions the job's script calls (``"simpick.workflow:simulate_job"``) or a whole module (an
engine adapter, which the registry imports by name), the source is read with :mod:`ast` and
followed through every name a function uses: a function or class of its own module, an
import at the top of a module or inside a function, ``module.attribute``. A module that is
imported at all brings what its top level imports (it runs when the module is loaded); a
function brings only what it names. So editing ``realsegments.py``, which the segments' code
imports, reruns the segment jobs and not the lab simulations, and editing the report reruns
no simulation.

Limits, on purpose: a name is followed wherever it occurs (a local variable that shadows a
function counts as the function: a few files too many, never too few); a whole file is
hashed, not the functions in it; code reached through ``importlib`` (the engine registry) or
a dispatch table that the caller resolves itself (``opaque``) must be named as a root.
Templates and other non-Python files beside a module (in folders that are not packages)
count as part of it.

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
        for node in self.tree.body:
            self._top_level(node)

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
            for child in ast.iter_child_nodes(node):
                if isinstance(child, ast.stmt):
                    self._top_level(child)
                elif isinstance(child, ast.ExceptHandler):
                    for stmt in child.body:
                        self._top_level(stmt)

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
    """The files reached from the roots, following names (see the module docstring)."""

    def __init__(self, root: Path, opaque: frozenset[str]):
        self.root, self.opaque = root, opaque
        self.known = modules(root)
        self.files: set[Path] = set()
        self.loaded: set[str] = set()
        self.done: set[tuple] = set()

    def load(self, module: str) -> None:
        """``module`` is imported: its file, its parent packages, and what its top level imports."""
        if module in self.loaded:
            return
        if module not in self.known:  # "from simpick.x import y" where y is a name, not a module
            return
        self.loaded.add(module)
        parts = module.split(".")
        for i in range(1, len(parts)):
            self.load(".".join(parts[:i]))
        parsed = _parse(module, self.root)
        self.files.add(parsed.path)
        for target in parsed.load_time:
            self.load(target)

    def follow(self, target: tuple) -> None:
        if target in self.done:
            return
        self.done.add(target)
        if target[0] == "module":
            self.whole(target[1])
        else:
            self.name(target[1], target[2])

    def whole(self, module: str) -> None:
        """A module used as a whole (a root, or passed around as an object): all its definitions."""
        self.load(module)
        if module not in self.known:
            return
        parsed = _parse(module, self.root)
        for name in parsed.definitions:
            self.follow(("name", module, name))

    def name(self, module: str, name: str) -> None:
        """``module.name`` is used: the module is loaded and, for a definition, what it names."""
        if module not in self.known:
            return
        self.load(module)
        if f"{module}:{name}" in self.opaque:
            return
        parsed = _parse(module, self.root)
        if name in parsed.definitions:
            self.uses(parsed, parsed.definitions[name])
        elif name in parsed.imports:  # re-exported
            self.follow(parsed.imports[name])
        elif f"{module}.{name}" in self.known:
            self.follow(("module", f"{module}.{name}"))

    def uses(self, parsed: _Module, node: ast.AST) -> None:
        """Everything ``node`` (a definition) names: its own imports first, then the module's."""
        local = {}
        for child in ast.walk(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                for bound, target in parsed.bindings(child):
                    local[bound] = target
                    self.load(target[1])
        as_base = set()
        for child in ast.walk(node):
            if isinstance(child, ast.Attribute) and isinstance(child.value, ast.Name):
                target = local.get(child.value.id) or parsed.imports.get(child.value.id)
                if target and target[0] == "module":
                    as_base.add(id(child.value))
                    self.attribute(target[1], child.attr)
        for child in ast.walk(node):
            if isinstance(child, ast.Name) and id(child) not in as_base:
                target = local.get(child.id) or parsed.imports.get(child.id)
                if target:
                    self.follow(target)
                elif child.id in parsed.definitions and parsed.definitions[child.id] is not node:
                    self.follow(("name", parsed.name, child.id))

    def attribute(self, module: str, attr: str) -> None:
        """``module.attr``: a submodule, or a name of the module."""
        if f"{module}.{attr}" in self.known:
            self.load(module)
            self.follow(("module", f"{module}.{attr}"))
        else:
            self.follow(("name", module, attr))


def data_files(module_file: Path) -> set[Path]:
    """Templates and other non-Python files beside a module, in folders that are not packages."""
    found = set()
    pending = [module_file.parent]
    while pending:
        folder = pending.pop()
        for path in folder.iterdir():
            if path.is_dir():
                if path.name != "__pycache__" and not (path / "__init__.py").exists():
                    pending.append(path)
            elif path.suffix not in (".py", ".pyc"):
                found.add(path)
    return found


@functools.lru_cache(maxsize=None)
def job_files(roots: tuple[str, ...], opaque: frozenset[str] = frozenset(), root: Path = ROOT) -> tuple[Path, ...]:
    """The files a job runs, from ``roots``: ``"module:function"`` (or a class or constant) or
    ``"module"`` (all of it). A root that does not exist is an error, so a renamed job function
    cannot silently drop out of the fingerprint."""
    closure = _Closure(root, opaque)
    known = modules(root)
    for entry in roots:
        module, _, name = entry.partition(":")
        if module not in known:
            raise KeyError(f"code version: no module {module!r} under {root}")
        if name and name not in _parse(module, root).definitions:
            raise KeyError(f"code version: {module} defines no {name!r}")
        closure.follow(("name", module, name) if name else ("module", module))
    files = set(closure.files)
    for path in closure.files:
        files |= data_files(path)
    return tuple(sorted(files))


@functools.lru_cache(maxsize=None)
def _digest(path: Path, root: Path) -> bytes:
    return path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0"


def job_code(*roots: str, opaque: tuple[str, ...] = (), root: Path | str = ROOT) -> str:
    """sha256 (16 hex digits) over the source files a job runs (:func:`job_files`), sorted by path."""
    root = Path(root)
    digest = hashlib.sha256()
    for path in job_files(tuple(sorted(set(roots))), frozenset(opaque), root):
        digest.update(_digest(path, root))
    return digest.hexdigest()[:16]


def code_version(*names: str, root: Path | str = ROOT) -> str:
    """sha256 (16 hex digits) over the named files or folders under ``root`` (``.py`` and
    templates, sorted by path); a name that does not exist is an error."""
    root = Path(root)
    digest = hashlib.sha256()
    files = set()
    for name in names:
        path = root / name
        if path.is_dir():
            files.update(p for p in path.rglob("*") if p.is_file() and p.suffix in (".py", ".j2", ".css"))
        elif path.is_file():
            files.add(path)
        else:
            raise FileNotFoundError(f"code_version: {path} does not exist")
    for path in sorted(files):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]
