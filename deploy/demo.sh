#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The README's first command: installs what is missing, builds, starts the quantization server
# (ispq-server, default flags) in the background, quantizes a bundled real T-mesh through the
# client with live progress, prints the result summary and stops the server gracefully.
set -euo pipefail
cd "$(dirname "$0")/.."

bash deploy/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j 2 --target ispq ispq-server

BIN=build/release
SAMPLE=tests/data/tmesh/hex-me/s07c_notch.tmesh.json
WORK=$(mktemp -d)
SERVER_LOG="$WORK/ispq-server.log"
SERVER_PID=""

stop_server() {
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -TERM "$SERVER_PID"
    wait "$SERVER_PID" || true
  fi
}
trap stop_server EXIT

# Starts the server with `$@` and waits until it has written its port; fails if it exits.
start_server() {
  rm -f "$WORK/port"
  "$BIN/server/ispq-server" --port_file "$WORK/port" "$@" 2>"$SERVER_LOG" &
  SERVER_PID=$!
  for _ in $(seq 1 200); do
    if [ -s "$WORK/port" ]; then return 0; fi
    if ! kill -0 "$SERVER_PID" 2>/dev/null; then return 1; fi
    sleep 0.05
  done
  return 1
}

echo "== starting ispq-server (defaults: 127.0.0.1:50051, one worker per hardware thread)"
if ! start_server; then
  echo "   port 50051 is taken (another server?); using a free port instead"
  cat "$SERVER_LOG"
  start_server --listen 127.0.0.1:0
fi
SERVER="127.0.0.1:$(cat "$WORK/port")"
head -n 1 "$SERVER_LOG"
"$BIN/client/ispq" health --server "$SERVER"

echo "== the T-mesh"
"$BIN/client/ispq" stats "$SAMPLE"

echo "== quantizing it on the server at resolution level 100 (progress on stderr)"
"$BIN/client/ispq" quantize "$SAMPLE" --server "$SERVER" --level 100 --out "$WORK/result.json"
echo "   result JSON: $WORK/result.json"
"$BIN/client/ispq" validate "$SAMPLE" --result "$WORK/result.json" --level 100

echo "== jobs on the server"
"$BIN/client/ispq" jobs --server "$SERVER"

echo "== stopping the server (SIGTERM: graceful shutdown)"
stop_server
SERVER_PID=""
grep -E "event=(job_start|job_end|shutdown_end|server_exit)" "$SERVER_LOG"
