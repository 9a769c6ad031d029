# SPDX-License-Identifier: Apache-2.0
"""The HTTP side over TLS (--http_tls_cert/--http_tls_key, by default gRPC's --tls_cert/--tls_key),
against a live server with certificates made here by openssl: /healthz, /readyz, /metrics (parsed
by Prometheus' own parser), the web view, a submission and its event stream answer over HTTPS to a
client that verifies the server against the CA; the same port refuses plaintext HTTP and a client
that does not trust the CA; the HTTP side's own certificate and --http_plaintext override the
default; headless Chromium, trusting the server's key, reaches the web view over HTTPS, follows a
job to its result through the page's event stream and fetches /metrics, and refuses the page
without that trust; and certificate or key files that cannot be used stop the server at start with
an error naming the file."""
import http.client
import json
import os
import shutil
import ssl
import subprocess
import sys
import tempfile
import unittest

from prometheus_client.parser import text_string_to_metric_families

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ispq_http_server as ispq  # noqa: E402
from devtools_pipe import Browser, trust_certificate_flag  # noqa: E402


def openssl(*args, cwd):
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True, timeout=120)


def make_ca(directory, name):
    """A CA (NAME-ca.crt, NAME-ca.key) and a server certificate it signs for localhost and
    127.0.0.1 (NAME.crt, NAME.key); the paths of the CA certificate, the certificate and the key."""
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj",
            f"/CN={name} test CA", "-keyout", f"{name}-ca.key", "-out", f"{name}-ca.crt",
            cwd=directory)
    openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=localhost", "-keyout",
            f"{name}.key", "-out", f"{name}.csr", cwd=directory)
    with open(os.path.join(directory, f"{name}.ext"), "w") as f:
        f.write("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
    openssl("x509", "-req", "-in", f"{name}.csr", "-CA", f"{name}-ca.crt", "-CAkey",
            f"{name}-ca.key", "-CAcreateserial", "-days", "2", "-extfile", f"{name}.ext", "-out",
            f"{name}.crt", cwd=directory)
    return tuple(os.path.join(directory, f) for f in (f"{name}-ca.crt", f"{name}.crt",
                                                      f"{name}.key"))


def https(port, ca_file, method, path, body=None, headers=None, host="localhost"):
    """(status, headers, body text) of one request over TLS, verifying the server against
    `ca_file` (and its name, `host`)."""
    context = ssl.create_default_context(cafile=ca_file)
    return ispq.exchange(http.client.HTTPSConnection(host, port, context=context, timeout=120),
                         method, path, body, headers)


class HttpsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.directory = tempfile.mkdtemp(prefix="ispq-http-tls-")
        cls.ca, cls.cert, cls.key = make_ca(cls.directory, "main")
        cls.other_ca, cls.other_cert, cls.other_key = make_ca(cls.directory, "other")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.directory, ignore_errors=True)

    def test_grpcs_certificate_serves_the_probes_metrics_and_web_view_over_https(self):
        with ispq.Server("--workers=1", f"--tls_cert={self.cert}", f"--tls_key={self.key}") as s:
            self.assertIn("http_tls=true", s.read_log())
            for path, body in (("/healthz", "SERVING"), ("/readyz", "READY")):
                for host in ("localhost", "127.0.0.1"):
                    status, _, text = https(s.http_port, self.ca, "GET", path, host=host)
                    self.assertEqual((status, text.strip()), (200, body), (path, host))
            status, headers, text = https(s.http_port, self.ca, "GET", "/metrics")
            self.assertEqual(status, 200, text)
            self.assertTrue(headers["Content-Type"].startswith("text/plain; version=0.0.4"))
            families = {f.name: f for f in text_string_to_metric_families(text)}
            self.assertEqual(families["ispq_ready"].samples[0].value, 1)
            status, headers, text = https(s.http_port, self.ca, "GET", "/")
            self.assertEqual(status, 200)
            self.assertTrue(headers["Content-Type"].startswith("text/html"), headers)

            # A job submitted and followed to its end over HTTPS: the event stream (a suspended
            # connection resumed as events arrive) works through TLS too.
            body = ('{"mesh":' + ispq.bundled("hex-me/s07c_notch.tmesh.json") +
                    ',"options":{"scaling":{"levelPercent":25}}}')
            status, _, text = https(s.http_port, self.ca, "POST", "/v1/jobs", body=body,
                                    headers=ispq.JSON)
            self.assertEqual(status, 200, text)
            name = json.loads(text)["name"]
            status, headers, text = https(s.http_port, self.ca, "GET", f"/v1/{name}:watch")
            self.assertEqual(status, 200, text)
            self.assertTrue(headers["Content-Type"].startswith("text/event-stream"), headers)
            self.assertIn("event: end", text)
            self.assertIn('"result"', text)

            # The gRPC side keeps the same certificate.
            health = subprocess.run([ispq.CLI, "health", f"--server=localhost:{s.port}",
                                     f"--tls_ca={self.ca}"], capture_output=True, text=True,
                                    timeout=120)
            self.assertEqual(health.returncode, 0, health.stderr)

            # Plaintext HTTP to the TLS port gets no HTTP answer.
            with self.assertRaises((http.client.HTTPException, ConnectionError)):
                s.request("GET", "/healthz", timeout=30)
            # A client that does not trust the server's CA refuses it: it is this certificate.
            with self.assertRaises(ssl.SSLCertVerificationError):
                https(s.http_port, self.other_ca, "GET", "/healthz")

    def test_a_browser_follows_a_job_in_the_web_view_over_https(self):
        with ispq.Server("--workers=1", f"--tls_cert={self.cert}", f"--tls_key={self.key}") as s:
            url = f"https://localhost:{s.http_port}/"
            # Without trust in the server's certificate, the browser refuses the page.
            with Browser() as untrusting:
                navigated = untrusting.call("Page.navigate", {"url": url}, session=True)
                self.assertIn("CERT", navigated.get("errorText", ""), navigated)
            body = ('{"mesh":' + ispq.bundled("hex-me/s07c_notch.tmesh.json") +
                    ',"options":{"scaling":{"levelPercent":100}}}')
            status, _, text = https(s.http_port, self.ca, "POST", "/v1/jobs", body=body,
                                    headers=ispq.JSON)
            self.assertEqual(status, 200, text)
            job_id = json.loads(text)["name"].split("/")[1]
            trust = trust_certificate_flag(self.cert)
            with Browser(extra_args=[trust]) as browser:
                navigated = browser.call("Page.navigate", {"url": url}, session=True)
                self.assertNotIn("errorText", navigated)
                browser.wait_for("document.readyState === 'complete' && "
                                 "document.getElementById('upload-form') !== null")
                self.assertEqual(browser.evaluate("location.protocol"), "https:")
                # The job list (refreshed every second over HTTPS) shows the job; clicking it
                # follows it over an event stream to its result.
                row = f"document.querySelector('#jobs tr[data-job=\"jobs/{job_id}\"]')"
                browser.wait_for(f"{row} !== null", timeout=120)
                browser.evaluate(f"{row}.click()")
                browser.wait_for("!document.getElementById('result').hidden", timeout=120)
                self.assertEqual(browser.evaluate(
                    "document.getElementById('result-valid').textContent"), "yes")
                metrics = browser.evaluate("fetch('/metrics').then(r => r.text())",
                                           await_promise=True)
                self.assertIn("ispq_ready 1", metrics)
                self.assertIn('ispq_jobs_finished_total{state="succeeded"} 1', metrics)

    def test_own_certificate_and_plaintext_override_the_default(self):
        with ispq.Server(f"--tls_cert={self.cert}", f"--tls_key={self.key}",
                         f"--http_tls_cert={self.other_cert}",
                         f"--http_tls_key={self.other_key}") as s:
            self.assertEqual(https(s.http_port, self.other_ca, "GET", "/healthz")[0], 200)
            with self.assertRaises(ssl.SSLCertVerificationError):
                https(s.http_port, self.ca, "GET", "/healthz")
        # HTTPS without TLS on gRPC.
        with ispq.Server(f"--http_tls_cert={self.cert}", f"--http_tls_key={self.key}") as s:
            self.assertEqual(https(s.http_port, self.ca, "GET", "/readyz")[0], 200)
        with ispq.Server(f"--tls_cert={self.cert}", f"--tls_key={self.key}",
                         "--http_plaintext") as s:
            self.assertIn("http_tls=false", s.read_log())
            self.assertEqual(s.request("GET", "/healthz")[0], 200)

    def test_unusable_files_stop_the_server_naming_the_file(self):
        missing = os.path.join(self.directory, "missing.crt")
        cases = [
            # (flags, the file the error must name)
            ([f"--http_tls_cert={missing}", f"--http_tls_key={self.key}"], missing),
            ([f"--http_tls_cert={self.key}", f"--http_tls_key={self.key}"], self.key),
            ([f"--http_tls_cert={self.cert}", f"--http_tls_key={self.cert}"], self.cert),
            ([f"--http_tls_cert={self.cert}", f"--http_tls_key={self.other_key}"],
             self.other_key),
            # By default gRPC's files serve the HTTP side, and are checked as its own.
            ([f"--tls_cert={self.ca}", f"--tls_key={self.key}"], self.ca),
        ]
        for flags, named in cases:
            with self.subTest(flags=flags):
                run = subprocess.run([ispq.SERVER, "--listen=127.0.0.1:0",
                                      "--http_listen=127.0.0.1:0", *flags],
                                     capture_output=True, text=True, timeout=120)
                self.assertEqual(run.returncode, 1, run.stderr)
                self.assertIn("event=start_error", run.stderr)
                self.assertIn(named, run.stderr)


if __name__ == "__main__":
    unittest.main()
