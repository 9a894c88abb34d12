"""The import graph of src/simpick has no cycle (issue 21): every import between simpick modules,
at the top of a module or inside a function, read from the source with ast (simpick.codeversion)."""

from simpick.codeversion import cycles, import_graph, modules


def test_the_package_has_no_import_cycle():
    graph = import_graph()
    assert len(graph) == len(modules()) > 40  # every module was read
    assert "simpick.realdata" in graph["simpick.workflow"]  # function-level imports are edges too
    found = cycles(graph)
    assert not found, "import cycles in src/simpick (cut one import of each): " + "; ".join(
        " -> ".join(cycle) for cycle in found)


def write_package(root, files):
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root / "simpick"


def test_a_cycle_through_a_function_level_import_is_found_and_named(tmp_path):
    pkg = write_package(tmp_path, {
        "simpick/__init__.py": "",
        "simpick/a.py": "from simpick.b import f\n",
        "simpick/b.py": "def f():\n    from simpick import c\n    return c.g()\n",
        "simpick/c.py": "import simpick.a\n\ndef g():\n    return 1\n",
        "simpick/sub/__init__.py": "from .leaf import x\n",
        "simpick/sub/leaf.py": "x = 1\n",
    })
    graph = import_graph(pkg)
    assert graph["simpick.sub"] == {"simpick.sub.leaf"}  # a relative import resolved
    assert cycles(graph) == [["simpick.a", "simpick.b", "simpick.c", "simpick.a"]]


def test_a_submodule_importing_its_package_that_imports_it_is_a_cycle(tmp_path):
    pkg = write_package(tmp_path, {
        "simpick/__init__.py": "",
        "simpick/report/__init__.py": "KEYS = ()\n\ndef build():\n    from simpick.report.load import load\n",
        "simpick/report/load.py": "def load():\n    from simpick.report import KEYS\n",
    })
    assert cycles(import_graph(pkg)) == [["simpick.report", "simpick.report.load", "simpick.report"]]
