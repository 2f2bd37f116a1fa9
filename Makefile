# Two commands from a fresh clone: `make demo` and `make test`.
# Each creates .venv with python3 -m venv when missing and installs the project into it.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.deformlab-installed
# JupyterHub's proxy, from the npm registry at the version tests/hub/package-lock.json pins.
HUB_PROXY := tests/hub/node_modules/.bin/configurable-http-proxy
SYSTEM_PACKAGES := bubblewrap libegl1 libgl1-mesa-dri chromium chromium-driver postgresql
export VTK_DEFAULT_OPENGL_WINDOW ?= vtkEGLRenderWindow

.PHONY: setup system-deps demo test test-fast bench meshes build release clean

setup: system-deps $(STAMP) $(HUB_PROXY)

# Pictures need EGL (libegl1, libgl1-mesa-dri); the grading sandbox needs bubblewrap; the
# PostgreSQL gradebook tests start a private server from Debian's postgresql (never its system service).
# JupyterHub's proxy needs Node.js and npm (from Debian when neither is there; a machine with
# NodeSource's nodejs has npm already).
system-deps:
	@if ! command -v npm >/dev/null; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing system packages: nodejs npm"; \
	    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm) >/dev/null \
	      || { echo "apt-get failed to install: nodejs npm" >&2; exit 1; }; \
	  else \
	    echo "warning: npm is missing (JupyterHub's proxy needs it); install it with: sudo apt-get install nodejs npm" >&2; \
	  fi; \
	fi
	@missing=""; for p in $(SYSTEM_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -z "$$missing" ]; then exit 0; fi; \
	if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "installing system packages:$$missing"; \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing) >/dev/null \
	    || { echo "apt-get failed to install:$$missing" >&2; exit 1; }; \
	else \
	  echo "warning: missing system packages:$$missing; install them with: sudo apt-get install$$missing" >&2; \
	fi

$(STAMP): pyproject.toml constraints.txt
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -c constraints.txt -e ".[dev]"
	@touch $@

# The JupyterHub course test (tests/hub) starts JupyterHub with this proxy.
$(HUB_PROXY): tests/hub/package.json tests/hub/package-lock.json
	@if command -v npm >/dev/null; then \
	  npm ci --prefix tests/hub --no-audit --no-fund --loglevel=error && touch $@; \
	else \
	  echo "warning: npm is missing: configurable-http-proxy is not installed, so the JupyterHub test will skip" >&2; \
	fi

demo: setup
	$(BIN)/python -m tests.demo

test: setup
	$(BIN)/python -m pytest -n 2 --dist loadscope --durations=20

bench: setup
	$(BIN)/python -m benchmarks

meshes: setup
	$(BIN)/python data/make_meshes.py

build: setup
	$(BIN)/deformlab build

release: setup
	$(BIN)/deformlab release

clean:
	rm -rf assignments/source assignments/release assignments/autograded assignments/feedback dist demo-out
