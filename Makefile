# Two commands from a fresh clone: `make demo` and `make test`.
# Each creates .venv with python3 -m venv when missing and installs the project into it.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.deformlab-installed
SYSTEM_PACKAGES := bubblewrap libegl1 libgl1-mesa-dri chromium chromium-driver postgresql
export VTK_DEFAULT_OPENGL_WINDOW ?= vtkEGLRenderWindow

.PHONY: setup system-deps demo test test-fast bench meshes build release clean

setup: system-deps $(STAMP)

# Pictures need EGL (libegl1, libgl1-mesa-dri); the grading sandbox needs bubblewrap; the
# PostgreSQL gradebook tests start a private server from Debian's postgresql (never its system service).
system-deps:
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

demo: setup
	$(BIN)/deformlab demo

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
