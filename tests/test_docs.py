"""The documentation: the mkdocs site builds with --strict (every page in the navigation, every link and
anchor resolves), the configuration page names every section of the config, and no document or config
comment, code or test points to a tracker nobody outside can see."""

import re
import subprocess
import sys

import yaml

from conftest import ROOT
from simpick.config import Study


def test_the_site_builds_strictly(tmp_path):
    out = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    assert (tmp_path / "site" / "index.html").is_file()
    nav = yaml.safe_load((ROOT / "mkdocs.yml").read_text())["nav"]
    pages = {page for entry in nav for page in entry.values()}
    assert pages == {p.name for p in (ROOT / "docs").glob("*.md")}, "a page missing from the navigation, or a stray"
    for page in pages:
        assert (tmp_path / "site" / ("" if page == "index.md" else page[:-3]) / "index.html").is_file(), page


def test_the_readme_fits_on_a_screen_and_its_links_resolve():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) < 150
    for target in re.findall(r"\]\(([^)#]+)\)", readme):
        if not target.startswith("http"):
            assert (ROOT / target).exists(), f"README links to {target}, which does not exist"


def test_the_configuration_page_names_every_section():
    page = (ROOT / "docs" / "configuration.md").read_text()
    missing = [name for name in Study.model_fields if f"`{name}`" not in page]
    assert not missing, f"docs/configuration.md does not describe {missing}"


# What the project's own documents, config, workflow files and code must not cite: the word "issue" and a number.
# An upstream project's tracker may be cited as a source, named right before it ("bullet3 issue #2590").
TRACKER = re.compile(r"\bissues?\s+#?\d+|\bissue-\d+", re.IGNORECASE)
UPSTREAM = re.compile(r"\b(?:bullet3|mujoco|drake|dart|sapien|physx|ode|newton)\s+(?:issues?|PR)\s+#\d+", re.IGNORECASE)
DOCUMENTS = [
    "README.md",
    "CHANGELOG.md",
    "mkdocs.yml",
    "docs",
    "config.yaml",
    "config",
    ".test",
    "Snakefile",
    "rules",
    "schemas",
    "profiles",
    "pyproject.toml",
    "Makefile",
    "src",  # code, comments, docstrings and the report's templates
    "tests",
    "scripts",
    "bench",
]


def tracker_numbers(line: str) -> list[str]:
    """The tracker numbers a line cites, upstream citations left out."""
    return TRACKER.findall(UPSTREAM.sub("", line))


def test_the_tracker_pattern_allows_only_upstream_citations():
    number = "issue" + " 17"  # built, so that this file passes its own check
    assert tracker_numbers(f"the gain ({number})") and tracker_numbers("see " + "Issues" + " #9 and 17")
    assert not tracker_numbers("upstream: bullet3 PR #4539 (open) and bullet3 " + "issue" + " #2590")
    assert tracker_numbers("bullet3 PR #4539 and " + "issue" + " #2590"), "an upstream name covers one citation only"


def test_no_tracker_numbers_in_documents_config_rules_or_code():
    found = []
    for name in DOCUMENTS:
        path = ROOT / name
        files = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
        for file in files:
            if file.suffix in (".png", ".pdf", ".pyc") or {"__pycache__", "simpick.egg-info"} & set(file.parts):
                continue
            for number, line in enumerate(file.read_text().splitlines(), 1):
                if tracker_numbers(line):
                    found.append(f"{file.relative_to(ROOT)}:{number}: {line.strip()[:100]}")
    assert not found, "say the reason, not a tracker number:\n" + "\n".join(found)


def test_every_config_field_has_a_description():
    """The config's models document themselves (the generated schema carries each description)."""
    import importlib
    import inspect
    import pkgutil

    from pydantic import BaseModel

    from simpick import config

    modules = [importlib.import_module(f"{config.__name__}.{m.name}") for m in pkgutil.iter_modules(config.__path__)]
    models = {m for module in modules for m in vars(module).values() if inspect.isclass(m) and issubclass(m, BaseModel)}
    missing = [
        f"{m.__name__}.{name}"
        for m in sorted(models, key=lambda m: m.__name__)
        if m.__module__.startswith(config.__name__ + ".")
        for name, field in m.model_fields.items()
        if not field.description
    ]
    assert not missing, f"simpick.config: give these fields Field(description=...): {missing}"
