#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang into build-fuzz, the whole project instrumented
# for coverage, AddressSanitizer and UndefinedBehaviorSanitizer, and runs each for SECONDS (default 60).
#   scripts/fuzz.sh [SECONDS]
# Each fuzzer starts from its seed corpus (tests/fuzz/corpus/NAME) and the regression inputs
# (tests/fuzz/regressions/NAME); what it learns goes to build-fuzz/corpus/NAME, never into the source
# tree. A finding stops the run with a non-zero status and leaves the input in build-fuzz/artifacts/:
# fix it, then add the input to tests/fuzz/regressions/NAME, which test_fuzz_regressions replays.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"

werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
cmake --preset fuzz -DPBS_WERROR="$werror" >/dev/null  # CMakePresets.json: build-fuzz/, clang, libFuzzer
cmake --build --preset fuzz -j"$(nproc)"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:print_summary=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:print_summary=1"
# target:corpus pairs
for pair in gltf_import:gltf surfel_file:surfels; do
  target="fuzz_${pair%%:*}"
  corpus="${pair##*:}"
  mkdir -p "build-fuzz/corpus/$corpus" build-fuzz/artifacts
  inputs=("build-fuzz/corpus/$corpus" "tests/fuzz/corpus/$corpus")
  [ -d "tests/fuzz/regressions/$corpus" ] && inputs+=("tests/fuzz/regressions/$corpus")
  options=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=30 -max_len=65536 -print_final_stats=1
           -artifact_prefix="build-fuzz/artifacts/$target-")
  [ -f "tests/fuzz/$corpus.dict" ] && options+=(-dict="tests/fuzz/$corpus.dict")
  echo "fuzz: $target for ${seconds} s"
  "build-fuzz/bin/$target" "${options[@]}" "${inputs[@]}"
done
