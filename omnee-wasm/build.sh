#!/usr/bin/env bash
# Shared by ci.sh and serve.sh (source it): installs what the wasm build needs
# and builds the demo into omnee-wasm/web/pkg. Idempotent.
set -euo pipefail

WASM_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$WASM_DIR/.." && pwd)"
PKG="$WASM_DIR/web/pkg"
E2E="$WASM_DIR/e2e"
# The demo's limit: 64 KiB (65,536 B) after wasm-opt (README.md: where the
# bytes went, and the levers measured). ci.sh fails above it (after the
# tests, so that a too-large module still gets tested).
MAX_WASM_BYTES=65536

# The Wasm features the module may use, for wasm-opt (the target-features
# section is stripped before wasm-bindgen, below): those of Rust's
# wasm32-unknown-unknown target without reference types and multivalue.
WASM_FEATURES=(--enable-bulk-memory --enable-bulk-memory-opt --enable-nontrapping-float-to-int
    --enable-sign-ext --enable-mutable-globals)

log() { printf '== omnee-wasm: %s\n' "$*"; }

# The wasm-bindgen crate version pinned by Cargo.lock (the CLI must match it).
wasm_bindgen_version() {
    awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' "$ROOT/Cargo.lock"
}

ensure_rust_target() {
    if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
        log "rustup target add wasm32-unknown-unknown"
        rustup target add wasm32-unknown-unknown
    fi
}

# wasm-bindgen-cli at exactly the Cargo.lock version (TOOLCHAIN.md §2.2/2.3):
# `cargo install --locked` first; if the registry lacks a locked dependency
# (webpki-roots 1.0.11 here), build the same release from its own source with
# that one dependency stepped back to the newest version the registry has;
# as a last resort resolve the dependencies afresh.
ensure_wasm_bindgen_cli() {
    local want have
    want="$(wasm_bindgen_version)"
    [ -n "$want" ] || { echo "no wasm-bindgen in Cargo.lock" >&2; return 1; }
    have="$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)"
    if [ "$have" = "$want" ] && command -v wasm-bindgen-test-runner >/dev/null; then
        log "wasm-bindgen-cli $want already installed"
        return
    fi
    log "installing wasm-bindgen-cli $want (a few minutes)"
    if cargo install wasm-bindgen-cli --version "$want" --locked; then
        return
    fi
    local crate scratch
    crate="$(ls "${CARGO_HOME:-$HOME/.cargo}"/registry/cache/*/wasm-bindgen-cli-"$want".crate 2>/dev/null | head -n 1 || true)"
    if [ -n "$crate" ]; then
        scratch="$(mktemp -d)"
        tar xzf "$crate" -C "$scratch"
        if (cd "$scratch/wasm-bindgen-cli-$want" \
            && cargo update -p webpki-roots --precise 1.0.10 \
            && CARGO_TARGET_DIR="$scratch/target" cargo install --path . --locked); then
            rm -rf "$scratch"
            return
        fi
        rm -rf "$scratch"
    fi
    log "falling back to an unlocked install of wasm-bindgen-cli =$want"
    cargo install wasm-bindgen-cli --version "=$want"
}

# npm packages (binaryen's wasm-opt, playwright-core) from the committed lockfile.
ensure_npm() {
    if [ -x "$E2E/node_modules/.bin/wasm-opt" ] && [ -d "$E2E/node_modules/playwright-core" ] \
        && [ "$E2E/node_modules/.package-lock.json" -nt "$E2E/package-lock.json" ]; then
        log "npm packages up to date"
        return
    fi
    log "npm ci"
    (cd "$E2E" && npm ci --no-audit --no-fund)
}

ensure_chromium() {
    if command -v chromium >/dev/null && command -v chromedriver >/dev/null; then
        return
    fi
    log "apt-get install chromium chromium-driver"
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y chromium chromium-driver
}

# The cargo target directory, honouring CARGO_TARGET_DIR and configuration.
target_dir() {
    (cd "$ROOT" && cargo metadata --format-version 1 --no-deps) \
        | node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.parse(s).target_directory))'
}

# Release wasm -> wasm-bindgen (--target web) -> wasm-opt, with the size check.
build_wasm() {
    log "cargo build --no-default-features --profile wasm-release --target wasm32-unknown-unknown"
    # The workspace's wasm-release profile (root Cargo.toml): LTO, one codegen
    # unit, panic = abort, no debug info, opt-level z; used by this build
    # only. Without default features: no std (lib.rs). omnee-core and
    # wasm-bindgen are compiled at opt-level s before LTO, which makes the
    # optimised module 477 B and 171 B smaller (measured; s for every
    # dependency makes it 1.5 KiB larger, libm at s alone 3 KiB).
    # Without reference types (1,157 B less, README.md): wasm-bindgen then
    # keeps JavaScript objects in a table of the glue instead of an externref
    # table with a shim per export. The flag is added to the caller's
    # RUSTFLAGS (or CARGO_ENCODED_RUSTFLAGS), not replacing them.
    local no_ref="-Ctarget-feature=-reference-types"
    (cd "$ROOT" \
        && if [ -n "${CARGO_ENCODED_RUSTFLAGS:-}" ]; then
            export CARGO_ENCODED_RUSTFLAGS="$CARGO_ENCODED_RUSTFLAGS"$'\x1f'"$no_ref"
        else
            export RUSTFLAGS="${RUSTFLAGS:+$RUSTFLAGS }$no_ref"
        fi \
        && cargo build -p omnee-wasm --no-default-features --profile wasm-release \
            --target wasm32-unknown-unknown \
            --config 'profile.wasm-release.package.omnee-core.opt-level = "s"' \
            --config 'profile.wasm-release.package.wasm-bindgen.opt-level = "s"')
    local raw
    raw="$(target_dir)/wasm32-unknown-unknown/wasm-release/omnee_wasm.wasm"
    rm -rf "$PKG"
    # The precompiled `core` still lists reference types in the
    # target-features section, from which wasm-bindgen would turn them on:
    # the section goes first (a copy, named as cargo's output for
    # wasm-bindgen's file names).
    local stripped
    stripped="$(mktemp -d)"
    "$E2E/node_modules/.bin/wasm-opt" "${WASM_FEATURES[@]}" --strip-target-features \
        "$raw" -o "$stripped/omnee_wasm.wasm"
    wasm-bindgen --target web --out-dir "$PKG" "$stripped/omnee_wasm.wasm"
    rm -rf "$stripped"
    local bg="$PKG/omnee_wasm_bg.wasm"
    local before
    before=$(stat -c %s "$bg")
    # -Oz, then the control flow rebuilt from flat code (--flatten
    # --rereloop, 660 B) and -Oz again with similar functions merged (80 B);
    # --converge repeats the passes while they still shrink the module. The
    # producers and target-features sections are for tools, not browsers
    # (265 B). About 5 s.
    "$E2E/node_modules/.bin/wasm-opt" "${WASM_FEATURES[@]}" -Oz --flatten --rereloop -Oz \
        --merge-similar-functions -Oz --converge --strip-producers --strip-target-features \
        "$bg" -o "$bg"
    # The names of the imports and exports, and the import module, shortened
    # to a letter or two (551 B), and the glue renamed to match
    # (minify.mjs, which checks that the two agree). The raw exports'
    # declarations (omnee_wasm_bg.wasm.d.ts) would keep the old names: gone.
    local names
    names="$(mktemp)"
    "$E2E/node_modules/.bin/wasm-opt" "${WASM_FEATURES[@]}" --minify-imports-and-exports-and-modules \
        "$bg" -o "$bg" >"$names"
    node "$WASM_DIR/minify.mjs" "$names" "$bg" "$PKG/omnee_wasm.js"
    rm -f "$names" "$PKG/omnee_wasm_bg.wasm.d.ts"
    WASM_BYTES=$(stat -c %s "$bg")
    WASM_GZIP_BYTES=$(gzip -9 -c "$bg" | wc -c)
    local margin="$((MAX_WASM_BYTES - WASM_BYTES)) B to spare"
    [ "$WASM_BYTES" -le "$MAX_WASM_BYTES" ] || margin="exceeded by $((WASM_BYTES - MAX_WASM_BYTES)) B"
    log "wasm size: raw $(stat -c %s "$raw") B, after wasm-bindgen $before B, after wasm-opt $WASM_BYTES B ($WASM_GZIP_BYTES B gzip), limit $MAX_WASM_BYTES B: $margin"
    WASM_SIZE_OK=1
    if [ "$WASM_BYTES" -gt "$MAX_WASM_BYTES" ]; then
        echo "omnee-wasm: optimised .wasm is $WASM_BYTES B > $MAX_WASM_BYTES B (the demo's limit)" >&2
        WASM_SIZE_OK=0
    fi
}
