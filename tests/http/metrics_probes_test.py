# SPDX-License-Identifier: Apache-2.0
"""/metrics, /healthz and /readyz of the HTTP side against a live server: the metrics parse with
Prometheus' own text-format parser (python3-prometheus-client) and follow what the server does
(accepted and finished jobs, rejections by reason, histograms, queue, memory); readiness turns
503 while the queue is full and 200 again when it drains."""
import json
import os
import sys
import unittest

from prometheus_client.parser import text_string_to_metric_families

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ispq_http_server as ispq  # noqa: E402
from tmesh_copies import disjoint_copies  # noqa: E402


def scrape(server):
    status, headers, text = server.request("GET", "/metrics")
    assert status == 200, (status, text)
    assert headers["Content-Type"].startswith("text/plain; version=0.0.4"), headers
    families = {family.name: family for family in text_string_to_metric_families(text)}
    return families


def sample(families, family, name=None, **labels):
    for s in families[family].samples:
        if (name is None or s.name == name) and all(s.labels.get(k) == v for k, v in labels.items()):
            return s.value
    raise KeyError(f"{family} {name} {labels}")


class MetricsTest(unittest.TestCase):
    def test_metrics_parse_and_follow_the_jobs(self):
        with ispq.Server("--workers=1") as server:
            before = scrape(server)
            expected = {
                "ispq_jobs": "gauge", "ispq_jobs_finished": "counter",
                "ispq_jobs_accepted": "counter", "ispq_requests_rejected": "counter",
                "ispq_evictions": "counter", "ispq_queue_length": "gauge",
                "ispq_busy_workers": "gauge", "ispq_workers": "gauge",
                "ispq_solve_seconds": "histogram", "ispq_queue_wait_seconds": "histogram",
                "ispq_memory_budget_bytes": "gauge", "ispq_memory_used_bytes": "gauge",
                "ispq_memory_used_by_kind_bytes": "gauge", "ispq_ready": "gauge",
                "ispq_http_event_streams": "gauge", "ispq_http_connections": "gauge",
                "ispq_http_refused": "counter", "ispq_http_late_connections": "counter",
            }
            for name, kind in expected.items():
                self.assertIn(name, before, f"{name} missing from /metrics")
                self.assertEqual(before[name].type, kind, name)
            self.assertEqual(sample(before, "ispq_jobs_accepted", "ispq_jobs_accepted_total"), 0)
            self.assertEqual(sample(before, "ispq_workers"), 1)
            self.assertEqual(sample(before, "ispq_ready"), 1)
            self.assertGreater(sample(before, "ispq_memory_budget_bytes"), 0)

            mesh = ispq.bundled("hex-me/s07c_notch.tmesh.json")
            names = [server.submit(mesh, level)["name"] for level in (10, 25, 100)]
            for name in names:
                job = server.wait_done(name)
                self.assertEqual(job["state"], "SUCCEEDED")
                verdict = ispq.validate(os.path.join(ispq.DATA, "hex-me/s07c_notch.tmesh.json"),
                                        job["result"], job["options"]["scaling"]["levelPercent"])
                self.assertTrue(verdict.get("valid"), verdict)
            status, _, _ = server.request("POST", "/v1/jobs", body='{"mesh": {"arcs": [{"length": -1}]}}',
                                          headers=ispq.JSON)
            self.assertEqual(status, 400)

            after = scrape(server)
            self.assertEqual(sample(after, "ispq_jobs_accepted", "ispq_jobs_accepted_total"), 3)
            self.assertEqual(sample(after, "ispq_jobs_finished", "ispq_jobs_finished_total",
                                    state="succeeded"), 3)
            self.assertEqual(sample(after, "ispq_jobs", state="succeeded"), 3)
            self.assertEqual(sample(after, "ispq_requests_rejected", "ispq_requests_rejected_total",
                                    reason="invalid"), 1)
            self.assertEqual(sample(after, "ispq_solve_seconds", "ispq_solve_seconds_count"), 3)
            self.assertEqual(sample(after, "ispq_solve_seconds", "ispq_solve_seconds_bucket",
                                    le="+Inf"), 3)
            self.assertGreater(sample(after, "ispq_solve_seconds", "ispq_solve_seconds_sum"), 0)
            self.assertEqual(sample(after, "ispq_queue_wait_seconds",
                                    "ispq_queue_wait_seconds_count"), 3)
            self.assertGreater(sample(after, "ispq_memory_used_by_kind_bytes", kind="results"), 0)
            # The same numbers as gRPC's GetServerStats (through the CLI).
            stats = json.loads(ispq.subprocess.run(
                [ispq.CLI, "server-stats", "--server", server.address], capture_output=True,
                text=True, timeout=60).stdout)
            self.assertEqual(int(stats["acceptedTotal"]), 3)
            self.assertEqual(int(stats["rejectedInvalidTotal"]), 1)


FEMUR = ("2017_-_Explicit_Cylindrical_Maps_for_General_Tubular_Shapes_femur_shell1"
         ".tmesh.json")


class ProbesTest(unittest.TestCase):
    def test_health_and_readiness(self):
        # One worker, one queue slot: a running job plus a queued one fill the server.
        with ispq.Server("--workers=1", "--max_queued_jobs=1") as server:
            self.assertEqual(server.request("GET", "/healthz")[0], 200)
            self.assertEqual(server.request("GET", "/readyz")[0], 200)
            # Jobs that are still running when the test acts: of the real meshes, femur_shell1
            # costs the most solve time per byte (0.43 s at level 100 for 257 KB), so 20 copies
            # run for several seconds in a request of 5 MB, on any machine and however fast the
            # quantizer becomes (120 copies of the notch took 0.7 s and finished too soon).
            femur = os.path.join(ispq.DATA, "metamesh-guided-hexalab", FEMUR)
            with open(femur) as f:
                long_mesh = json.dumps(disjoint_copies(json.load(f), 20))
            running = server.submit(long_mesh, 100)["name"]
            queued = server.submit(long_mesh, 100)["name"]
            status, headers, text = server.request(
                "POST", "/v1/jobs", body='{"mesh":' + long_mesh + ',"options":{"scaling":{"levelPercent":100}}}',
                headers=ispq.JSON)
            self.assertEqual(status, 429, text)  # RESOURCE_EXHAUSTED: the queue is full
            self.assertIn("Retry-After", headers)
            self.assertEqual(json.loads(text)["status"], "RESOURCE_EXHAUSTED")
            status, _, text = server.request("GET", "/readyz")
            self.assertEqual(status, 503, text)
            self.assertEqual(server.request("GET", "/healthz")[0], 200)  # alive though busy
            families = scrape(server)
            self.assertEqual(sample(families, "ispq_ready"), 0)
            self.assertEqual(sample(families, "ispq_queue_length"), 1)
            self.assertEqual(sample(families, "ispq_busy_workers"), 1)
            self.assertEqual(sample(families, "ispq_requests_rejected",
                                    "ispq_requests_rejected_total", reason="queue_full"), 1)
            for name in (queued, running):
                server.json("POST", f"/v1/{name}:cancel", "")
            for name in (queued, running):
                server.wait_done(name)
            # The readiness monitor polls; give it a moment (bounded only against a hang: how soon
            # it notices depends on the machine's load).
            deadline = ispq.time.monotonic() + ispq.SAFETY_NET
            while server.request("GET", "/readyz")[0] != 200 and ispq.time.monotonic() < deadline:
                ispq.time.sleep(0.05)
            self.assertEqual(server.request("GET", "/readyz")[0], 200)


if __name__ == "__main__":
    unittest.main()
