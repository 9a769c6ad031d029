# SPDX-License-Identifier: Apache-2.0
"""The HTTP side bounded before it trusts anything (issue 24): every attack of the issue's table
against a live ispq-server with a 256 MiB memory budget, asserting what the server answers, how
much of an attack it reads and how much memory it takes (its peak resident set, /proc/PID/status),
and that the probes and the job routes keep answering while hundreds of slow and idle clients
hold connections. The figures are printed (ctest -V) and collected by http_attack_report.py."""
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import http_attacks as attacks  # noqa: E402
import ispq_http_server as ispq  # noqa: E402

# What a refusal may read beyond the limit: the kernel's socket buffers on loopback.
BUFFERS_MIB = 16
# Resident memory an attack may add to the server's (the target: budget + 64 MiB).
MARGIN_MIB = 64


def show(name, figures):
    print(f"\n{name}: {json.dumps(figures, default=str)}", flush=True)


class BodyBoundsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = ispq.Server(attacks.BUDGET_FLAG, "--max_message_bytes=4194304", "--workers=1")

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()

    def test_compressed_bodies_are_refused_unread(self):
        for coding in ("gzip", "deflate"):
            figures = attacks.compressed_body(self.server, coding)
            show(f"{coding} body", figures)
            self.assertEqual(figures["status"], 415, figures)
            self.assertEqual(json.loads(figures["body"])["status"], "INVALID_ARGUMENT")
            self.assertLess(figures["peak_mib"] - figures["rss_before_mib"], BUFFERS_MIB, figures)

    def test_chunked_body_stops_at_the_limit(self):
        figures = attacks.chunked_body(self.server)
        show("chunked 512 MiB body, 4 MiB limit", figures)
        self.assertEqual(figures["status"], 413, figures)
        self.assertIn(b"--max_message_bytes", figures["body"])
        self.assertLess(figures["sent_mib"], 4 + BUFFERS_MIB, figures)
        self.assertLess(figures["peak_mib"] - figures["rss_before_mib"], 2 * 4 + BUFFERS_MIB,
                        figures)

    def test_body_without_length_is_411(self):
        figures = attacks.unframed_body(self.server)
        self.assertEqual(figures["status"], 411, figures)
        self.assertIn(b"Content-Length", figures["body"])

    def test_deep_json_is_refused_before_parsing(self):
        figures = attacks.nested_bodies(self.server)
        show("JSON nested 10^3..10^6 deep, then eight 1 MB of [", figures)
        self.assertEqual(set(figures["statuses"].values()), {400}, figures)
        self.assertEqual(figures["eight"], {400: 8}, figures)
        self.assertLess(figures["peak_mib"] - figures["rss_before_mib"], BUFFERS_MIB, figures)
        status, text = attacks.nested_json(self.server, 10**4)
        self.assertIn(b"deeper than 64 levels", text)

    def test_header_floods_are_cut_short(self):
        figures = attacks.header_floods(self.server)
        show("header floods", figures)
        expected = {"header lines": 431, "one header": 431, "request line": 414}
        for name, status in expected.items():
            self.assertEqual(figures[name]["status"], status, (name, figures[name]))
            self.assertLess(figures[name]["sent_mib"], BUFFERS_MIB, (name, figures[name]))
            self.assertLess(figures[name]["peak_mib"] - figures[name]["rss_before_mib"],
                            BUFFERS_MIB, (name, figures[name]))
        # Within the connection's memory pool, the server's own checks answer, in JSON.
        port = self.server.http_port
        long_target = attacks.exchange(self.server, f"GET /healthz?a={'a' * 9000} HTTP/1.1\r\n"
                                       f"Host: 127.0.0.1:{port}\r\n\r\n".encode())
        self.assertEqual(long_target[0], 414)
        many = "".join(f"X-{i}: a\r\n" for i in range(101))
        many_headers = attacks.exchange(self.server, f"GET /healthz HTTP/1.1\r\n"
                                        f"Host: 127.0.0.1:{port}\r\n{many}\r\n".encode())
        self.assertEqual(many_headers[0], 431)
        self.assertEqual(json.loads(many_headers[2])["status"], "RESOURCE_EXHAUSTED")

    def test_the_server_still_serves(self):
        self.assertEqual(self.server.request("GET", "/healthz")[0], 200)
        job = self.server.submit(ispq.bundled("hex-me/s07c_notch.tmesh.json"), 10)
        self.assertEqual(self.server.wait_done(job["name"], timeout=120)["state"], "SUCCEEDED")


class AuthenticatedBodyTest(unittest.TestCase):
    def test_compressed_body_is_refused_before_authentication(self):
        token_file = os.path.join(ispq.ARTIFACTS, "http_bounds_token")
        os.makedirs(ispq.ARTIFACTS, exist_ok=True)
        with open(token_file, "w") as f:
            f.write("s3cret-token\n")
        with ispq.Server(attacks.BUDGET_FLAG, f"--auth_token_file={token_file}") as server:
            figures = attacks.compressed_body(server, "gzip")
            show("gzip body, tokens configured, none sent", figures)
            self.assertEqual(figures["status"], 415, figures)
            self.assertLess(figures["peak_mib"] - figures["rss_before_mib"], BUFFERS_MIB, figures)
            figures = attacks.compressed_body(server, "gzip", token="s3cret-token")
            self.assertEqual(figures["status"], 415, figures)
            status, _, _ = attacks.post_json(server, "/v1/jobs", attacks.notch_request(),
                                             [("Content-Type", "application/json")])
            self.assertEqual(status, 401)


class ConcurrentBodiesTest(unittest.TestCase):
    def test_bodies_are_reserved_as_they_arrive(self):
        with ispq.Server(attacks.BUDGET_FLAG, "--workers=1") as server:
            figures = attacks.concurrent_bodies(server)
            show("40 bodies of 30 MiB at once", figures)
            statuses = figures["statuses"]
            self.assertEqual(sum(statuses.values()), 40, figures)
            self.assertLessEqual(set(statuses), {200, 429, 503}, figures)  # all answered
            self.assertGreater(statuses.get(429, 0) + statuses.get(503, 0), 0, figures)
            self.assertLessEqual(figures["peak_mib"], attacks.BUDGET / attacks.MiB + MARGIN_MIB,
                                 figures)
            self.assertEqual(server.request("GET", "/healthz")[0], 200)


class SlowClientsTest(unittest.TestCase):
    def test_probes_and_jobs_answer_during_300_slow_and_300_idle_connections(self):
        with ispq.Server(attacks.BUDGET_FLAG, "--workers=1") as server:
            figures = attacks.slow_and_idle(server, seconds=20)
            show("300 slow + 300 idle connections, 20 s", figures)
            for path, minimum in (("/healthz", 100), ("/readyz", 50), ("/metrics", 20)):
                self.assertEqual(set(figures[path]["statuses"]), {200}, (path, figures[path]))
                self.assertGreaterEqual(figures[path]["n"], minimum, (path, figures[path]))
            jobs = figures["jobs"]
            self.assertGreater(jobs.get("http_SUCCEEDED", 0), 0, jobs)
            self.assertGreater(jobs.get("grpc_valid", 0), 0, jobs)
            self.assertEqual(jobs.get("http_failed", 0) + jobs.get("grpc_failed", 0), 0, jobs)
            # The slow connections were let go of (head and idle deadlines) and came back.
            connections = figures["connections"]
            self.assertGreater(connections.get("closed_by_server_slow", 0), 0, connections)
            self.assertGreater(server.metric("ispq_http_late_connections_total"), 0)
            self.assertGreater(connections.get("closed_by_server_idle", 0), 0, connections)
            self.assertLessEqual(figures["peak_mib"], attacks.BUDGET / attacks.MiB + MARGIN_MIB)


class CrossSiteTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = ispq.Server(attacks.BUDGET_FLAG, "--workers=1")

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()

    def test_cross_site_and_rebound_requests_are_refused(self):
        figures = attacks.cross_site(self.server)
        show("cross-site", figures)
        self.assertEqual(figures["text_plain_form"], 415)
        self.assertEqual(figures["foreign_origin"], 403)
        self.assertEqual(figures["foreign_host_post"], 421)
        self.assertEqual(figures["foreign_host_list"], 421)
        self.assertEqual(figures["own_origin"], 200)
        self.assertEqual(figures["jobs_created"], 1, figures)  # the own origin's only
        # Probes answer whatever the Host, as orchestrators send the pod's address.
        for path in ("/healthz", "/readyz", "/metrics"):
            status = attacks.exchange(self.server, attacks.head(self.server, "GET", path,
                                                                host="10.1.2.3:8080"))[0]
            self.assertEqual(status, 200, path)

    def test_only_json_is_parsed(self):
        refused = 'ispq_http_refused_total{status="415"}'
        before = self.server.metric(refused)
        figures = attacks.content_types(self.server)
        self.assertEqual(self.server.metric(refused) - before, 4)
        show("content types", figures)
        self.assertEqual(figures, {"text/plain": 415, "application/xml": 415, "image/png": 415,
                                   "missing": 415})

    def test_nul_bom_duplicates_and_bad_utf8_are_400(self):
        figures = attacks.lenient_json(self.server)
        show("lenient JSON", {k: [v[0], v[1][:120]] for k, v in figures.items()})
        for name, (status, text) in figures.items():
            self.assertEqual(status, 400, (name, text))
        self.assertIn(b"NUL", figures["raw NUL"][1])
        self.assertIn(b"byte order mark", figures["BOM"][1])
        self.assertIn(b"repeats the key", figures["duplicate keys"][1])
        self.assertIn(b"UTF-8", figures["invalid UTF-8"][1])


class AllowedHostsTest(unittest.TestCase):
    def test_configured_names_replace_the_defaults(self):
        with ispq.Server("--http_allowed_hosts=ispq.example.com,proxy.example:8443") as server:
            for host, expected in (("ispq.example.com", 200),
                                   (f"ispq.example.com:{server.http_port}", 200),
                                   ("proxy.example:8443", 200), ("proxy.example:80", 421),
                                   (f"127.0.0.1:{server.http_port}", 421)):
                status = attacks.exchange(server, attacks.head(server, "GET", "/v1/jobs",
                                                               host=host))[0]
                self.assertEqual(status, expected, host)

    def test_malformed_names_are_refused_at_startup(self):
        with self.assertRaises(RuntimeError) as refused:
            ispq.Server("--http_allowed_hosts=http://x")
        self.assertIn("--http_allowed_hosts entry", str(refused.exception))


if __name__ == "__main__":
    unittest.main()
