# The two entry points of the README. Both create .venv on first use.
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed

.PHONY: study test bench clean

$(STAMP): pyproject.toml
	@# ODE comes from the system (Debian libode8); headers for the binding's own tests
	ldconfig -p | grep -q 'libode\.so\.8' || { apt-get update && apt-get install -y --no-install-recommends libode8 libode-dev; } || \
	  { echo "simpick: install ODE 0.16 first: apt-get install libode8 libode-dev (as root)"; exit 1; }
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --upgrade pip
	$(VENV)/bin/pip install --quiet -e '.[test]'
	touch $(STAMP)

study: $(STAMP)
	$(VENV)/bin/snakemake --cores 2

test: $(STAMP)
	$(VENV)/bin/python -m pytest

bench: $(STAMP)
	$(VENV)/bin/python bench/run.py

clean:
	rm -rf results .snakemake
