#!/usr/bin/env bash
# Builds pbs with AddressSanitizer + UndefinedBehaviorSanitizer (PBS_SANITIZE) into build-asan and runs
# the whole suite under them. Extra arguments go to ctest (e.g. -R test_surfel_file).
set -euo pipefail
cd "$(dirname "$0")/.."

# The asan preset builds with clang at -O1 -g1: fast enough for the heavier suites, stacks with file and line
# (full -g costs a third more build time), and assert() stays on (no NDEBUG). Clang rather than GCC, whose
# Release build setup.sh makes: each file compiles instrumented in 35-40 % less time (a clean build: 8 minutes
# on two cores), and a second compiler's warnings and language rules are checked on every change (warnings are
# errors when CI=true, as in setup.sh).
werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
cmake --preset asan -DPBS_WERROR="$werror" >/dev/null  # CMakePresets.json: build-asan/, PBS_SANITIZE
cmake --build --preset asan -j"$(nproc)"

# Any report fails the test that made it: stop at the first error, with a stack trace. LSAN_OPTIONS
# (the suppressions for Mesa's llvmpipe) is set per test by tests/CMakeLists.txt.
# intercept_tls_get_addr=0: the runtime can take a dynamic TLS block (of a dlopen()ed library:
# the OpenImageIO plug-in) for an old-glibc one and hand LeakSanitizer a bogus range, whose scan at
# exit crashes the tracer ("Tracer caught signal 11") although nothing leaked.
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1:check_initialization_order=1:strict_init_order=1:intercept_tls_get_addr=0:print_summary=1"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1:print_summary=1"
# Left out here: the default scene cut into 1, 2, 3 and 7 shards and merged (14 whole-scene surfelize runs,
# 270 s of the 700 under the sanitizers on two cores, against 55 s in the Release suite, which runs it). The
# same shard, merge and capture code runs here on the two cities' shard tests and the default scene's
# surfelize tests.
ctest --test-dir build-asan --output-on-failure -j2 -E '^SurfelizeShards\.DefaultScene' "$@"
