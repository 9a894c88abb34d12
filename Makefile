# The two entry points of the README (study, test). Each target creates .venv on first use.
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed
# The set-up's independent parts (the study's venv, Newton's and Genesis' venvs, the Gazebo program) are built side
# by side: on a fresh machine they are mostly downloads (pip is quiet, so their lines hardly interleave; the suite's
# output is printed as it runs).
MAKEFLAGS += --jobs=4

.PHONY: study test test-fast docs bench clean lock schema engine-venvs study-eight gzphysics system-packages

# The system's packages in one apt pass (an apt-get update at most once): ODE (Debian libode8, and its headers for
# the binding's own tests), the browser the interactive report's test drives (tests/test_browser.py), sdformat 12's
# own reader (ign sdf, with which the settings files' tests convert the Gazebo tags) and what the Gazebo physics
# program builds against (GZ_PACKAGES). ODE and Chromium are required; the others, where they cannot be
# installed, leave out what needs them, and the study says so. Order-only prerequisite of the venv and the Gazebo
# program: it runs first, and never by itself makes them rebuild.
GZ_PACKAGES := cmake g++ libignition-physics-dev libignition-physics5-dartsim-plugin5 libignition-physics5-bullet-plugin5 \
  libsdformat-dev
system-packages:
	@need=; ldconfig -p | grep -q 'libode\.so\.8' || need="$$need libode8 libode-dev"; \
	command -v ign >/dev/null || need="$$need libsdformat-dev ignition-tools ruby sdformat-sdf"; \
	dpkg -s $(GZ_PACKAGES) >/dev/null 2>&1 || need="$$need $(GZ_PACKAGES)"; \
	browser=; command -v chromium >/dev/null || browser=chromium; \
	if [ -n "$$need$$browser" ]; then \
	  apt-get update -qq || echo "simpick: apt-get update failed"; \
	  [ -z "$$need" ] || apt-get install -y -qq --no-install-recommends $$need >/dev/null || \
	    echo "simpick: apt-get could not install some of:$$need"; \
	  [ -z "$$browser" ] || apt-get install -y -qq chromium >/dev/null || echo "simpick: apt-get could not install chromium"; \
	fi
	@ldconfig -p | grep -q 'libode\.so\.8' || { echo "simpick: install ODE 0.16 first: apt-get install libode8 libode-dev (as root)"; exit 1; }
	@command -v chromium >/dev/null || { echo "simpick: install Chromium first: apt-get install chromium (as root)"; exit 1; }
	@command -v ign >/dev/null || echo "simpick: ign sdf could not be installed; the study runs without it, tests/test_simulator_files.py fails"

$(STAMP): pyproject.toml constraints.txt | system-packages
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --upgrade pip
	$(VENV)/bin/pip install --quiet -c constraints.txt -e '.[test]'
	@# engines with platform-bound wheels: one that cannot install is left out of the study, which says so
	for extra in physx drake; do $(VENV)/bin/pip install --quiet -c constraints.txt -e ".[$$extra]" || \
	  echo "simpick: engine $$extra could not be installed; the study will run without it"; done
	touch $(STAMP)

study: $(STAMP) gzphysics
	$(VENV)/bin/snakemake --cores 2

# Gazebo (gz-sim)'s rows run Gazebo Fortress's own physics layer (Ignition Physics 5's dartsim plugin, sdformat 12:
# Debian's packages) through a small program, src/simpick/engines/gz, built into build/gz. A machine that cannot
# install or build it runs the study without the Gazebo rows, and the study says why (build/gz.log keeps the error).
gzphysics: build/gz/gzphysics_run

build/gz/gzphysics_run: src/simpick/engines/gz/gzphysics_run.cc src/simpick/engines/gz/CMakeLists.txt | system-packages
	mkdir -p build && : >build/gz.log
	{ dpkg -s $(GZ_PACKAGES) >/dev/null 2>&1 || { echo "system packages missing: $(GZ_PACKAGES)" >>build/gz.log; false; }; } && \
	  cmake -S src/simpick/engines/gz -B build/gz -DCMAKE_BUILD_TYPE=Release >>build/gz.log 2>&1 && \
	  cmake --build build/gz >>build/gz.log 2>&1 || \
	  { rm -f $@; echo "simpick: the Gazebo physics program could not be built (build/gz.log); the study will run without the Gazebo (gz-sim) rows"; }

# Newton and Genesis pin what the study cannot (newton[sim]: mujoco 3.17 against 4.0.0; genesis-world: pillow<12
# against 13, and torch): each gets a venv of its own, from the same Python (the study talks to it with pickle,
# simpick.engines.isolated). One that cannot install is left out, and the study says so: pip's last error lines
# are kept in .venv-<engine>.failed, which the study's report quotes. Torch is installed first,
# as the CPU build, so that genesis-world's resolution never pulls a CUDA torch.
TORCH ?= torch==2.13.0
engine-venvs: .venv-newton/.installed .venv-genesis/.installed

.venv-newton/.installed: envs/newton-constraints.txt
	rm -rf .venv-newton .venv-newton.failed && $(PYTHON) -m venv .venv-newton
	{ .venv-newton/bin/pip install --quiet --upgrade pip && \
	  .venv-newton/bin/pip install --quiet -c envs/newton-constraints.txt 'newton[sim]' pydantic numpy \
	    2> .venv-newton.log && touch $@; } || \
	  { rm -rf .venv-newton; tail -n 3 .venv-newton.log > .venv-newton.failed; \
	    echo "simpick: newton could not be installed (.venv-newton.failed); the study will run without it"; }

.venv-genesis/.installed: envs/genesis-constraints.txt
	rm -rf .venv-genesis .venv-genesis.failed && $(PYTHON) -m venv .venv-genesis
	{ .venv-genesis/bin/pip install --quiet --upgrade pip && .venv-genesis/bin/pip install --quiet '$(TORCH)' \
	    2> .venv-genesis.log && \
	  .venv-genesis/bin/pip install --quiet -c envs/genesis-constraints.txt genesis-world pydantic numpy \
	    2>> .venv-genesis.log && touch $@; } || \
	  { rm -rf .venv-genesis; tail -n 3 .venv-genesis.log > .venv-genesis.failed; \
	    echo "simpick: genesis could not be installed (.venv-genesis.failed); the study will run without it"; }

# The study with eight engines: config.yaml's six, Newton and Genesis (config/engines/newton_genesis.yaml)
study-eight: $(STAMP) engine-venvs gzphysics
	$(VENV)/bin/snakemake --cores 2 --configfile config.yaml config/engines/newton_genesis.yaml

# Two pytest-xdist workers, one a core: the tests of a module that share a fixture (a Snakemake run, an engine's
# records) run on one worker, as do those of one named group (tests/conftest.py: the session's tiny study).
PYTEST_PARALLEL ?= -n 2 --dist loadgroup

# The suite steps every registered engine, Newton and Genesis included: engine-venvs builds their venvs
# (measured: 72 s and 97 s from the registries of a CI machine). One that cannot be built is left out with the
# reason printed above, and its engine's tests fail (tests/test_engines.py checks every engine is installed).
test: $(STAMP) engine-venvs gzphysics
	$(VENV)/bin/python -m pytest $(PYTEST_PARALLEL) --durations=25

# The tests that start no Snakemake run and step neither DART nor Drake; `make test` runs them all.
test-fast: $(STAMP)
	$(VENV)/bin/python -m pytest $(PYTEST_PARALLEL) -m "not workflow and not slow"

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
