#!/usr/bin/env bash
# OMNEE in a Mitsuba 3 scene, from a checkout, one command from the
# repository root:
#   bash examples/mitsuba/run.sh [integrator] [spp]
# Installs Mitsuba 3.9.1, Dr.Jit 1.5.0 and omnee (pip install ./omnee-py,
# a Rust toolchain builds it) into target/omnee-mitsuba-venv, finds an LLVM
# for Dr.Jit (Debian 12's LLVM 15 cannot compile volpath's kernels; it
# installs Debian's libllvm19 if missing) and renders fog.xml into fog.exr.
set -euo pipefail
cd "$(dirname "$0")/../.."
source omnee-py/tests-mitsuba/llvm19.sh
venv="$PWD/target/omnee-mitsuba-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet -r omnee-py/tests-mitsuba/requirements.txt
"$venv/bin/python" -m pip install --quiet ./omnee-py
"$venv/bin/python" examples/mitsuba/render.py "$@"
