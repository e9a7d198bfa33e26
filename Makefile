# The two commands of the README. Both set up the pinned environment in .venv first (idempotent).
VENV   := .venv
PYTHON := $(VENV)/bin/python

.PHONY: setup check test

setup: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	python3 -m venv $(VENV)
	$(PYTHON) -m pip install --quiet --disable-pip-version-check -e .
	touch $@

# main job: exported files current, conformance of every system against both engines, the lecture's
# printed equations classified (errata report); results written to reports/
check: setup
	$(VENV)/bin/harness export --check
	$(VENV)/bin/harness check --out reports
	$(VENV)/bin/harness claims --out reports

# the test suite (fixed-seed hypothesis profile `ci`; HYPOTHESIS_PROFILE=long for the randomized one)
test: setup
	$(PYTHON) -m pytest -n 2 -q
