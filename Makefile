# Two commands on a fresh machine: `make serve` runs the service, `make test` runs the tests.
# Both first build .venv from the pinned requirements.lock (the same install step the
# Dockerfile runs); code is used in place from this folder.
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: serve test bench openapi

$(VENV)/.installed: requirements.lock
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -r requirements.lock
	touch $@

serve: $(VENV)/.installed
	$(PY) -m service

test: $(VENV)/.installed
	$(PY) -m pytest

bench: $(VENV)/.installed
	$(PY) -m bench

openapi: $(VENV)/.installed
	$(PY) -m scripts.export_openapi
