#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The server under ThreadSanitizer (the `tsan` preset: RelWithDebInfo, -fsanitize=thread):
# builds only what it runs, then runs every server unit test (tests/server: job store and
# PostgreSQL claims, queue, event log, publishers, pools...) and the integration tests that
# drive the job engine, streaming, shutdown and the PostgreSQL store through real, instrumented
# ispq-server processes (tests/integration).
#
#   tests/tsan/run_tsan.sh [GTEST_FILTER_OF_THE_INTEGRATION_TESTS]
#
# Debian's gRPC, protobuf, abseil and libpq are not instrumented: absl::Mutex is annotated for
# TSan by tests/tsan/absl_sync_annotations.cc, and what remains inside those libraries is
# suppressed by tests/tsan/tsan.supp (each entry says why it is not our race). Every process,
# the servers the tests start included, writes its reports to one folder; exit status 0 only if
# every test passed and there is no report.
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=2  # the machines have 2 cores

# The job engine (lifecycle, cancellation, watchers, deadlines while queued or running),
# streaming over gRPC and HTTP/SSE, the HTTP API, stored meshes, shutdown, idempotency under
# concurrent calls, uploads, and replicas sharing a PostgreSQL store, about 100 s under TSan; and
# every server and client unit test.
INTEGRATION=${1:-"JobLifecycleTest.*:AdmissionTest.*:HttpEventStreamTest.*:HttpApiTest.*:StoredMeshTest.*:ShutdownTest.*:IntermediateQuantizationTest.*:IdempotencyTest.ConcurrentCallsWithOneIdMakeOneJob:MeshUploadTest.AStalledUploadIsDroppedAndItsMemoryReleased:MeshUploadTest.SizesThatDisagreeWithTheDeclarationAreRefused:ReplicasTest.AJobSubmittedToOneReplicaIsWatchedFetchedAndCancelledThroughTheOthers:ReplicasTest.RoundRobinSpreadsCallsOverEveryReplica"}

cmake --preset tsan >/dev/null
cmake --build --preset tsan -j "$JOBS" --target ispq_server_unit_tests ispq_client_unit_tests \
  ispq_service_tests

reports=$(mktemp -d "${TMPDIR:-/tmp}/ispq-tsan.XXXXXX")
trap 'rm -rf "$reports"' EXIT
# halt_on_error: the first report ends the process (a server's ends its test); log_path: the
# reports of the servers (whose stderr is their test's log file) are not lost.
export TSAN_OPTIONS="suppressions=$PWD/tests/tsan/tsan.supp:halt_on_error=1:second_deadlock_stack=1:log_path=$reports/tsan"

status=0
build/tsan/tests/server/ispq_server_unit_tests --gtest_brief=1 || status=1
build/tsan/tests/client/ispq_client_unit_tests --gtest_brief=1 || status=1
build/tsan/tests/integration/ispq_service_tests --gtest_brief=1 --gtest_filter="$INTEGRATION" ||
  status=1

if compgen -G "$reports/tsan.*" >/dev/null; then
  for report in "$reports"/tsan.*; do
    echo "== ThreadSanitizer report of process ${report##*.}"
    cat "$report"
  done
  status=1
fi
exit $status
