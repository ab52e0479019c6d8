#!/usr/bin/env bash
# The shape the project promises (docs/architecture.md), checked on the
# source: front ends depend on the library, never on the CLI; one type per
# name across the library crates; the CLI stays a thin front end; code names
# no tracker issues. Prints what it measured; exits 1 on the first broken rule.
set -euo pipefail
cd "$(dirname "$0")/.."
fail() { echo "layout: $*" >&2; exit 1; }

# No crate but the CLI itself names omnee-cli as a dependency.
deps=$(git grep -l -E '^omnee-cli *=' -- '*Cargo.toml' | grep -v '^omnee-cli/' || true)
[ -z "$deps" ] || fail "these crates depend on omnee-cli (use omnee-render): $deps"

# A struct, enum, trait, union or type alias name is defined once across the
# core, the library and the CLI (associated types and test modules aside).
dups=$(grep -rhoE '^\s*(pub(\([a-z]+\))? )?(struct|enum|trait|union) [A-Z][A-Za-z0-9_]*|^(pub(\([a-z]+\))? )?type [A-Z][A-Za-z0-9_]*' \
  --include='*.rs' omnee-core/src omnee-render/src omnee-cli/src |
  sed -E 's/.*(struct|enum|trait|union|type) //' | sort | uniq -d)
[ -z "$dups" ] || fail "type names defined more than once: $(echo $dups)"

# The CLI's code outside its test modules.
cli_lines=$(for f in $(git ls-files 'omnee-cli/src/*.rs'); do
  awk '/^#\[cfg\(test\)\]/ { exit } { n++ } END { print n + 0 }' "$f"
done | awk '{ s += $1 } END { print s }')
[ "$cli_lines" -le 1500 ] || fail "omnee-cli has $cli_lines lines of non-test Rust (at most 1500)"

# One way to do each thing: SplitMix64 (its increment and its finaliser's
# multipliers) is written once, in the core's rng module, which every Rust
# crate uses (the C programs, which cannot, bring their own).
splitmix=$(git grep -n -i -E '0x(9e37_?79b9_?7f4a_?7c15|bf58_?476d_?1ce4_?e5b9|94d0_?49bb_?1331_?11eb)' -- \
  '*.rs' ':!omnee-core/src/rng.rs' || true)
[ -z "$splitmix" ] || fail "SplitMix64 written again (use omnee_core::rng): $splitmix"

# Code and comments say what they do, not which tracker issue asked for it.
refs=$(git grep -n -I -i -E '\b(issue|ticket) ?#?[0-9]+|\bissue[0-9]+' -- \
  '*.rs' '*.toml' '*.py' '*.c' '*.h' '*.js' '*.mjs' '*.sh' || true)
[ -z "$refs" ] || fail "code refers to tracker issues: $refs"

echo "layout: no crate depends on omnee-cli; no type name defined twice; omnee-cli $cli_lines lines of non-test Rust; SplitMix64 written once; no tracker numbers in code"
