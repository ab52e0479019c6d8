#!/usr/bin/env bash
# omnee-py in CI: a fresh venv, the pinned test dependencies, the package
# installed the way a user installs it (`pip install ./omnee-py`), the
# wheel's size, the type stub checked by `mypy --strict` and against the
# module by `mypy.stubtest`, then the pytest suite,
# which also compares `omnee.estimate` with the `omnee` binary.
# Run from the repository root: `bash omnee-py/ci.sh`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${OMNEE_PY_VENV:-$PWD/target/omnee-py-venv}"
python3 -m venv --clear "$venv"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -r omnee-py/requirements-test.txt
# The binary the agreement tests run (release, as a user would), wherever
# cargo puts it (CARGO_TARGET_DIR or target/).
cargo build --locked --release -p omnee-cli
target_dir="$(cargo metadata --format-version 1 --no-deps --locked |
  "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
export OMNEE_BIN="$target_dir/release/omnee"
# The user's command, `pip install ./omnee-py`, in two steps: the wheel a
# user would build (the build environment's maturin comes from
# pyproject.toml), checked to be stripped (at most 3 MB), then installed.
wheels="$(mktemp -d)"
trap 'rm -rf "$wheels"' EXIT
"$venv/bin/python" -m pip wheel --quiet --no-deps --wheel-dir "$wheels" ./omnee-py
"$venv/bin/python" - "$wheels" <<'PY'
import pathlib, sys
(wheel,) = pathlib.Path(sys.argv[1]).glob("omnee-*.whl")
size = wheel.stat().st_size
print(f"{wheel.name}: {size:,} bytes")
assert size <= 3_000_000, f"the wheel is {size:,} bytes; allowed: at most 3,000,000"
PY
"$venv/bin/python" -m pip install --quiet "$wheels"/omnee-*.whl
# The stub and the package under `mypy --strict`, with a script that uses
# the API as a user would (tests/typing_check.py).
(cd omnee-py && "$venv/bin/python" -m mypy --strict --no-incremental \
  python/omnee tests/typing_check.py)
# Run from outside the source tree so that `import omnee` is the installed package.
cd omnee-py/tests
# The installed stub against the installed module: every name, signature
# and default as the extension defines them.
"$venv/bin/python" -m mypy.stubtest omnee._omnee
CI="${CI:-true}" "$venv/bin/python" -m pytest -q -p no:cacheprovider .
