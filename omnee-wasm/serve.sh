#!/usr/bin/env bash
# Builds the omnee-wasm demo and serves it on http://127.0.0.1:${PORT:-8000}/
# (no network needed once the tools are installed; see build.sh).
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/build.sh"
ensure_rust_target
ensure_wasm_bindgen_cli
ensure_npm
build_wasm
port="${PORT:-8000}"
log "serving $WASM_DIR/web on http://127.0.0.1:$port/ (Ctrl-C to stop)"
exec python3 -m http.server --bind 127.0.0.1 --directory "$WASM_DIR/web" "$port"
