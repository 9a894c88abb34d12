# The two entry points of the README. Both create .venv on first use.
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed

.PHONY: study test bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --upgrade pip
	$(VENV)/bin/pip install --quiet -e '.[test]'
	touch $(STAMP)

study: $(STAMP)
	$(VENV)/bin/snakemake --cores 2

test: $(STAMP)
	$(VENV)/bin/python -m pytest

clean:
	rm -rf results .snakemake
