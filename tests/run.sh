#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The whole test suite, from a fresh checkout: installs what is missing, builds (Release) and
# runs every test with CTest, checks the lock annotations with clang's thread-safety analysis,
# runs the core unit tests once more under AddressSanitizer and UndefinedBehaviorSanitizer, the
# server's unit tests and part of its integration tests under ThreadSanitizer, and fuzzes the
# request parser and loader for a bounded time.
# `.ci/run` calls exactly this. It needs nothing beside the checkout: the tests' data is in
# tests/data, and the Standalone test (tests/deploy/check_standalone.py) fails if anything in
# the tree refers to a path outside the checkout.
set -euo pipefail
cd "$(dirname "$0")/.."

bash deploy/install-deps.sh

JOBS=2  # the machines have 2 cores

cmake --preset release >/dev/null
cmake --build --preset release -j "$JOBS"
ctest --preset release -j "$JOBS" --timeout 900

# About 220 s of CPU (84 TUs, syntax only; ~2 min of wall on 2 idle cores); nothing is cached.
echo "== clang thread-safety analysis of the server, client and threaded tests (syntax only) =="
python3 tests/static/check_thread_safety.py --build build/release --jobs "$JOBS"

echo "== core unit tests under ASan/UBSan =="
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$JOBS" --target ispq_unit_tests
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  build/asan/tests/core/ispq_unit_tests --gtest_brief=1

# Cold: ~700 s of CPU to build (231 steps; 10 min of wall on a shared 2-core machine), then
# ~100 s of tests; with a warm ccache the build takes ~20 s.
echo "== server unit tests and job-engine/streaming/store integration tests under TSan =="
bash tests/tsan/run_tsan.sh

echo "== fuzzing the T-mesh and request parsers, 30 s per target =="
bash tests/fuzz/run_fuzzers.sh 30
