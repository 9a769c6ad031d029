#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The benchmark report in one command: builds the benchmark, runs ISP (with its lower bound,
# timed side by side without it), ISP without mixed-sign sheets and exact mode on every real
# T-mesh at all 8 levels, and turns the tables into a self-contained HTML page with PNG plots
# that reproduce the ISP paper's Figs. 8, 11, 13 and 14 and its headline claims on our data and
# our machine (tests/bench/report/make_report.py).
#
#   tests/bench/report/make_report.sh [OUT_DIR]      (default build/report)
#
# Environment: EXACT_TIME_LIMIT (seconds per exact run, default 60), REPEAT (ISP runs per
# instance, the fastest kept; default 3), SKIP_RUNS=1 to redraw from the tables already in
# OUT_DIR. Takes a few minutes on 2 cores; run it on an otherwise idle machine for timings.
set -euo pipefail
cd "$(dirname "$0")/../../.."
out=${1:-build/report}
exact_limit=${EXACT_TIME_LIMIT:-60}
repeat=${REPEAT:-3}
mkdir -p "$out"

if [ "${SKIP_RUNS:-0}" != 1 ]; then
  cmake --preset release >/dev/null
  cmake --build --preset release -j 2 --target ispq_bench
  bench=build/release/tests/bench/ispq_bench
  echo "== ISP, with its lower bound; then without and with it, side by side"
  "$bench" --out "$out/isp.tsv" --trace_out "$out/isp_trace.tsv" --lower_bound on \
    --repeat "$repeat" --compare_lower_bound | tee "$out/isp_summary.txt"
  echo "== ISP without mixed-sign sheets"
  "$bench" --out "$out/isp_uniform.tsv" --mixed_sign=false --lower_bound off \
    | tee "$out/isp_uniform_summary.txt"
  echo "== exact mode, ${exact_limit} s per run"
  "$bench" --out "$out/exact.tsv" --trace_out "$out/exact_trace.tsv" --method exact \
    --time_limit "$exact_limit" | tee "$out/exact_summary.txt"
fi

# Debian's interpreter, where python3-matplotlib is installed (a python3 earlier on PATH may be
# another installation without it).
python=/usr/bin/python3
[ -x "$python" ] || python=python3
"$python" tests/bench/report/make_report.py --data "$out" --reference tests/data/reference \
  --out "$out/report.html"
