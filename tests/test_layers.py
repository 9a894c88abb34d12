"""The stage packages are layers: a module imports only from its own layer or a lower one, at the top
of a module or inside a function alike (read from the source with ast: simpick.codeversion).

The order, lowest first, and why each sits where it does:

- core: the package, errors, seeds, writing a table (tables), the job log (joblog), the statistics
  of an IMU window shared by real and simulated data (imustats);
- inputs: the robot, terrains, motions, the paper's published figures and reference statistics;
- mechanics: the analytic Coulomb model of the robot (simpick.coulomb, simpick.slope; it reads the robot);
- real: real logs, datasets, their segments and turning windows (inputs too, read from the real robot);
- engines: the adapters and their registry;
- simulate: driving an engine over a case (and the jobs that do), traces;
- compare: traces against their reference, the paper's metrics and the real-data metrics;
- score: the paper's scores, the verdict, the published Table 11 recomputed;
- studies: validation, calibration and the sweep, which run the stages below for one question;
- report: reads every table the stages wrote, and formats;
- sources: the kinds of source of cases, read at planning time only (no job imports them);
- config: the study's settings, validated against what every stage allows (its models read
  the stages' constants and settings models);
- plan: what each rule depends on, its code version (codeversion), read by the Snakefile only;
- cli: the command-line helpers outside the workflow, which read a config as the Snakefile does
  (simpick.config.read_study) and call one study below.

Nothing in a lower layer names a higher one; a new import against the order fails here with the
module, the line and the layers. ``ALLOWED`` lists the imports against it that are known and owed a
fix (each with its reason); it is meant to be emptied, never extended.
"""

import ast

from conftest import ROOT
from simpick.codeversion import modules

LAYERS = (
    ("core", ("simpick", "simpick.errors", "simpick.seeds", "simpick.tables", "simpick.joblog", "simpick.imustats")),
    ("inputs", ("simpick.inputs",)),
    ("mechanics", ("simpick.coulomb", "simpick.slope")),
    ("real", ("simpick.real",)),
    ("engines", ("simpick.engines",)),
    ("simulate", ("simpick.simulate",)),
    ("compare", ("simpick.compare",)),
    ("score", ("simpick.score",)),
    ("studies", ("simpick.studies",)),
    ("report", ("simpick.report",)),
    ("sources", ("simpick.sources",)),
    ("config", ("simpick.config", "simpick.schema")),
    ("plan", ("simpick.plan", "simpick.codeversion")),
    ("cli", ("simpick.cli",)),
)

# (importing module, imported module): why it is still there. Known imports against the order, to
# be removed by moving what they need; an entry that no longer occurs fails the test too, so the
# list only shrinks.
ALLOWED: dict[tuple[str, str], str] = {}


def layer_of(module: str) -> int:
    """The index in LAYERS of the layer whose longest prefix names ``module``."""
    best = None
    for index, (_, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and (best is None or len(prefix) > best[1]):
                best = (index, len(prefix))
    assert best is not None, f"{module} is in no layer of tests/test_layers.py: add it to LAYERS"
    return best[0]


def imports(path, name):
    """(line, imported simpick module) of every import statement of a module, wherever it stands;
    ``from simpick.x import y`` imports simpick.x.y where that is a module, else simpick.x."""
    known = modules()
    tree = ast.parse(path.read_text(), filename=str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names if a.name.split(".")[0] == "simpick"]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([node.module] if node.module else []))
            if base.split(".")[0] != "simpick":
                continue
            found += [(node.lineno, f"{base}.{a.name}" if f"{base}.{a.name}" in known else base) for a in node.names]
    return found


def against_the_order():
    found = {}
    for name, path in modules().items():
        for line, target in imports(path, name):
            if layer_of(target) > layer_of(name):
                found.setdefault((name, target), set()).add(line)
    return {pair: sorted(lines) for pair, lines in found.items()}


def test_every_module_has_a_layer():
    assert len(modules()) > 40
    for name in modules():
        layer_of(name)


def test_no_module_imports_from_a_higher_layer():
    found = against_the_order()
    new = {pair: lines for pair, lines in found.items() if pair not in ALLOWED}
    assert not new, "imports against the layers (tests/test_layers.py):\n" + "\n".join(
        f"  {a} (line {', '.join(map(str, lines))}, {LAYERS[layer_of(a)][0]}) imports {b} ({LAYERS[layer_of(b)][0]})"
        for (a, b), lines in sorted(new.items())
    )
    gone = sorted(set(ALLOWED) - set(found))
    assert not gone, f"no longer imported, remove from ALLOWED: {gone}"


def test_a_job_dispatch_table_names_its_own_or_a_lower_layer():
    """Modules a job imports by name (a source kind's prepare function, an engine adapter) are in
    the job's layer or below: importing by name must not hide an import against the order."""
    from simpick.engines import ADAPTERS, REFERENCE_MODELS
    from simpick.simulate.jobs import PREPARE

    for spec in PREPARE.values():
        assert layer_of(spec.split(":")[0]) <= layer_of("simpick.simulate.jobs"), spec
    for spec in {**ADAPTERS, **REFERENCE_MODELS}.values():
        assert layer_of(spec.split(":")[0]) == layer_of("simpick.engines"), spec


def test_scripts_run_jobs_of_the_stages_only():
    """A workflow script imports a stage's job (and the job log), never planning code."""
    for script in sorted((ROOT / "scripts").glob("*.py")):
        for line, target in imports(script, "scripts"):
            assert layer_of(target) < layer_of("simpick.sources"), (script.name, line, target)


# The stages downstream of the readers, and planning: a unit reaches them in the form every reader gives
# (simpick.real.steps, the canonical log), never by which dataset it came from.
DOWNSTREAM = ("simulate", "compare", "score", "studies", "report", "plan")
# A dataset's own modules: its reader (simpick.real) and its source (simpick.sources: planning reaches it by
# its kind, simpick.sources.module, not by name).
DATASET_MODULES = {"drive": ("simpick.real.drive", "simpick.real.logs.drive", "simpick.sources.drive")}


def dataset_specific(name, path):
    """(dataset, why) of every way a module is one dataset's: its name, or an import of that dataset's
    reader or source module."""
    found = []
    for dataset, owned in DATASET_MODULES.items():
        if dataset in name.rpartition(".")[2]:
            found.append((dataset, f"is named {name.rpartition('.')[2]!r}"))
        for line, target in imports(path, name):
            if any(target == m or target.startswith(m + ".") or target.startswith(m + "_") for m in owned):
                found.append((dataset, f"imports {target} (line {line})"))
    return found


def test_no_stage_downstream_of_the_readers_is_one_datasets():
    """Every real dataset is a source whose reader yields the same units: nothing in simulate, compare,
    score, studies, report or plan asks which dataset a unit came from (labels aside), so no module there
    is named for a dataset or imports its reader or source module."""
    downstream = {index for index, (layer, _) in enumerate(LAYERS) if layer in DOWNSTREAM}
    found = {
        name: why
        for name, path in modules().items()
        if layer_of(name) in downstream and (why := dataset_specific(name, path))
    }
    assert not found, "dataset-specific modules downstream of the readers:\n" + "\n".join(
        f"  {name}: {dataset} ({reason})" for name, reasons in sorted(found.items()) for dataset, reason in reasons
    )


def test_the_dataset_check_sees_a_dataset_module(tmp_path):
    """The check above is not vacuous: a module named for DRIVE, or importing its reader, is found."""
    named = tmp_path / "drive_tables.py"
    named.write_text("x = 1\n")
    assert dataset_specific("simpick.compare.drive_tables", named) == [("drive", "is named 'drive_tables'")]
    importing = tmp_path / "errors.py"
    importing.write_text("from simpick.real.logs.drive_files import PICKLE\nimport simpick.sources.drive\n")
    reasons = [why for _, why in dataset_specific("simpick.compare.errors", importing)]
    assert reasons == ["imports simpick.real.logs.drive_files (line 1)", "imports simpick.sources.drive (line 2)"]
    # the readers' own modules are where a dataset's quirks belong
    assert layer_of("simpick.real.drive") < min(index for index, (layer, _) in enumerate(LAYERS) if layer in DOWNSTREAM)
