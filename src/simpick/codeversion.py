"""Which library code a job runs, and its fingerprint for the rule's params.

Snakemake reruns a job when its params change, but it does not look into imported library code:
an edited metric under src/simpick would silently keep serving results computed by the old code.
Each rule therefore carries, as a param, a hash of the source files its job can run
(:meth:`simpick.plan.Plan.script_code`: :func:`job_code`). One rule says which files, the same for
every job:

1. **Roots**: the simpick modules the job's script imports (``scripts/<script>.py``), plus the
   modules the job reaches by name only, which the plan declares: a model's adapter modules
   (:meth:`simpick.plan.Plan.engine_modules`: the registry imports an adapter by name) and the
   module that drives a source kind's cases (:data:`simpick.simulate.jobs.PREPARE`).
2. **Files**: every module reachable from the roots through ``import`` statements, wherever the
   statement stands in a module (at the top or inside a function: both count the same), with the
   packages that hold them; plus the templates beside a reached module that names them (a folder
   that is not a package, named by the module's source as a string: ``"templates"``).
3. **Hash**: of each file, its syntax tree without comments, docstrings or the places of its
   imports (the imports count as a sorted set of what they bind). Moving an import inside a module,
   reformatting, or editing a comment or a docstring changes no version; editing code reruns every
   job that can reach it.

A whole module counts, not the functions of it a job calls: a job whose module shares a file with
another job's function reruns when that function is edited (a few reruns too many, never too
few), and a maintainer can tell which jobs an edit reruns from the imports alone.

Parsing every module is most of a workflow's planning time; :func:`use_cache` keeps what it gives
(each module's imports and top-level names, each job's version) in a file keyed by the sources'
contents, so that a later process that finds the same sources parses none of them. The key is the
content, never a time stamp: an edited file is parsed again, and a version read from the file is the
one the parse would give.

The same parse gives :func:`import_graph` (every import between simpick modules, at the top or
inside functions), which ``tests/test_imports.py`` keeps free of cycles and ``tests/test_layers.py``
keeps in the order of the stages.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
PACKAGE = ROOT.name  # "simpick"
# what use_cache() keeps: "modules" (key -> imports and top-level names), "jobs" (key -> version);
# each key hashes the contents it stands for and this Python's version (its syntax trees)
_STORE: dict[str, dict] = {"modules": {}, "jobs": {}}
_STORE_FILE: list[Path] = []  # the file use_cache() reads and writes back, once set
_USED: dict[str, set[str]] = {"modules": set(), "jobs": set()}
_STORE_LIMIT = 5000  # entries kept beyond those this process used


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def use_cache(path: str | Path) -> None:
    """Read what earlier processes parsed from ``path`` (a JSON file; a missing or broken one is
    an empty cache) and write it back, with this process's additions, when the process ends."""
    import atexit

    path = Path(path)
    try:
        stored = json.loads(path.read_text())
        _STORE.update({k: dict(stored[k]) for k in ("modules", "jobs")})
    except (OSError, ValueError, KeyError, TypeError):
        pass
    if not _STORE_FILE:
        atexit.register(save_cache)
    _STORE_FILE[:] = [path]


def save_cache() -> None:
    """Write the cache back (use_cache's file): the entries this process used, and the others while
    they number fewer than a limit."""
    if not _STORE_FILE or not (_USED["modules"] or _USED["jobs"]):
        return
    kept = {}
    for kind in ("modules", "jobs"):
        entries = _STORE[kind]
        if len(entries) > len(_USED[kind]) + _STORE_LIMIT:
            entries = {k: v for k, v in entries.items() if k in _USED[kind]}
        kept[kind] = entries
    path = _STORE_FILE[0]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{id(kept)}.partial")
        tmp.write_text(json.dumps(kept, sort_keys=True))
        tmp.replace(path)
    except OSError:  # a cache that cannot be written costs time, never a result
        pass


@functools.cache
def _known_key(root: Path) -> str:
    """What a module's imports depend on besides its text: which modules exist, and the Python."""
    return _sha(("\n".join(sorted(modules(root))) + "\n" + sys.version.split()[0]).encode())


@functools.cache
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
    """One parsed module: the simpick modules its import statements name, and its top-level names."""

    def __init__(self, name: str, path: Path, known: dict[str, Path], known_key: str = ""):
        self.name, self.path, self.known = name, path, known
        self.is_package = path.name == "__init__.py"
        self.text = path.read_text()
        self.digest = _sha(self.text.encode())
        # the cache's key of what parsing this text gives (use_cache)
        self.key = _sha(f"{name}\0{self.digest}\0{known_key}".encode())

    @functools.cached_property
    def tree(self) -> ast.Module:
        return ast.parse(self.text, filename=str(self.path))

    def _cached(self, field: str, compute) -> frozenset[str]:
        entry = _STORE["modules"].get(self.key)
        if entry is None or field not in entry:
            entry = dict(entry or {}, **{field: sorted(compute())})
            _STORE["modules"][self.key] = entry
        _USED["modules"].add(self.key)
        return frozenset(entry[field])

    def absolute(self, node: ast.ImportFrom) -> str:
        """The dotted module an ``from ... import`` names, relative imports resolved."""
        if not node.level:
            return node.module or ""
        base = self.name.split(".") if self.is_package else self.name.split(".")[:-1]
        base = base[: len(base) - node.level + 1]
        return ".".join(base + ([node.module] if node.module else []))

    def targets(self, node: ast.Import | ast.ImportFrom) -> set[str]:
        """The simpick modules one import statement names: ``from simpick.x import y`` names
        simpick.x.y where that is a module, else simpick.x (a package's parents load with it:
        :func:`job_files` counts them)."""
        if isinstance(node, ast.Import):
            return {alias.name for alias in node.names if alias.name.split(".")[0] == PACKAGE}
        module = self.absolute(node)
        if module.split(".")[0] != PACKAGE:
            return set()
        return {f"{module}.{a.name}" if f"{module}.{a.name}" in self.known else module for a in node.names}

    @functools.cached_property
    def imported(self) -> frozenset[str]:
        """Every simpick module any import statement of this module names, wherever it stands."""
        return self._cached("imported", self._imported)

    def _imported(self) -> set[str]:
        found = set()
        for node in ast.walk(self.tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                found |= self.targets(node)
        return {m for m in found if m in self.known}

    @functools.cached_property
    def defined(self) -> frozenset[str]:
        """The names the module's top level binds (definitions, assignments, imports), guarded
        ones included."""
        return self._cached("defined", self._defined)

    def _defined(self) -> set[str]:
        names = set()
        for node in self._top_statements(self.tree.body):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
                for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                    names |= {n.id for n in ast.walk(target) if isinstance(n, ast.Name)}
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                names |= {(a.asname or a.name).split(".")[0] for a in node.names}
        return names

    @staticmethod
    def _top_statements(body):
        for node in body:
            yield node
            if isinstance(node, (ast.If, ast.Try, ast.With)):
                for field in ("body", "orelse", "finalbody"):
                    yield from _Module._top_statements(getattr(node, field, []))
                for handler in getattr(node, "handlers", []):
                    yield from _Module._top_statements(handler.body)

    @functools.cached_property
    def code(self) -> str:
        """What is hashed of the module: its syntax tree with docstrings and import statements taken
        out, then the sorted set of what the imports bind. Comments and layout are not in a syntax
        tree at all."""
        tree = ast.parse(self.text)
        bound = set()
        for node in ast.walk(tree):
            for field in ("body", "orelse", "finalbody"):
                statements = getattr(node, field, None)
                if not isinstance(statements, list):
                    continue
                kept = []
                for i, stmt in enumerate(statements):
                    if isinstance(stmt, ast.Import):
                        bound |= {("import", a.name, a.asname or "") for a in stmt.names}
                    elif isinstance(stmt, ast.ImportFrom):
                        bound |= {("from", self.absolute(stmt), a.name, a.asname or "") for a in stmt.names}
                    elif not (i == 0 and field == "body" and _is_docstring(node, stmt)):
                        kept.append(stmt)
                setattr(node, field, kept)
        return ast.dump(tree) + "\n" + "\n".join(" ".join(b) for b in sorted(bound))


def _is_docstring(parent: ast.AST, stmt: ast.stmt) -> bool:
    return (
        isinstance(parent, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
        and isinstance(stmt, ast.Expr)
        and isinstance(stmt.value, ast.Constant)
        and isinstance(stmt.value.value, str)
    )


@functools.cache
def _parse(name: str, root: Path = ROOT) -> _Module:
    known = modules(root)
    return _Module(name, known[name], known, _known_key(root))


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """module -> the simpick modules it imports (top level and inside functions alike)."""
    return {name: set(_parse(name, root).imported) - {name} for name in modules(root)}


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
                found.append(path[path.index(nxt) :])
                break
            seen.add(nxt)
    return found


@functools.cache
def data_files(module: str, root: Path = ROOT) -> frozenset[Path]:
    """The templates and other non-Python files a module reads: those in a folder beside it that
    is not a package, where the module's source names the folder or the file as a string
    (simpick.report.render: ``"templates"``)."""
    parsed = _parse(module, root)
    found = set()
    for folder in parsed.path.parent.iterdir():
        if not folder.is_dir() or folder.name == "__pycache__" or (folder / "__init__.py").exists():
            continue
        for path in folder.rglob("*"):
            if (
                path.is_file()
                and path.suffix not in (".py", ".pyc")
                and any(f"{quote}{name}{quote}" in parsed.text for name in (folder.name, path.name) for quote in "\"'")
            ):
                found.add(path)
    return frozenset(found)


def _root_module(entry: str, root: Path) -> str:
    """The module of a root (``"module"`` or ``"module:name"``); a module or a name that does not
    exist is an error, so a renamed job function cannot silently drop out of the fingerprint."""
    known = modules(root)
    module, _, name = entry.partition(":")
    if module not in known:
        raise KeyError(f"code version: no module {module!r} under {root}")
    if name and name not in _parse(module, root).defined and f"{module}.{name}" not in known:
        raise KeyError(f"code version: {module} defines no {name!r}")
    return module


@functools.cache
def _reached(roots: tuple[str, ...], root: Path) -> tuple[str, ...]:
    """The modules reachable from ``roots`` through import statements, with their packages, sorted."""
    known = modules(root)
    seen, todo = set(), [_root_module(entry, root) for entry in roots]
    while todo:
        module = todo.pop()
        if module in seen or module not in known:
            continue
        seen.add(module)
        parts = module.split(".")
        todo += [".".join(parts[:i]) for i in range(1, len(parts))]  # its packages load first
        todo += _parse(module, root).imported
    return tuple(sorted(seen))


def job_files(*roots: str, root: Path | str = ROOT) -> list[Path]:
    """The source files (and templates) of the code a job can run, from ``roots``: ``"module"`` or
    ``"module:name"`` (the module; the name must exist in it)."""
    root = Path(root)
    reached = _reached(tuple(sorted(set(roots))), root)
    files = {_parse(m, root).path for m in reached}
    for module in reached:
        files |= data_files(module, root)
    return sorted(files)


def job_code(*roots: str, root: Path | str = ROOT) -> str:
    """sha256 (16 hex digits) of the code a job can run (:func:`job_files`; each module as
    :attr:`_Module.code`, each template as its bytes); computed once per set of roots in a process
    (the planning of 1000 jobs asks for the same few versions again and again)."""
    return _job_code(tuple(sorted(set(roots))), Path(root))


@functools.cache
def _job_code(roots: tuple[str, ...], root: Path) -> str:
    reached = _reached(roots, root)
    # the cache's key (use_cache): every file the version hashes, by content
    key = hashlib.sha256(f"{roots}\0{_known_key(root)}".encode())
    for module in reached:
        key.update(f"{module}\0{_parse(module, root).digest}\0".encode())
        for path in sorted(data_files(module, root)):
            key.update(path.relative_to(root).as_posix().encode() + b"\0" + _sha(path.read_bytes()).encode())
    key = key.hexdigest()
    _USED["jobs"].add(key)
    if key not in _STORE["jobs"]:
        _STORE["jobs"][key] = _version(reached, root)
    return _STORE["jobs"][key]


def _version(reached: tuple[str, ...], root: Path) -> str:
    """The version of the code of ``reached`` (the modules' code and their templates' bytes)."""
    digest = hashlib.sha256()
    for module in reached:
        digest.update(module.encode() + b"\0" + _parse(module, root).code.encode() + b"\0")
    for module in reached:
        for path in sorted(data_files(module, root)):  # templates
            digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def clear_cache() -> None:
    """Forget every parsed module and version (for a process that edits the sources it reads), and
    what use_cache() read (its file is read again by the next use_cache())."""
    for cached in (modules, _parse, _reached, _job_code, data_files, script_roots, _known_key):
        cached.cache_clear()
    for kind in ("modules", "jobs"):
        _STORE[kind].clear()
        _USED[kind].clear()


@functools.cache
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
