#!/usr/bin/env bash
# The Mitsuba 3 example, one command from the repository root:
#   bash examples/mitsuba/run.sh            # self-test, then the equal-time runs and the figure
#   bash examples/mitsuba/run.sh ARGS...    # compare.py ARGS... only (e.g. --selftest, --light above)
# Installs the pinned Mitsuba, Dr.Jit and numpy from PyPI and omnee's Python
# package (./omnee-py, built with the Rust toolchain) into its own venv,
# target/mitsuba-example-venv. Not run by CI (CI installs no Mitsuba).
#
# Mitsuba's array variant (llvm_ad_rgb) needs an LLVM shared library that
# can compile volpath's kernels: Debian 12's LLVM 15 cannot ("Cannot
# select: fmaximum"), LLVM 19 can. DRJIT_LIBLLVM_PATH, if set, is used as
# it is; otherwise the newest libLLVM 16 or later in the system's library
# folders, and as root on Debian `apt-get install libllvm19` if none is there.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv="$PWD/target/mitsuba-example-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet mitsuba==3.9.1 drjit==1.5.0 numpy==2.4.6
"$venv/bin/python" -m pip install --quiet ./omnee-py

find_llvm() {
  local lib best="" best_version=0 version
  for lib in /usr/lib/*/libLLVM-[0-9]*.so /usr/lib/*/libLLVM.so.[0-9]* /usr/lib/llvm-*/lib/libLLVM*.so*; do
    [ -e "$lib" ] || continue
    # The major version: from the file's name (libLLVM-19.so, libLLVM.so.19.1),
    # else from its folder (/usr/lib/llvm-19/lib/libLLVM.so).
    version="$(basename "$lib" | grep -oE '[0-9]+' | head -n 1 || true)"
    [ -n "$version" ] || version="$(echo "$lib" | grep -oE 'llvm-[0-9]+' | grep -oE '[0-9]+' | head -n 1 || true)"
    [ -n "$version" ] || continue
    if [ "$version" -ge 16 ] && [ "$version" -gt "$best_version" ]; then
      best="$lib" best_version="$version"
    fi
  done
  echo "$best"
}
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  DRJIT_LIBLLVM_PATH="$(find_llvm)"
  if [ -z "$DRJIT_LIBLLVM_PATH" ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "no libLLVM >= 16 found: apt-get install libllvm19" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19 >/dev/null
    DRJIT_LIBLLVM_PATH="$(find_llvm)"
  fi
  if [ -z "$DRJIT_LIBLLVM_PATH" ]; then
    echo "no libLLVM >= 16 found: install one (Debian 12: apt-get install libllvm19) or set DRJIT_LIBLLVM_PATH" >&2
    exit 1
  fi
fi
export DRJIT_LIBLLVM_PATH
echo "Dr.Jit's LLVM: $DRJIT_LIBLLVM_PATH" >&2

run() { "$venv/bin/python" examples/mitsuba/compare.py "$@"; }
if [ "$#" -gt 0 ]; then
  run "$@"
  exit
fi
run --selftest
run --light inside --seconds 10 --reference-spp 16384 --figure docs/figures/mitsuba-equal-time.png \
  --json target/mitsuba-example-inside.json
run --light above --seconds 10 --reference-spp 16384 --json target/mitsuba-example-above.json
