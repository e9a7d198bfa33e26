# The two commands of the README. Both set up the pinned environment in .venv first (idempotent).
VENV   := .venv
PYTHON := $(VENV)/bin/python
CHROMIUM := /usr/bin/chromium
# OpenGL for MuJoCo's offscreen renderer (the report's pictures): EGL through Mesa (MUJOCO_GL=egl, the default
# of harness/report/render.py), OSMesa as the fallback (MUJOCO_GL=osmesa)
GL_MARKER := /usr/lib/x86_64-linux-gnu/libEGL_mesa.so.0

.PHONY: setup check test bench

setup: $(VENV)/.installed $(CHROMIUM) $(GL_MARKER)

# Debian's headless browser for the report's browser test (tests/test_report_browser.py); skipped when present
$(CHROMIUM):
	apt-get update && apt-get install -y --no-install-recommends chromium

# Debian's Mesa EGL/OSMesa for headless rendering (skipped when present)
$(GL_MARKER):
	apt-get update && apt-get install -y --no-install-recommends libosmesa6 libegl1 libegl-mesa0 libgl1-mesa-dri

# The pinned packages are installed by uv (from the same registry as pip, pinned itself): it fetches and unpacks
# the wheels in parallel: the set-up took 13.5-17.0 s on fresh clones against 68-86 s with pip (drake, pinocchio, …);
# pip installs them when uv cannot (the same pins, slower).
UV_VERSION := 0.13.8

# Bytecode is written when a module is first imported: the project's commands run without PYTHONDONTWRITEBYTECODE
# (set on some machines), under which every process would compile again what it imports (3.7 s of a one-system
# check). Compiling everything at install instead took 15 s of the set-up, mostly for modules no command imports.
unexport PYTHONDONTWRITEBYTECODE

$(VENV)/.installed: pyproject.toml
	python3 -m venv $(VENV)
	$(PYTHON) -m pip install --quiet --quiet --disable-pip-version-check uv==$(UV_VERSION)
	$(VENV)/bin/uv pip install --quiet --python $(PYTHON) -e . || { \
	  echo "set-up: uv could not install the packages; installing them with pip instead" >&2; \
	  $(PYTHON) -m pip install --quiet --quiet --disable-pip-version-check --no-compile -e .; }
	$(PYTHON) -c "$(WARM_UP)"
	touch $@

# The bytecode of what the commands import, written once at the set-up: a command run by hand where
# PYTHONDONTWRITEBYTECODE is set would otherwise compile SymPy, NumPy, the engines' bindings … again at every start
# (`harness list` on a fresh clone there: 7.5-8.9 s, 3.5 s after this step, which takes 7.9 s once)
WARM_UP := from harness import catalogue, cli, run; catalogue.repository().systems(); \
  import harness.engines.pinocchio_engine, harness.engines.mujoco_engine, harness.compare.claims, \
  harness.scenes.trajectories, harness.report.site

# main job: exported files current, conformance of every system against both engines, the lecture's
# printed equations classified (errata report), every robot of example-robot-data in Pinocchio, MuJoCo and Drake,
# and our derivation of every fixed-base tree up to 7 DoF (fails on a disagreement without a proven cause), the hard
# cases at their full horizons (fails where a bound does not hold); results written to reports/, readable from
# reports/index.html. `harness main` runs `export --check`, `check`, `claims`, `robots --symbolic`, `hard` and
# `report` as those commands do, on one pool of two worker processes kept for all of them
# (harness.pool.workers_kept: no phase starts its own processes or loads and compiles again what the previous one
# had); a system's printed equations are classified in the job that checks it, on the numbers its check computed,
# and the robots' and hard cases' jobs follow in the pool while the claims are written. A failed check still gets
# its report built (the report shows the failure); the job then exits non-zero.
check: setup
	$(VENV)/bin/harness main --jobs 2 --out reports

# the test suite (fixed-seed hypothesis profile `ci`; HYPOTHESIS_PROFILE=long for the randomized one)
test: setup
	$(PYTHON) -m pytest -n 2 --dist loadgroup -q

# performance studies (on demand, not part of check/test): work-precision of the scenes, evaluation and
# derivation cost; writes reports/bench.json, reports/bench.md, reports/bench/*.svg. BENCH_ARGS=--quick for ~2 min
bench: setup
	$(VENV)/bin/harness bench --out reports $(BENCH_ARGS)
