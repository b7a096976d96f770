# The two commands a newcomer needs: `make demo` and `make test`. Each does its own set-up.
VENV := .venv/bin
PYTEST_ARGS ?=

.PHONY: setup demo test lint bench clean

setup:
	bash tools/setup.sh

demo: setup
	$(VENV)/obstacle-fusion run --duration 20

test: setup
	bash tools/run_tests.sh $(PYTEST_ARGS)

lint: setup
	$(VENV)/ruff check host tools tests
	$(VENV)/ruff format --check host tools tests setup.py
	$(VENV)/mypy

bench: setup
	for b in tools/bench_*.py; do $(VENV)/python $$b || exit 1; done

clean:
	rm -rf firmware/build tools/emulator/build .pytest_cache
