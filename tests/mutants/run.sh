#!/usr/bin/env bash
# Mutation check of the property suite: applies each patch in
# tests/mutants/patches to the working tree, runs the root suite
# (`cargo test -p omnee --test suite`) and the core's own tests
# (`cargo test -p omnee-core`), records which tests fail, and reverts.
#
#   tests/mutants/run.sh                 # every patch, after an unmutated baseline
#   tests/mutants/run.sh 07 hg-norm      # only patches whose file name contains 07 or hg-norm
#
# Environment: CARGO_TARGET_DIR as usual; MUTANTS_OUT (default
# $CARGO_TARGET_DIR or target, then /mutants) for the logs and the results;
# MUTANTS_TIMEOUT seconds per test command (default 900); MUTANTS_BASELINE=0
# skips the unmutated run; MUTANTS_CORE=0 skips the core's tests (the suite
# alone, about half the time).
#
# It edits the source files the patches touch, so run it in a checkout of
# your own (a `git clone` of the repository) with those files unmodified;
# the patch is reverted on exit, also on Ctrl-C.
set -u -o pipefail

root=$(git rev-parse --show-toplevel)
cd "$root"
target=${CARGO_TARGET_DIR:-$root/target}
out=${MUTANTS_OUT:-$target/mutants}
limit=${MUTANTS_TIMEOUT:-900}
mkdir -p "$out"

all=(tests/mutants/patches/*.patch)
patches=()
if [ $# -eq 0 ]; then
    patches=("${all[@]}")
else
    for p in "${all[@]}"; do
        for want in "$@"; do
            case "$(basename "$p")" in *"$want"*) patches+=("$p"); break ;; esac
        done
    done
fi
[ ${#patches[@]} -gt 0 ] || { echo "no patch matches: $*" >&2; exit 2; }

# Only files the patches touch must be clean (the suite itself may be new).
touched=$(grep -h '^+++ b/' "${all[@]}" | sed 's|^+++ b/||' | sort -u)
# shellcheck disable=SC2086
if ! git diff --quiet HEAD -- $touched; then
    echo "uncommitted changes in files the patches touch:" >&2
    # shellcheck disable=SC2086
    git diff --stat HEAD -- $touched >&2
    exit 2
fi

applied=""
revert() {
    if [ -n "$applied" ]; then
        git apply -R "$applied" || echo "could not revert $applied" >&2
        applied=""
    fi
}
trap revert EXIT
trap 'revert; exit 130' INT TERM

# `test NAME ... FAILED` lines of a cargo test log, comma-separated.
failures() {
    grep -E '^test .* \.\.\. FAILED$' "$1" | sed -E 's/^test (.*) \.\.\. FAILED$/\1/' |
        sort -u | paste -sd, -
}

# run LABEL LOG CMD...: the command under the time limit; prints
# "pass", "FAIL <tests>", "timeout" or "error" (failed without a failing test:
# a compile error or a crash).
run() {
    local log=$1
    shift
    timeout -k 10 "$limit" "$@" >"$log" 2>&1
    local rc=$?
    local failed
    failed=$(failures "$log")
    if [ $rc -eq 0 ]; then
        echo "pass"
    elif [ -n "$failed" ]; then
        echo "FAIL $failed"
    elif [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
        echo "timeout"
    else
        echo "error"
    fi
}

suite=(cargo test -p omnee --test suite --no-fail-fast)
core=(cargo test -p omnee-core --no-fail-fast)

results="$out/results.tsv"
printf 'mutation\tsuite\tcore\tseconds\n' >"$results"
start_all=$(date +%s)

measure() { # NAME DIR
    local name=$1 dir=$2 t0 s c
    t0=$(date +%s)
    mkdir -p "$dir"
    if ! cargo test -p omnee --test suite --no-run >"$dir/build.log" 2>&1; then
        s="build failed" c="build failed"
    else
        s=$(run "$dir/suite.log" "${suite[@]}")
        if [ "${MUTANTS_CORE:-1}" = 0 ]; then
            c="not run"
        elif ! cargo test -p omnee-core --no-run >>"$dir/build.log" 2>&1; then
            c="build failed"
        else
            c=$(run "$dir/core.log" "${core[@]}")
        fi
    fi
    local secs=$(($(date +%s) - t0))
    printf '%s\t%s\t%s\t%s\n' "$name" "$s" "$c" "$secs" >>"$results"
    printf '%-45s suite: %s\n%-45s core:  %s  (%ss)\n' "$name" "$s" "" "$c" "$secs"
}

if [ "${MUTANTS_BASELINE:-1}" != 0 ]; then
    measure "(unmutated)" "$out/baseline"
fi

for p in "${patches[@]}"; do
    name=$(basename "$p" .patch)
    if ! git apply --check "$p" 2>"$out/$name.apply.log"; then
        printf '%s\tdoes not apply\tdoes not apply\t0\n' "$name" >>"$results"
        echo "$name: does not apply (see $out/$name.apply.log)"
        continue
    fi
    git apply "$p" && applied=$p
    measure "$name" "$out/$name"
    revert
done

total=$(($(date +%s) - start_all))
echo "total: ${total}s; results in $results"

# The README's table: mutation, what it breaks, suite tests, core tests.
{
    echo "| mutation | breaks | caught by the suite | caught by the core's tests |"
    echo "|---|---|---|---|"
    tail -n +2 "$results" | while IFS=$'\t' read -r name s c _; do
        patch=tests/mutants/patches/$name.patch
        what=$( [ -f "$patch" ] && sed -n 's/^Breaks: //p' "$patch" || echo "baseline")
        cell() {
            case "$1" in
            "FAIL "*) echo "${1#FAIL }" | sed 's/,/, /g' ;;
            pass) echo "**not caught**" ;;
            *) echo "$1" ;;
            esac
        }
        [ "$name" = "(unmutated)" ] && cell() { echo "$1"; }
        echo "| \`$name\` | $what | $(cell "$s") | $(cell "$c") |"
    done
} >"$out/results.md"
echo "table in $out/results.md"
