"""The import graph of src/simpick has no cycle: every import between simpick modules,
at the top of a module or inside a function, read from the source with ast (simpick.codeversion)."""

from simpick.codeversion import cycles, import_graph, modules


def test_the_package_has_no_import_cycle():
    graph = import_graph()
    assert len(graph) == len(modules()) > 40  # every module was read
    assert "simpick.compare.real" in graph["simpick.compare.jobs"]  # function-level imports are edges too
    found = cycles(graph)
    assert not found, "import cycles in src/simpick (cut one import of each): " + "; ".join(
        " -> ".join(cycle) for cycle in found
    )


def write_package(root, files):
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root / "simpick"


def test_a_cycle_through_a_function_level_import_is_found_and_named(tmp_path):
    pkg = write_package(
        tmp_path,
        {
            "simpick/__init__.py": "",
            "simpick/a.py": "from simpick.b import f\n",
            "simpick/b.py": "def f():\n    from simpick import c\n    return c.g()\n",
            "simpick/c.py": "import simpick.a\n\ndef g():\n    return 1\n",
            "simpick/sub/__init__.py": "from .leaf import x\n",
            "simpick/sub/leaf.py": "x = 1\n",
        },
    )
    graph = import_graph(pkg)
    assert graph["simpick.sub"] == {"simpick.sub.leaf"}  # a relative import resolved
    assert cycles(graph) == [["simpick.a", "simpick.b", "simpick.c", "simpick.a"]]


def test_a_submodule_importing_its_package_that_imports_it_is_a_cycle(tmp_path):
    pkg = write_package(
        tmp_path,
        {
            "simpick/__init__.py": "",
            "simpick/report/__init__.py": "KEYS = ()\n\ndef build():\n    from simpick.report.load import load\n",
            "simpick/report/load.py": "def load():\n    from simpick.report import KEYS\n",
        },
    )
    assert cycles(import_graph(pkg)) == [["simpick.report", "simpick.report.load", "simpick.report"]]


# the packages of the data flow's stages (docs/conventions.md "Layout"); a job function lives in one of them
STAGES = ("inputs", "real", "simulate", "compare", "score", "studies", "report")


def test_every_job_a_script_runs_lives_in_a_stage_package():
    import ast

    from conftest import ROOT

    helpers = {"simpick.joblog", "simpick.simulate.watchdog"}  # the log wrapper, the watchdog's limit
    found = {
        script.name: [
            node.module
            for node in ast.walk(ast.parse(script.read_text()))
            if isinstance(node, ast.ImportFrom)
            and (node.module or "").startswith("simpick")
            and node.module not in helpers
        ]
        for script in sorted((ROOT / "scripts").glob("*.py"))
    }
    assert found and all(len(modules) == 1 for modules in found.values()), found  # one job module a script
    outside = {
        name: module for name, (module,) in found.items() if module == "simpick" or module.split(".")[1] not in STAGES
    }
    assert not outside, f"scripts running a job outside the stage packages {STAGES}: {outside}"
    assert all((ROOT / "src" / "simpick" / stage / "__init__.py").exists() for stage in STAGES)
    defined = [
        p.relative_to(ROOT / "src" / "simpick")
        for p in (ROOT / "src" / "simpick").rglob("*.py")
        if any(line.startswith("def ") and "_job(" in line for line in p.read_text().splitlines())
    ]
    assert defined and all(len(p.parts) > 1 and p.parts[0] in STAGES for p in defined), defined
