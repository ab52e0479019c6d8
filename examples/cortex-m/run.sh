#!/usr/bin/env bash
# omnee on a microcontroller: builds the firmware for a Cortex-M4F
# (thumbv7em-none-eabihf), runs it under QEMU on the MPS2 AN386 board model,
# measures its footprint, and prints as its last line one JSON object
#   {"machine", "phase", "samples", "estimate", "stderr", "reference",
#    "flash_bytes", "static_ram_bytes", "stack_bytes"}
# for the minimal firmware (OMNEE + Henyey-Greenstein, f32). Exits 0 only when
# the estimate lies within 4.5 standard errors of the quadrature reference
# (computed on the host at build time) and the firmware that links
# everything passes its own checks. Also builds both for
# riscv32imac-unknown-none-elf and reports their sizes (not run).
#
# Installs what it needs on a fresh Debian machine: the rustup targets and
# Debian's qemu-system-arm. Flash is the sections stored in flash (vector
# table, code, constants, unwind tables, .data's initial values), static RAM
# .data + .bss + .uninit, both read from the ELF with llvm-size or GNU size;
# the stack's peak is measured on the device by painting.
set -euo pipefail
cd "$(dirname "$0")"
SECONDS=0
log() { printf '[%4ds] %s\n' "$SECONDS" "$*" >&2; }

arm=thumbv7em-none-eabihf
riscv=riscv32imac-unknown-none-elf
log "rustup targets $arm $riscv"
rustup target add "$arm" "$riscv" >/dev/null 2>&1 || rustup target add "$arm" "$riscv"

if ! command -v qemu-system-arm >/dev/null; then
  log "installing qemu-system-arm (Debian)"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    qemu-system-arm >/dev/null
fi
qemu-system-arm --version | head -1 >&2

if command -v llvm-size >/dev/null; then size_tool=llvm-size; else size_tool=size; fi

# "flash static_ram" of an ELF: the sizes of its sections by name.
footprint() {
  "$size_tool" -A "$1" | awk '
    $1 ~ /^\.(vector_table|text|init|rodata|eh_frame|data|gnu\.sgstubs)/ { flash += $2 }
    $1 ~ /^\.(data|bss|uninit)/ { ram += $2 }
    END { print flash + 0, ram + 0 }'
}

log "building the firmware ($arm, $riscv)"
cargo build --locked --release --target "$arm" --bins
cargo build --locked --release --target "$riscv" --bins
# Where cargo put them: CARGO_TARGET_DIR or the configuration may move the
# target directory away from ./target.
target=$(cargo metadata --format-version 1 --no-deps |
  sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')

# The firmware prints "key value ..." lines, floats as hex IEEE bits.
run() {
  timeout 900 qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
    -semihosting-config enable=on,target=native -kernel "$target/$arm/release/$1"
}
field() { awk -v k="$1" '$1 == k { print $2; exit }' <<<"$2"; }
f32() { perl -e 'printf "%.9g", unpack("f", pack("L", hex($ARGV[0])))' "$1"; }
f64() { perl -e 'printf "%.17g", unpack("d", pack("Q", hex($ARGV[0])))' "$1"; }

log "running the firmware that links everything (every phase function and technique, f32 and f64)"
everything_status=0
everything=$(run everything) || everything_status=$?
printf '%s\n' "$everything" >&2
read -r everything_flash everything_ram < <(footprint "$target/$arm/release/everything")
everything_stack=$((16#$(field stack_bytes "$everything")))

log "running the minimal firmware (OMNEE + HG, f32)"
minimal_status=0
minimal=$(run minimal) || minimal_status=$?
printf '%s\n' "$minimal" >&2
read -r flash ram < <(footprint "$target/$arm/release/minimal")
read -r riscv_flash riscv_ram < <(footprint "$target/$riscv/release/minimal")
read -r riscv_everything_flash riscv_everything_ram < <(footprint "$target/$riscv/release/everything")
stack=$((16#$(field stack_bytes "$minimal")))

# What (a) links: no other phase function or technique, and how much
# software double arithmetic (libm's sinf/cosf compute in double; the core's
# parameter checks compare in f64).
if command -v llvm-nm >/dev/null; then nm_tool=llvm-nm; else nm_tool=nm; fi
symbols=$("$nm_tool" -S -C "$target/$arm/release/minimal")
others=$(grep -cE 'Draine|Mie|FournierForand|Tabulated|Rayleigh|Isotropic|Mixture|Equiangular|Distance|OmneeMis|OneSample|integral' <<<"$symbols" || true)
double_bytes=$(perl -ne '@f = split " ", $_, 4;
  $s += hex $f[1] if @f == 4 && $f[3] =~ /^__aeabi_(d|f2d|i2d)|__(adddf|muldf|subdf|divdf)3$|^libm::math::(k_sinf|k_cosf|scalbn)::/;
  END { print $s + 0 }' <<<"$symbols")

{
  echo
  echo "| firmware | target | flash (B) | static RAM (B) | peak stack (B) |"
  echo "|---|---|---:|---:|---:|"
  echo "| (a) OMNEE + HG, f32 | $arm | $flash | $ram | $stack |"
  echo "| (b) everything, f32 + f64 | $arm | $everything_flash | $everything_ram | $everything_stack |"
  echo "| (a) OMNEE + HG, f32 | $riscv | $riscv_flash | $riscv_ram | not run |"
  echo "| (b) everything, f32 + f64 | $riscv | $riscv_everything_flash | $riscv_everything_ram | not run |"
  echo
  echo "(a) links $others symbols of other phase functions or techniques and $double_bytes B of double-precision code"
  echo "qemu exit: minimal $minimal_status, everything $everything_status; ${SECONDS} s"
} >&2

printf '{"machine": "%s", "phase": "%s", "samples": %d, "estimate": %s, "stderr": %s, "reference": %s, "flash_bytes": %d, "static_ram_bytes": %d, "stack_bytes": %d}\n' \
  "$(field machine "$minimal")" "$(field phase "$minimal")" \
  "$((16#$(field samples "$minimal")))" \
  "$(f32 "$(field estimate "$minimal")")" "$(f32 "$(field stderr "$minimal")")" \
  "$(f64 "$(field reference "$minimal")")" "$flash" "$ram" "$stack"

[ "$minimal_status" -eq 0 ] && [ "$(field agrees "$minimal")" = 00000001 ] &&
  [ "$everything_status" -eq 0 ] && [ "$others" -eq 0 ]
