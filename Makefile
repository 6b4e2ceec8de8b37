# Two commands on a fresh machine: `make serve` runs the service, `make test` runs the tests.
# Both first build .venv from the pinned requirements-dev.lock (runtime pins from
# requirements.lock plus the development tools) and install this project into it, editable
# and without dependencies, so `import camcore` works from any folder with .venv's python.
# The container installs requirements.lock alone (Dockerfile).
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: serve test test-fast test-tools lint bench openapi

# the quick tier: no external program (Chromium, LibreOffice, FreeCAD, node, wrk, a client generator, the
# image's, the image built), no bench, no fuzz or property run, no docs block run by a program or a live server, no memory soak
FAST_TESTS := not (chromium or libreoffice or freecad or node or wrk or generator or container or image or bench or fuzz or property or docs or soak)

$(VENV)/.installed: requirements.lock requirements-dev.lock pyproject.toml
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -r requirements-dev.lock
	$(VENV)/bin/pip install --no-deps --no-build-isolation -e .
	touch $@

serve: $(VENV)/.installed
	$(PY) -m service

# the programs the tests run (Chromium, wrk, LibreOffice, node): installed only when missing
test-tools:
	VENV=$(VENV) scripts/install_test_tools.sh

# the gates: ruff clean on every Python file (the code, its tests, the bench, the scripts, the
# clients' recipes), mypy (with the pydantic plugin, pyproject.toml) on the code
lint: $(VENV)/.installed
	$(VENV)/bin/ruff check .
	$(VENV)/bin/mypy camcore service

# the tests that time or weigh the machine (bench ratios, load with wrk, the memory soak, the image's
# pod, a computation against its estimate or deadline) run alone; everything else first on both cores.
# Both parts run; either failing fails the target.
ALONE_TESTS := bench or wrk or soak or image or timing

test: test-tools $(VENV)/.installed lint
	PYTHONDONTWRITEBYTECODE= $(PY) -m pytest -n 2 --dist worksteal -m "not ($(ALONE_TESTS))"; shared=$$?; \
	$(PY) -m pytest -m "$(ALONE_TESTS)"; alone=$$?; \
	test $$shared -eq 0 -a $$alone -eq 0

# on both cores (pytest-xdist, an idle worker taking tests queued for the other); the fuzz module is not even collected (every test of it is fuzz, and
# reading the document into schemathesis is seconds of each worker's start); pytest keeps the test
# modules it rewrote (its asserts) as bytecode, half of each worker's start, where the environment
# would forbid writing it (PYTHONDONTWRITEBYTECODE)
test-fast: $(VENV)/.installed
	PYTHONDONTWRITEBYTECODE= $(PY) -m pytest -n 2 --dist worksteal -m "$(FAST_TESTS)" --ignore=tests/service/test_fuzz.py

bench: $(VENV)/.installed
	$(PY) -m bench

openapi: $(VENV)/.installed
	$(PY) -m scripts.export_openapi
