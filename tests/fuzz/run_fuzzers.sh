#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets (the `fuzz` preset: clang, ASan, UBSan) and runs each for a bounded
# time, seeded with the real T-meshes of tests/data/tmesh. The test command runs it with
# 30 s per target; run it longer by hand, e.g. `tests/fuzz/run_fuzzers.sh 3600`.
#
#   tests/fuzz/run_fuzzers.sh [SECONDS_PER_TARGET]   (default 30)
#
# Exit status 0 only if no target found anything (crash, sanitizer report, leak, timeout of a
# single input, out-of-memory, or a result called valid that the validator rejects). Findings are
# written to build/fuzz/findings/; the corpora grow in build/fuzz/corpus/.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-30}

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j 2

out=build/fuzz
mkdir -p "$out/corpus/tmesh_json" "$out/corpus/quantize_request" "$out/corpus/tmesh_wire" \
  "$out/findings" "$out/seeds" "$out/seeds_binary"
cp tests/data/tmesh/*/*.tmesh.json "$out/seeds/"
"$out/tests/fuzz/ispq_fuzz_seeds" "$out/corpus/quantize_request" "$out/seeds_binary" >/dev/null

status=0
run() {  # target corpus [seed dirs]
  local target=$1 corpus=$2; shift 2
  echo "== $target, ${seconds}s"
  # -rss_limit_mb bounds memory per process; -timeout flags any single input slower than 20 s.
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$out/tests/fuzz/ispq_$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 \
      -max_len=2000000 -print_final_stats=1 -artifact_prefix="$out/findings/$target-" \
      "$corpus" "$@" 2>"$out/$target.log"; then
    status=1
    echo "FINDING: $target (see $out/$target.log and $out/findings/)"
    tail -n 30 "$out/$target.log"
  fi
  grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$out/$target.log" | sed 's/^/  /'
}
run tmesh_json_fuzzer "$out/corpus/tmesh_json" "$out/seeds"
run quantize_request_fuzzer "$out/corpus/quantize_request"
run tmesh_wire_fuzzer "$out/corpus/tmesh_wire" "$out/seeds_binary"
exit $status
