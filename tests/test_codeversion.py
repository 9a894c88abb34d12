"""A job's code version is the code it can reach through import statements, wherever they stand
(simpick.codeversion), hashed without comments, docstrings or the places of its imports: on a
made-up package, which edits change it; on src/simpick, that moving imports changes none and that
each model's jobs hold its own adapter only."""

import ast
import shutil

import pytest

from conftest import ROOT
from simpick.codeversion import clear_cache, job_code, job_files, modules, script_roots

PACKAGE = {
    "simpick/__init__.py": "",
    "simpick/io.py": "import json\n\n\ndef write(x):\n    return json.dumps(x)\n",
    "simpick/physics.py": '"""Falling."""\nG = 9.81\n\n\ndef fall(t):\n    return G * t * t / 2\n',
    "simpick/segments.py": "from simpick.physics import G\n\nCOLUMNS = ['a']\n",
    "simpick/lab.py": (
        "import math\n\nfrom simpick.io import write\n\n\n"
        "def run(t):\n    from simpick import physics\n\n    return write(math.floor(physics.fall(t)))\n"
    ),
    "simpick/rtf.py": "from simpick.io import write\n\n\ndef rtf_job(x):\n    return write(x)\n",
    "simpick/report/__init__.py": "",
    "simpick/report/build.py": "TEMPLATES = 'templates'\n\n\ndef render():\n    return TEMPLATES\n",
    "simpick/report/templates/page.j2": "{{ x }}\n",
}


@pytest.fixture()
def package(tmp_path):
    for name, text in PACKAGE.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    clear_cache()
    yield tmp_path / "simpick"
    clear_cache()


def edit(package, name, old, new):
    path = package.parent / name
    assert path.read_text().count(old) == 1, (name, old)
    path.write_text(path.read_text().replace(old, new))
    clear_cache()


def versions(package):
    return {
        "lab": job_code("simpick.lab:run", root=package),
        "segments": job_code("simpick.segments", root=package),
        "rtf": job_code("simpick.rtf:rtf_job", root=package),
        "report": job_code("simpick.report.build:render", root=package),
    }


def changed(package, name, old, new):
    before = versions(package)
    edit(package, name, old, new)
    after = versions(package)
    return sorted(k for k in before if before[k] != after[k])


def test_files_follow_imports_wherever_they_stand(package):
    def names(*roots):
        return [p.relative_to(package).as_posix() for p in job_files(*roots, root=package)]

    assert names("simpick.lab:run") == ["__init__.py", "io.py", "lab.py", "physics.py"]  # an import in a function
    assert names("simpick.segments") == ["__init__.py", "physics.py", "segments.py"]
    assert names("simpick.report.build:render") == [
        "__init__.py",
        "report/__init__.py",
        "report/build.py",
        "report/templates/page.j2",
    ]


def test_an_edit_changes_the_versions_of_the_jobs_that_can_reach_it_only(package):
    assert changed(package, "simpick/segments.py", "COLUMNS = ['a']", "COLUMNS = ['a', 'b']") == ["segments"]
    # a module two jobs import: both
    assert changed(package, "simpick/physics.py", "G * t * t / 2", "0.5 * G * t * t") == ["lab", "segments"]
    # the writer the lab and the rtf job import
    assert changed(package, "simpick/io.py", "json.dumps(x)", "json.dumps(x, indent=1)") == ["lab", "rtf"]
    assert changed(package, "simpick/report/templates/page.j2", "{{ x }}", "{{ y }}") == ["report"]
    # a new import of the rtf job
    assert changed(
        package,
        "simpick/rtf.py",
        "from simpick.io import write\n",
        "from simpick.io import write\nfrom simpick.segments import COLUMNS\n",
    ) == ["rtf"]


def test_comments_docstrings_and_layout_change_no_version(package):
    assert changed(package, "simpick/physics.py", "G = 9.81", "# gravity\nG = (\n    9.81\n)  # m/s^2") == []
    assert changed(package, "simpick/physics.py", '"""Falling."""', '"""Falling bodies, at g."""') == []


def test_moving_an_import_inside_a_module_changes_no_version(package):
    before = versions(package)
    # the lab's function-level import of simpick to the module's top, its top-level math into the function
    edit(package, "simpick/lab.py", "    from simpick import physics\n\n", "")
    edit(
        package,
        "simpick/lab.py",
        "import math\n\nfrom simpick.io import write\n",
        "from simpick import physics\nfrom simpick.io import write\n",
    )
    edit(package, "simpick/lab.py", "def run(t):\n", "def run(t):\n    import math\n\n")
    assert versions(package) == before
    # taking an import away is a change
    assert changed(package, "simpick/lab.py", "from simpick import physics\n", "") == ["lab"]


def test_the_cache_file_gives_the_same_versions_and_parses_nothing_unchanged(package, tmp_path, monkeypatch):
    """use_cache (the workflow's planning): a later process that finds the same sources reads the
    versions from the file, parsing no module; an edited module is parsed again and its jobs'
    versions change as without the cache."""
    import simpick.codeversion as codeversion

    fresh = versions(package)
    cache = tmp_path / "cache" / "code-versions.json"
    codeversion.clear_cache()
    codeversion.use_cache(cache)
    assert versions(package) == fresh
    codeversion.save_cache()
    assert cache.is_file()

    codeversion.clear_cache()  # a new process: nothing in memory, the file read again
    codeversion.use_cache(cache)

    def no_parse(*args, **kwargs):
        raise AssertionError("parsed a module the cache holds")

    with monkeypatch.context() as m:
        m.setattr(codeversion.ast, "parse", no_parse)
        assert versions(package) == fresh
    assert changed(package, "simpick/physics.py", "G * t * t / 2", "G * t**2 / 2") == ["lab", "segments"]
    codeversion.save_cache()
    codeversion._STORE_FILE.clear()


def test_a_root_that_does_not_exist_is_an_error(package):
    with pytest.raises(KeyError, match="defines no 'simulate'"):
        job_code("simpick.lab:simulate", root=package)
    with pytest.raises(KeyError, match="no module 'simpick.gone'"):
        job_code("simpick.gone:f", root=package)


def test_a_script_names_the_functions_it_runs(tmp_path):
    script = tmp_path / "s.py"
    script.write_text("from simpick.joblog import logged\nfrom simpick.simulate.jobs import simulate_job\nimport os\n")
    assert script_roots(script) == ("simpick.joblog:logged", "simpick.simulate.jobs:simulate_job")


# --- on src/simpick itself ---


def script_versions(root):
    """Every workflow script's version, with each model's adapter for the scripts that step one."""
    from simpick.engines import ADAPTERS
    from simpick.plan.study import Plan

    found = {}
    for script in sorted((ROOT / "scripts").glob("*.py")):
        found[script.stem] = job_code(*script_roots(script), root=root)
        for engine in ADAPTERS:
            found[script.stem, engine] = job_code(*script_roots(script), *Plan.engine_modules(engine), root=root)
    return found


def hoist_imports(text: str) -> str:
    """``text`` with every import inside a function or class moved to the module's top (where the
    function keeps a statement besides it)."""
    tree = ast.parse(text)
    hoisted = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            rest = [s for s in node.body if not isinstance(s, (ast.Import, ast.ImportFrom))]
            if rest and len(rest) < len(node.body):
                hoisted += [s for s in node.body if isinstance(s, (ast.Import, ast.ImportFrom))]
                node.body = rest
    start = next(
        (
            i
            for i, s in enumerate(tree.body)
            if not (isinstance(s, ast.Expr) or (isinstance(s, ast.ImportFrom) and s.module == "__future__"))
        ),
        len(tree.body),
    )
    tree.body[start:start] = hoisted
    return ast.unparse(tree)


def test_moving_the_imports_of_src_simpick_changes_no_code_version(tmp_path):
    """Every function-level import of every module moved to its module's top (and the files
    reformatted by ast.unparse, comments gone): no job's version changes."""
    copy = tmp_path / "simpick"
    shutil.copytree(ROOT / "src" / "simpick", copy, ignore=shutil.ignore_patterns("__pycache__"))
    clear_cache()
    try:
        before = script_versions(copy)
        moved = 0
        for path in sorted(copy.rglob("*.py")):
            text = path.read_text()
            new = hoist_imports(text)
            moved += new.count("\nimport ") + new.count("\nfrom ") - text.count("\nimport ") - text.count("\nfrom ")
            path.write_text(new)
        assert moved > 5  # some imports did stand inside functions
        clear_cache()
        assert script_versions(copy) == before
    finally:
        clear_cache()


def test_each_models_jobs_hold_its_own_adapter_only():
    """An edit to one engine's modules reruns that engine's jobs only: a simulate job's files hold no
    other engine's adapter, and no report, scoring or planning code."""
    from simpick.engines import ADAPTERS, REFERENCE_MODELS
    from simpick.plan.study import Plan

    src = ROOT / "src" / "simpick"
    adapters = {name: spec.split(":")[0] for name, spec in {**ADAPTERS, **REFERENCE_MODELS}.items()}
    assert len(modules()) > 40
    for engine, adapter in adapters.items():
        for step in ("simulate", "validate", "cpu_load", "calibrate"):
            files = {
                p.relative_to(src).with_suffix("").as_posix().replace("/", ".")
                for p in job_files(
                    *script_roots(ROOT / "scripts" / f"{step}.py"), *Plan.engine_modules(engine), "simpick.sources.lab"
                )
            }
            assert adapter.removeprefix("simpick.") in files, (engine, step)
            others = {m.removeprefix("simpick.") for e, m in adapters.items() if m != adapter}
            assert not files & others, (engine, step, files & others)
            assert not [f for f in files if f.split(".")[0] in ("report", "plan", "config", "schema")], files


def test_the_gazebo_programs_sources_are_in_the_code_of_the_jobs_that_run_it_only(tmp_path):
    """The Gazebo profiles run a compiled program (simpick/engines/gz, built by make gzphysics): an edit to
    its C++ or its CMakeLists.txt changes the code version of every job that reaches the gzphysics adapter
    (the models job among them, which writes Gazebo's worlds with it), and of no other job (here on a copy of
    src/simpick, the real sources untouched)."""
    from simpick.engines import ADAPTERS
    from simpick.plan.study import Plan

    copy = tmp_path / "simpick"
    shutil.copytree(ROOT / "src" / "simpick", copy, ignore=shutil.ignore_patterns("__pycache__"))
    steps = ("simulate", "validate", "cpu_load", "calibrate")
    models = ("gzphysics", *ADAPTERS)

    def versions():
        clear_cache()
        return {
            (step, model): job_code(
                *script_roots(ROOT / "scripts" / f"{step}.py"), *Plan.engine_modules(model), root=copy
            )
            for step in steps
            for model in models
        } | {script.stem: job_code(*script_roots(script), root=copy) for script in (ROOT / "scripts").glob("*.py")}

    try:
        before = versions()
        assert "ode" in models and len(before) > len(steps) * 3
        for name, comment in (("gzphysics_run.cc", "// an edit"), ("CMakeLists.txt", "# an edit")):
            path = copy / "engines" / "gz" / name
            path.write_text(f"{path.read_text()}\n{comment}\n")
            after = versions()
            changed = {k for k in before if before[k] != after[k]}
            # the models job runs the program too: Gazebo's worlds are its own, Gazebo Classic's its URDF conversion
            assert changed == {(step, "gzphysics") for step in steps} | {"simulator_models"}, changed
            before = after
    finally:
        clear_cache()


def test_a_report_or_table_edit_leaves_the_calibration_jobs_code_as_it_is():
    """The calibration's jobs read the split through simpick.score.split alone: the simulators' table, its
    report words and the first page's answer (simpick.score.simulators, .profiles, .sentences) are not their
    code, so an edit there does not refit every simulator."""
    for script in ("simulator_calibrate", "simulator_split"):
        files = {
            p.relative_to(ROOT / "src").as_posix() for p in job_files(*script_roots(ROOT / "scripts" / f"{script}.py"))
        }
        assert "simpick/score/split.py" in files or script == "simulator_split", script
        reached = {f for f in files if f.startswith("simpick/score/") or f.startswith("simpick/report/")}
        assert reached <= {"simpick/score/__init__.py", "simpick/score/split.py"}, (script, sorted(reached))
