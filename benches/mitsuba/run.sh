#!/usr/bin/env bash
# The Mitsuba 3 head-to-head, one command from the repository root:
#   bash benches/mitsuba/run.sh [head_to_head.py options, e.g. --seconds 8]
# Installs Mitsuba from PyPI into its own venv (target/mitsuba-venv), builds
# the omnee binary (release) and prints the table of docs/benchmarks.md.
# Not run by CI.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv="$PWD/target/mitsuba-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet mitsuba==3.9.1 drjit==1.5.0 numpy==2.4.6 scipy==1.17.1
cargo build --locked --release -p omnee-cli
"$venv/bin/python" benches/mitsuba/head_to_head.py --omnee "$PWD/target/release/omnee" "$@"
