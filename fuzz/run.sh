#!/usr/bin/env bash
# Runs one fuzz target for a bounded time, on a scratch copy of its committed seed corpus
# (fuzz/corpus/TARGET is never written), with the flags every run uses.
#
#   fuzz/run.sh TARGET SECONDS [SCRATCH]     # SCRATCH: keep the grown corpus and artifacts
#
# TARGET: problem, grid, certificate, trace_csv, trace_jsonl or bag. Extra libFuzzer flags go in
# FUZZ_FLAGS (e.g. FUZZ_FLAGS="-fork=1 -ignore_crashes=1" for a long campaign). A crash
# leaves its input in SCRATCH/artifacts/ and exits non-zero. Needs cargo-fuzz 0.13 on PATH;
# stable Rust is enough (-s none: no sanitizer).
set -euo pipefail
target=$1
seconds=$2
cd "$(dirname "$0")/.."
scratch=${3:-$(mktemp -d)}
mkdir -p "$scratch/corpus" "$scratch/artifacts"
cp fuzz/corpus/"$target"/* "$scratch/corpus/"
# Longest input: a problem or grid file is small; certificates, maps and traces are larger.
case $target in
  problem | grid) max_len=16384 ;;
  *) max_len=65536 ;;
esac
# shellcheck disable=SC2086 # FUZZ_FLAGS is a list of flags
cargo fuzz run -s none "$target" "$scratch/corpus" -- \
  -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 -max_total_time="$seconds" \
  -artifact_prefix="$scratch/artifacts/" -print_final_stats=1 ${FUZZ_FLAGS:-}
