# shellcheck shell=bash
# Sourced by dist/build.sh and dist/check.sh: paths, logging, and the tools
# the packaging needs, each installed where it is missing (a fresh CI machine
# has none of them) and kept, outside the repository, for the next run:
#   - Debian: cmake, pkg-config, a C compiler, libssl-dev (cargo-c links it);
#   - PyPI, in a venv: maturin, ziglang (its `--zig` linker targets glibc
#     2.17 without Docker), auditwheel, abi3audit (requirements-tools.txt);
#   - crates.io: cargo-c, pinned (0.10.24 is the newest that builds with
#     rustc 1.95; Debian's 0.9 cannot read this workspace's manifests).
#     It compiles cargo itself: only its `cargo-cinstall` is built, in the
#     dev profile without debug information or incremental state, since one
#     install of a small library needs no optimised cargo (4.6 min of CPU
#     here; 6.9 min with the dev profile's debug information and
#     incremental state).
# OMNEE_DIST_TOOLS moves the tools (default: ~/.cache/omnee-dist).
set -euo pipefail

DIST="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$DIST/.." && pwd)"
TOOLS="${OMNEE_DIST_TOOLS:-${XDG_CACHE_HOME:-$HOME/.cache}/omnee-dist}"
CARGO_C_VERSION=0.10.24

log() { printf '== dist [%4ds]: %s\n' "$SECONDS" "$*"; }
fail() { echo "dist: $*" >&2; exit 1; }

# The cargo target directory, honouring CARGO_TARGET_DIR and configuration.
target_dir() {
  (cd "$ROOT" && cargo metadata --format-version 1 --no-deps --locked) |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])'
}

# The version of workspace package $1.
package_version() {
  (cd "$ROOT" && cargo metadata --format-version 1 --no-deps --locked) |
    python3 -c 'import json, sys
print(next(p["version"] for p in json.load(sys.stdin)["packages"] if p["name"] == sys.argv[1]))' "$1"
}

# The one file in directory $1 matching glob $2 (fails on none or several).
one_file() {
  # shellcheck disable=SC2206 # $2 is a glob
  local matches=("$1"/$2)
  if [ "${#matches[@]}" -ne 1 ] || [ ! -f "${matches[0]}" ]; then
    fail "expected one $2 in $1, found: ${matches[*]}"
  fi
  echo "${matches[0]}"
}

# Debian packages, given as command:package (a command that must exist) or
# :package (a package that must be installed).
ensure_debian() {
  local missing=() spec command package
  for spec in "$@"; do
    command="${spec%%:*}" package="${spec#*:}"
    if [ -n "$command" ]; then
      command -v "$command" >/dev/null && continue
    else
      dpkg -s "$package" >/dev/null 2>&1 && continue
    fi
    missing+=("$package")
  done
  [ "${#missing[@]}" -eq 0 ] && return
  log "apt-get install ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
}

# The venv of PyPI tools; puts it first on PATH (maturin finds zig as
# `python -m ziglang` of the interpreter on PATH).
ensure_python_tools() {
  local venv="$TOOLS/venv"
  if ! cmp -s "$DIST/requirements-tools.txt" "$venv/requirements-tools.txt"; then
    log "PyPI tools into $venv (requirements-tools.txt)"
    python3 -m venv --clear "$venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
      -r "$DIST/requirements-tools.txt"
    cp "$DIST/requirements-tools.txt" "$venv/requirements-tools.txt"
  fi
  PATH="$venv/bin:$PATH"
}

# cargo-c's `cargo cinstall`, on PATH.
ensure_cargo_c() {
  local root="$TOOLS/cargo-c-$CARGO_C_VERSION"
  if ! "$root/bin/cargo-cinstall" cinstall --version 2>/dev/null | grep -q "^cargo-c $CARGO_C_VERSION+"; then
    ensure_debian pkg-config:pkg-config :libssl-dev cc:gcc
    log "cargo install cargo-c $CARGO_C_VERSION (cargo-cinstall, dev profile: about 5 min of CPU)"
    local start=$SECONDS
    CARGO_PROFILE_DEV_DEBUG=false CARGO_INCREMENTAL=0 \
      cargo install cargo-c --version "=$CARGO_C_VERSION" --locked --debug --bin cargo-cinstall \
      --root "$root"
    log "installed cargo-c in $((SECONDS - start)) s"
  fi
  PATH="$root/bin:$PATH"
}
