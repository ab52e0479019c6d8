#!/usr/bin/env bash
# CI for the C API, run by .ci/run from the repository root:
#  1. regenerates include/omnee.h with the pinned cbindgen and fails if the
#     committed header differs;
#  2. compiles the header alone as C99 and as C++17 (-Wall -Wextra -Werror
#     -pedantic) and links a C++ caller;
#  3. builds the staticlib, then the example, the error-path test, the
#     promises test (corrupted objects, normals and directions of any length,
#     extreme scales, outputs as documented), the batch-over-connections test,
#     the bridges test (bad input, and the estimates of I_K against the
#     isotropic closed form) and the bit-pattern program with
#     cc -std=c99 -Wall -Wextra -Werror -fsanitize=address,undefined, and
#     runs them;
#  4. checks that the C results equal the Rust API's bit for bit.
# Prints each step's time; installs cbindgen if it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

CBINDGEN_VERSION=0.29.4
target=${CARGO_TARGET_DIR:-target}
out=$target/omnee-ffi-ci
mkdir -p "$out"
SECONDS=0
step() { printf '\n--> [%4ds] %s\n' "$SECONDS" "$*"; }

step "cbindgen $CBINDGEN_VERSION"
if ! cbindgen --version 2>/dev/null | grep -qx "cbindgen $CBINDGEN_VERSION"; then
  start=$SECONDS
  cargo install cbindgen --version "=$CBINDGEN_VERSION" --locked
  echo "installed cbindgen in $((SECONDS - start)) s"
fi

step "the committed header is cbindgen's output"
cbindgen --quiet --config omnee-ffi/cbindgen.toml --crate omnee-ffi --output "$out/omnee.h"
if ! diff -u omnee-ffi/include/omnee.h "$out/omnee.h"; then
  echo "omnee-ffi/include/omnee.h is stale: regenerate it with"
  echo "  cbindgen --config omnee-ffi/cbindgen.toml --crate omnee-ffi --output omnee-ffi/include/omnee.h"
  exit 1
fi

step "the header compiles as C99 and C++17"
if ! command -v cc >/dev/null || ! command -v c++ >/dev/null; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends g++ >/dev/null
fi
warn=(-Wall -Wextra -Werror -pedantic -Iomnee-ffi/include)
printf '#include "omnee.h"\nint main(void) { return 0; }\n' >"$out/header.c"
cc -std=c99 "${warn[@]}" -c "$out/header.c" -o "$out/header_c.o"
cat >"$out/header.cpp" <<'EOF'
#include "omnee.h"
int main() {
  omnee_phase_f32 phase;
  return omnee_phase_hg_f32(&phase, 0.5f, nullptr) == OMNEE_OK ? 0 : 1;
}
EOF
c++ -std=c++17 "${warn[@]}" -c "$out/header.cpp" -o "$out/header_cpp.o"

step "staticlib (release)"
cargo build --locked --release -p omnee-ffi
lib=("$target/release/libomnee_ffi.a" -lm -lpthread -ldl)
c++ "$out/header_cpp.o" "${lib[@]}" -o "$out/header_cpp" && "$out/header_cpp"

step "C programs under AddressSanitizer and UndefinedBehaviorSanitizer"
cflags=(-std=c99 -Wall -Wextra -Werror -g -fsanitize=address,undefined -fno-sanitize-recover=all
  -Iomnee-ffi/include)
for program in examples/estimate tests/errors tests/promises tests/bits tests/connections \
  tests/bridges; do
  cc "${cflags[@]}" "omnee-ffi/$program.c" "${lib[@]}" -o "$out/$(basename "$program")"
done
"$out/estimate"
"$out/errors"
"$out/promises"
"$out/connections"
"$out/bridges"

step "C results equal the Rust API's, bit for bit"
"$out/bits" >"$out/bits.txt"
cargo run --locked --release -q -p omnee-ffi --example expected >"$out/expected.txt"
if ! diff -u "$out/expected.txt" "$out/bits.txt"; then
  echo "the C API's results differ from the Rust API's (above: - Rust, + C)"
  exit 1
fi
echo "bits: $(wc -l <"$out/bits.txt") lines identical ($(grep -o ' [0-9a-f]\{8,16\}' "$out/bits.txt" | wc -l) numbers)"

step "omnee-ffi: all checks passed"
