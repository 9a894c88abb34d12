"""A job's code version comes from the functions it runs and what they import and name
(simpick.codeversion), read from the source: on a made-up package, which edits change it."""

import pytest

from simpick.codeversion import clear_cache, dispatch_entry, job_code, job_files, script_roots

PACKAGE = {
    "simpick/__init__.py": "",
    "simpick/io.py": "import json\n\n\ndef write(x):\n    return json.dumps(x)\n",
    "simpick/physics.py": "G = 9.81\n\n\ndef fall(t):\n    return G * t * t / 2\n\n\ndef unused():\n    return 0\n",
    "simpick/segments.py": "from simpick.physics import G\n\nCOLUMNS = ['a']\n",
    "simpick/jobs.py": (
        "from simpick.io import write\n\n\n"
        "def _lab(t):\n    from simpick import physics\n    return physics.fall(t)\n\n\n"
        "def _segments(t):\n    from simpick.segments import COLUMNS\n    return COLUMNS\n\n\n"
        "KINDS = {'lab': _lab, 'segments': _segments}\n\n\n"
        "def simulate_job(kind, t):\n    return write(KINDS[kind](t))\n\n\n"
        "def rtf_job(x):\n    return write(x)\n"),
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
    lab = dict(roots=("simpick.jobs:simulate_job", "simpick.jobs:_lab"), opaque=("simpick.jobs:KINDS",))
    seg = dict(roots=("simpick.jobs:simulate_job", "simpick.jobs:_segments"), opaque=("simpick.jobs:KINDS",))
    return {"lab": job_code(*lab["roots"], opaque=lab["opaque"], root=package),
            "segments": job_code(*seg["roots"], opaque=seg["opaque"], root=package),
            "rtf": job_code("simpick.jobs:rtf_job", root=package),
            "report": job_code("simpick.report.build:render", root=package)}


def changed(package, name, old, new):
    before = versions(package)
    edit(package, name, old, new)
    after = versions(package)
    return sorted(k for k in before if before[k] != after[k])


def test_files_follow_function_level_imports_and_module_attributes(package):
    names = lambda *roots, **kw: [p.relative_to(package).as_posix() for p in job_files(*roots, root=package, **kw)]
    assert names("simpick.jobs:_lab") == ["__init__.py", "io.py", "jobs.py", "physics.py"]
    assert names("simpick.jobs:simulate_job", "simpick.jobs:_lab", opaque=("simpick.jobs:KINDS",)) == [
        "__init__.py", "io.py", "jobs.py", "physics.py"]
    # without the table opaque, the dispatch reaches every kind
    assert "segments.py" in names("simpick.jobs:simulate_job")
    assert names("simpick.report.build:render") == ["__init__.py", "report/__init__.py", "report/build.py",
                                                    "report/templates/page.j2"]
    assert dispatch_entry("simpick.jobs", "KINDS", "segments", root=package) == "simpick.jobs:_segments"


def test_an_edit_changes_the_versions_of_the_jobs_that_run_it_only(package):
    # a module only the segments import: the segments' version alone
    assert changed(package, "simpick/segments.py", "COLUMNS = ['a']", "COLUMNS = ['a', 'b']") == ["segments"]
    # a function the lab reaches through a function-level import and an attribute
    assert changed(package, "simpick/physics.py", "G * t * t / 2", "0.5 * G * t * t") == ["lab"]
    # a function no job reaches: nobody
    assert changed(package, "simpick/physics.py", "return 0\n", "return 1\n") == []
    # a constant of a module both load (segments imports it at the top, the lab's fall reads it)
    assert changed(package, "simpick/physics.py", "G = 9.81", "G = 9.80665") == ["lab", "segments"]
    # one job function of a shared module: the other's version stays
    assert changed(package, "simpick/jobs.py", "return write(x)", "return write([x])") == ["rtf"]
    # the writer every job calls
    assert changed(package, "simpick/io.py", "json.dumps(x)", "json.dumps(x, indent=1)") == ["lab", "rtf",
                                                                                             "segments"]
    assert changed(package, "simpick/report/templates/page.j2", "{{ x }}", "{{ y }}") == ["report"]
    # a comment between definitions runs nothing
    assert changed(package, "simpick/jobs.py", "KINDS = {", "# the kinds\nKINDS = {") == []


def test_a_root_that_does_not_exist_is_an_error(package):
    with pytest.raises(KeyError, match="defines no 'simulate'"):
        job_code("simpick.jobs:simulate", root=package)
    with pytest.raises(KeyError, match="no module 'simpick.gone'"):
        job_code("simpick.gone:f", root=package)


def test_a_script_names_the_functions_it_runs(tmp_path):
    script = tmp_path / "s.py"
    script.write_text("from simpick.joblog import logged\nfrom simpick.simulate.jobs import simulate_job\nimport os\n")
    assert script_roots(script) == ("simpick.joblog:logged", "simpick.simulate.jobs:simulate_job")
