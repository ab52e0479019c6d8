#!/usr/bin/env bash
# omnee-py in CI: a fresh venv, the pinned test dependencies, the package
# installed the way a user installs it (`pip install ./omnee-py`), then the
# pytest suite, which also compares `omnee.estimate` with the `omnee` binary.
# Run from the repository root: `bash omnee-py/ci.sh`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${OMNEE_PY_VENV:-$PWD/target/omnee-py-venv}"
python3 -m venv --clear "$venv"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -r omnee-py/requirements-test.txt
# The binary the agreement tests run (release, as a user would).
cargo build --locked --release -p omnee-cli
export OMNEE_BIN="$PWD/target/release/omnee"
# The user's command; the build environment's maturin comes from pyproject.toml.
"$venv/bin/python" -m pip install --quiet ./omnee-py
# Run from outside the source tree so that `import omnee` is the installed package.
cd omnee-py/tests
"$venv/bin/python" -m pytest -q -p no:cacheprovider .
