#!/usr/bin/env bash
# Uses each artefact that dist/build.sh put in OUT as its users would, with
# nothing from the source tree but the programs that exercise them:
#   python  the wheel installed from the file alone (pip --no-index
#           --no-deps; numpy from the registry) into CPython 3.9, 3.10, 3.12
#           and 3.13, the sdist built and installed by pip into 3.11; each
#           then samples (consumer/sample.py). A missing interpreter fails.
#   c       omnee-ffi/examples/estimate.c built with `pkg-config --cflags
#           --libs omnee`, with CMake's find_package(omnee) and omnee::omnee
#           (consumer/c), both against the shared library, and linked with
#           libomnee.a by `pkg-config --static`; the SONAME and its links;
#           the library exports the header's omnee_* functions and nothing else.
#   crates  the packaged omnee-core builds for thumbv7em-none-eabihf on its
#           own; the packaged omnee-cli, installed by `cargo install --path`
#           against the packaged libraries, renders the default scene.
#   web     the static folder, served by `python3 -m http.server`, passes
#           the demo's end-to-end test (omnee-wasm/e2e).
# Usage, from anywhere: bash dist/check.sh OUT
# Runs every check, then prints "dist: N passed, N failed"; exits 1 if any
# failed. Installs what it needs (dist/tools.sh, omnee-wasm/build.sh).
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/tools.sh"
[ $# -eq 1 ] || { echo "usage: bash dist/check.sh OUT" >&2; exit 2; }
OUT="$(cd "$1" && pwd)"
cd "$ROOT"
SECONDS=0
# Scratch space outside the repository (a package unpacked inside it would
# be taken for a member of its workspace); build outputs that later runs
# reuse go to the target directory.
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
TARGET="$(target_dir)/dist-check"
PIP=(--quiet --disable-pip-version-check)

passed=0 failed=0 failures=()
# Runs check function $1 (with errexit, in a subshell) and counts it.
run_check() {
  log "check: $*"
  set +e
  (set -e; "$@")
  local rc=$?
  set -e
  if [ "$rc" -eq 0 ]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)) failures+=("$*")
    log "FAILED: $*"
  fi
}

# CPython $1 (e.g. 3.9): pyenv's, else one on PATH that runs (a pyenv
# shim of a version not selected does not).
find_python() {
  local python
  for python in "${PYENV_ROOT:-$HOME/.pyenv}"/versions/"$1".*/bin/python"$1" \
    "$(command -v "python$1" || true)"; do
    [ -x "$python" ] && "$python" -c '' 2>/dev/null && { echo "$python"; return; }
  done
  true
}

# A venv of CPython $1 in $2; fails, naming the version, if it is missing.
make_venv() {
  local python
  python="$(find_python "$1")"
  [ -n "$python" ] || fail "CPython $1 is missing (looked in pyenv's versions and on PATH)"
  "$python" -m venv "$2"
}

# consumer/sample.py with venv $1's interpreter, run outside the source tree.
sample() {
  (cd "$WORK" && "$1/bin/python" "$DIST/consumer/sample.py")
}

check_wheel_contents() {
  local wheel
  wheel="$(one_file "$OUT/python" 'omnee-*.whl')"
  # Every file of the package's source folder, and the licence texts.
  python3 - "$wheel" omnee-py/python <<'PY'
import pathlib, sys, zipfile
wheel, source = sys.argv[1], pathlib.Path(sys.argv[2])
names = set(zipfile.ZipFile(wheel).namelist())
files = [p.relative_to(source).as_posix() for p in (source / "omnee").rglob("*")
         if p.is_file() and "__pycache__" not in p.parts]
missing = [f for f in files if f not in names]
missing += [f"licenses/{n}" for n in ("LICENSE-MIT", "LICENSE-APACHE")
            if not any(x.endswith(f".dist-info/licenses/{n}") for x in names)]
assert not missing, f"the wheel lacks {missing}"
print(f"{pathlib.Path(wheel).name}: {len(files)} files of omnee-py/python/omnee and both licences")
PY
}

check_wheel() {
  local venv="$WORK/wheel-$1"
  make_venv "$1" "$venv"
  "$venv/bin/python" -m pip install "${PIP[@]}" --no-index --no-deps "$OUT"/python/omnee-*.whl
  "$venv/bin/python" -m pip install "${PIP[@]}" -r "$DIST/consumer/requirements.txt"
  sample "$venv"
}

check_sdist() {
  local venv="$WORK/sdist"
  make_venv 3.11 "$venv"
  "$venv/bin/python" -m pip install "${PIP[@]}" -r "$DIST/consumer/requirements.txt"
  # pip builds it with maturin from the registry and the Rust toolchain.
  CARGO_TARGET_DIR="$TARGET/sdist" "$venv/bin/python" -m pip install "${PIP[@]}" \
    "$(one_file "$OUT/python" 'omnee-*.tar.gz')"
  sample "$venv"
}

# pkg-config and CMake see the installed prefix only.
export PKG_CONFIG_PATH="$OUT/c/lib/pkgconfig"
EXAMPLE="$ROOT/omnee-ffi/examples/estimate.c"

# The NEEDED entries of ELF file $1, one per line.
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'; }

check_c_pkg_config() {
  local libdir
  libdir="$(pkg-config --variable=libdir omnee)"
  # shellcheck disable=SC2046 # pkg-config's flags are words
  cc -std=c99 -Wall -Wextra -Werror $(pkg-config --cflags omnee) "$EXAMPLE" \
    $(pkg-config --libs omnee) -lm -Wl,-rpath,"$libdir" -o "$WORK/estimate-pkg-config"
  needed "$WORK/estimate-pkg-config" | grep -qx "$(soname)"
  "$WORK/estimate-pkg-config"
}

check_c_cmake() {
  cmake -S "$DIST/consumer/c" -B "$WORK/cmake" -DCMAKE_PREFIX_PATH="$OUT/c" \
    -DOMNEE_EXAMPLE="$EXAMPLE" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$WORK/cmake"
  needed "$WORK/cmake/estimate" | grep -qx "$(soname)"
  "$WORK/cmake/estimate"
}

check_c_static() {
  # libomnee.a for -lomnee (the prefix has the shared library too), then
  # what the static library itself needs (Libs.private); --as-needed drops
  # the shared library that pkg-config's -lomnee names again.
  # shellcheck disable=SC2046
  cc -std=c99 -Wall -Wextra -Werror $(pkg-config --cflags omnee) "$EXAMPLE" \
    $(pkg-config --libs-only-L omnee) -Wl,--as-needed -Wl,-Bstatic -lomnee -Wl,-Bdynamic \
    $(pkg-config --static --libs omnee) -lm -o "$WORK/estimate-static"
  if needed "$WORK/estimate-static" | grep -q libomnee; then
    fail "the statically linked program needs $(needed "$WORK/estimate-static" | grep libomnee)"
  fi
  "$WORK/estimate-static"
}

# The SONAME cargo-c gives a 0.y.z library: libomnee.so.0.y (x.y.z: .x).
soname() {
  local version
  version="$(package_version omnee-ffi)"
  case "$version" in
    0.*) echo "libomnee.so.$(echo "$version" | cut -d. -f1,2)" ;;
    *) echo "libomnee.so.${version%%.*}" ;;
  esac
}

check_c_library() {
  local version lib
  version="$(package_version omnee-ffi)"
  lib="$OUT/c/lib/libomnee.so.$version"
  readelf -d "$lib" | grep -F "Library soname: [$(soname)]"
  [ "$(readlink "$OUT/c/lib/$(soname)")" = "libomnee.so.$version" ]
  [ "$(readlink "$OUT/c/lib/libomnee.so")" = "libomnee.so.$version" ]
  # The exported (defined, dynamic) symbols are exactly the header's functions.
  nm -D --defined-only "$lib" | awk '{ print $NF }' | sort >"$WORK/exported"
  grep -oE '^[A-Za-z_][A-Za-z0-9_ *]*[ *](omnee_[a-z0-9_]+)\(' "$OUT/c/include/omnee.h" |
    grep -oE 'omnee_[a-z0-9_]+\($' | tr -d '(' | sort >"$WORK/declared"
  if ! diff -u "$WORK/declared" "$WORK/exported"; then
    fail "the library's exported symbols (+) differ from the header's functions (-)"
  fi
  cmp "$OUT/c/include/omnee.h" omnee-ffi/include/omnee.h
  echo "$(soname) -> libomnee.so.$version; exports $(wc -l <"$WORK/exported") symbols, all omnee_*, exactly the header's functions"
}

# The packages unpacked side by side, as cargo would fetch them.
unpack_crates() {
  [ -d "$WORK/crates" ] && return
  mkdir -p "$WORK/crates"
  local crate
  for crate in "$OUT"/crates/*.crate; do
    tar xzf "$crate" -C "$WORK/crates"
  done
}

check_crate_files() {
  local crate listing file
  for crate in "$OUT"/crates/*.crate; do
    listing="$(tar tzf "$crate")"
    for file in Cargo.toml Cargo.lock README.md LICENSE-MIT LICENSE-APACHE; do
      echo "$listing" | grep -qx "[^/]*/$file" || fail "$(basename "$crate") lacks $file"
    done
    echo "$(basename "$crate"): README.md, LICENSE-MIT, LICENSE-APACHE, Cargo.lock"
  done
}

check_crate_core_cortex_m() {
  unpack_crates
  rustup target add thumbv7em-none-eabihf >/dev/null 2>&1
  (cd "$WORK/crates/omnee-core-$(package_version omnee-core)" &&
    CARGO_TARGET_DIR="$TARGET/crates" cargo build --locked --release --target thumbv7em-none-eabihf)
}

check_crate_cli() {
  unpack_crates
  local core render
  core="$WORK/crates/omnee-core-$(package_version omnee-core)"
  render="$WORK/crates/omnee-render-$(package_version omnee-render)"
  # The packaged libraries stand in for the published ones.
  CARGO_TARGET_DIR="$TARGET/crates" cargo install --locked --root "$WORK/cli" \
    --path "$WORK/crates/omnee-cli-$(package_version omnee-cli)" \
    --config "patch.crates-io.omnee-core.path = \"$core\"" \
    --config "patch.crates-io.omnee-render.path = \"$render\""
  mkdir -p "$WORK/render"
  (cd "$WORK/render" && "$WORK/cli/bin/omnee" render --progress never)
  local image
  for image in omnee.exr omnee.png; do
    [ -s "$WORK/render/$image" ] || fail "omnee render wrote no $image"
  done
  ls -l "$WORK/render"
}

check_web() {
  local wasm bytes
  wasm="$(one_file "$OUT/web/pkg" '*.wasm')"
  bytes="$(stat -c %s "$wasm")"
  [ "$bytes" -le 65536 ] || fail "$wasm is $bytes B, over the demo's 65,536 B"
  [ -z "$(find "$OUT/web" ! -type f ! -type d)" ] || fail "$OUT/web has more than plain files"
  (
    source "$ROOT/omnee-wasm/build.sh"
    ensure_chromium
    ensure_npm
    OMNEE_WEB_DIR="$OUT/web" node "$E2E/e2e.mjs"
  )
}

ensure_debian cc:gcc pkg-config:pkg-config cmake:cmake
run_check check_wheel_contents
for version in 3.9 3.10 3.12 3.13; do
  run_check check_wheel "$version"
done
run_check check_sdist
run_check check_c_library
run_check check_c_pkg_config
run_check check_c_cmake
run_check check_c_static
run_check check_crate_files
run_check check_crate_core_cortex_m
run_check check_crate_cli
run_check check_web

log "checked in $SECONDS s${failures[*]:+; failed: ${failures[*]}}"
echo "dist: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
