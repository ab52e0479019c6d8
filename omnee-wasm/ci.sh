#!/usr/bin/env bash
# CI for omnee-wasm: installs what is missing (wasm target, Chromium +
# ChromeDriver, wasm-bindgen-cli at the Cargo.lock version, npm packages from
# the lockfile), builds and size-checks the optimised .wasm, runs the native
# tests, the wasm-bindgen-test suite in headless Chromium and the Playwright
# end-to-end test of the demo page. Idempotent; run from anywhere.
set -euo pipefail
start=$SECONDS
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/build.sh"

ensure_rust_target
ensure_chromium
ensure_wasm_bindgen_cli
ensure_npm
build_wasm

log "native tests"
(cd "$ROOT" && cargo test -p omnee-wasm)

log "wasm-bindgen-test in headless Chromium"
(cd "$WASM_DIR" \
    && CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=wasm-bindgen-test-runner \
       CHROMEDRIVER=/usr/bin/chromedriver \
       WASM_BINDGEN_TEST_WEBDRIVER_JSON="$WASM_DIR/webdriver.json" \
       cargo test -p omnee-wasm --target wasm32-unknown-unknown --test web)

log "end-to-end test of the page (Playwright, /usr/bin/chromium)"
node "$E2E/e2e.mjs"

# The size limit is checked last so that a too-large module still gets tested.
if [ "$WASM_SIZE_OK" != 1 ]; then
    echo "omnee-wasm ci: FAILED: optimised wasm $WASM_BYTES B > $MAX_WASM_BYTES B (tests passed; $((SECONDS - start)) s)"
    exit 1
fi
echo "omnee-wasm ci: OK (optimised wasm $WASM_BYTES B <= $MAX_WASM_BYTES B; $WASM_GZIP_BYTES B gzip; $((SECONDS - start)) s)"
