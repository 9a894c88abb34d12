# The two entry points of the README (study, test). Each target creates .venv on first use.
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed

.PHONY: study test test-fast docs bench clean lock schema

$(STAMP): pyproject.toml constraints.txt
	@# ODE comes from the system (Debian libode8); headers for the binding's own tests
	ldconfig -p | grep -q 'libode\.so\.8' || { apt-get update && apt-get install -y --no-install-recommends libode8 libode-dev; } || \
	  { echo "simpick: install ODE 0.16 first: apt-get install libode8 libode-dev (as root)"; exit 1; }
	@# the browser the interactive report's test drives (tests/test_browser.py): the system's Chromium
	command -v chromium >/dev/null || { apt-get update && apt-get install -y chromium; } || \
	  { echo "simpick: install Chromium first: apt-get install chromium (as root)"; exit 1; }
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --upgrade pip
	$(VENV)/bin/pip install --quiet -c constraints.txt -e '.[test]'
	@# engines with platform-bound wheels: one that cannot install is left out of the study, which says so
	for extra in physx drake; do $(VENV)/bin/pip install --quiet -c constraints.txt -e ".[$$extra]" || \
	  echo "simpick: engine $$extra could not be installed; the study will run without it"; done
	touch $(STAMP)

study: $(STAMP)
	$(VENV)/bin/snakemake --cores 2

test: $(STAMP)
	$(VENV)/bin/python -m pytest

# The tests that start no Snakemake run and step neither DART nor Drake; `make test` runs them all.
test-fast: $(STAMP)
	$(VENV)/bin/python -m pytest -m "not workflow and not slow"

# The documentation site (docs/, mkdocs.yml) into site/
docs: $(STAMP)
	$(VENV)/bin/mkdocs build --strict

bench: $(STAMP)
	$(VENV)/bin/python bench/run.py

# The config's JSON schema from the pydantic models (tests/test_schema.py fails when it is stale).
schema: $(STAMP)
	$(VENV)/bin/python -m simpick.schema schemas/config.schema.json

clean:
	rm -rf results .snakemake

# Re-resolve the dependencies of pyproject.toml from the registry and pin what comes out.
lock:
	rm -rf .lock-venv && $(PYTHON) -m venv .lock-venv
	.lock-venv/bin/pip install --quiet --upgrade pip
	.lock-venv/bin/pip install --quiet -e '.[test,physx,drake]'
	{ echo "# Pinned versions for 'make' (pip install -c constraints.txt): what the test suite last passed with."; \
	  echo "# Refresh: make lock (resolves pyproject.toml afresh in a scratch venv and freezes it), then make test."; \
	  .lock-venv/bin/pip freeze --exclude-editable; } > constraints.txt
	rm -rf .lock-venv
