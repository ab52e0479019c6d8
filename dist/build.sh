#!/usr/bin/env bash
# Builds every artefact of omnee into OUT, each as its ecosystem ships it:
#   OUT/python/  one wheel for CPython >= 3.9 (abi3, manylinux_2_17: glibc
#                >= 2.17), checked by auditwheel and abi3audit, and the sdist;
#   OUT/c/       the install prefix of cargo-c's `cargo cinstall`: include/
#                omnee.h, lib/libomnee.so.X.Y.Z with its SONAME links,
#                lib/libomnee.a, lib/pkgconfig/omnee.pc, and the CMake
#                package lib/cmake/omnee (the imported target omnee::omnee);
#   OUT/crates/  `cargo package` of omnee-core, omnee-render and omnee-cli,
#                each verified by building it from the package alone;
#   OUT/web/     the browser demo as a static folder (index.html, the
#                module, its glue) for any static server.
# Usage, from anywhere: bash dist/build.sh OUT
# Replaces those four folders of OUT; installs the tools it needs
# (dist/tools.sh). dist/check.sh then uses each artefact as its users do.
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/tools.sh"
[ $# -eq 1 ] || { echo "usage: bash dist/build.sh OUT" >&2; exit 2; }
mkdir -p "$1"
OUT="$(cd "$1" && pwd)"
rm -rf "$OUT/python" "$OUT/c" "$OUT/crates" "$OUT/web"
mkdir -p "$OUT/python" "$OUT/crates" "$OUT/web"
cd "$ROOT"
SECONDS=0

build_python() {
  ensure_python_tools
  log "python: the abi3 wheel (maturin --zig, manylinux_2_17) and the sdist"
  maturin build --release --locked --zig --compatibility manylinux_2_17 \
    -m omnee-py/Cargo.toml --out "$OUT/python"
  maturin sdist -m omnee-py/Cargo.toml --out "$OUT/python"
  local wheel
  wheel="$(one_file "$OUT/python" 'omnee-*.whl')"
  case "$(basename "$wheel")" in
    *-cp39-abi3-*manylinux_2_17_x86_64*.whl) ;;
    *) fail "the wheel's tags are not cp39-abi3 and manylinux_2_17_x86_64: $wheel" ;;
  esac
  one_file "$OUT/python" 'omnee-*.tar.gz' >/dev/null
  log "python: auditwheel and abi3audit"
  # auditwheel names the most compatible platform the wheel's symbol
  # versions and libraries allow; it must be the one the tag claims.
  local audit
  audit="$(auditwheel show "$wheel")"
  echo "$audit"
  echo "$audit" | tr -s ' \n' ' ' |
    grep -q 'is consistent with the following platform tag: "manylinux_2_17_x86_64"' ||
    fail "auditwheel: the wheel is not manylinux_2_17_x86_64"
  abi3audit --strict --summary "$wheel"
}

build_c() {
  ensure_cargo_c
  ensure_debian cmake:cmake
  log "c: cargo cinstall -p omnee-ffi --prefix $OUT/c"
  # Without debug information: what a distribution ships (the workspace's
  # release profile keeps line tables; the .so would be 6 MB instead of 1).
  CARGO_PROFILE_RELEASE_DEBUG=false CARGO_PROFILE_RELEASE_STRIP=debuginfo \
    cargo cinstall -p omnee-ffi --release --locked --prefix "$OUT/c" --libdir lib
  local version soname
  version="$(package_version omnee-ffi)"
  soname="$(readelf -d "$OUT/c/lib/libomnee.so.$version" |
    sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')"
  [ -n "$soname" ] || fail "lib/libomnee.so.$version has no SONAME"
  log "c: the CMake package (omnee::omnee, $soname)"
  cmake -DPREFIX="$OUT/c" -DVERSION="$version" -DSONAME="$soname" -P "$DIST/c/config.cmake"
}

build_crates() {
  log "crates: cargo package (each verified by a build from the package alone)"
  local crates=(omnee-core omnee-render omnee-cli) packages=() target name
  for name in "${crates[@]}"; do packages+=(-p "$name"); done
  # Together: each is verified against the others as packaged (cargo's
  # local registry of this run), as if they were published.
  cargo package --locked --allow-dirty "${packages[@]}"
  target="$(target_dir)"
  for name in "${crates[@]}"; do
    cp "$target/package/$name-$(package_version "$name").crate" "$OUT/crates/"
  done
}

build_web() {
  log "web: the demo's module and page (omnee-wasm/build.sh)"
  (
    source "$ROOT/omnee-wasm/build.sh"
    ensure_rust_target
    ensure_wasm_bindgen_cli
    ensure_npm
    build_wasm
    [ "$WASM_SIZE_OK" = 1 ] || exit 1
    # Plain files only: a static host serves the folder as it is.
    cp -RL "$WASM_DIR/web/." "$OUT/web/"
  )
}

build_python
build_c
build_crates
build_web
log "built in $SECONDS s:"
(cd "$OUT" && find python c crates web \( -type f -o -type l \) -printf '%10s  %p\n' | sort -k2)
