# SPDX-License-Identifier: Apache-2.0
"""A live ispq-server with its HTTP side on free loopback ports, for the HTTP side's Python tests
(tests/http). The binaries, the bundled data and the artifact directory come from the
environment CTest sets (tests/http/CMakeLists.txt). Every wait is bounded. The server dies with
the test process, however that ends (die_with_parent)."""
import http.client
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from child_processes import die_with_parent

SERVER = os.environ.get("ISPQ_SERVER_BINARY", "")
CLI = os.environ.get("ISPQ_CLI", "")
DATA = os.environ.get("ISPQ_TEST_DATA", "")
ARTIFACTS = os.environ.get("ISPQ_TEST_ARTIFACTS", tempfile.gettempdir())
# Bodies are JSON and say so: the server parses no other type.
JSON = {"Content-Type": "application/json"}
# Bounds waits that are not pass/fail conditions (a server starting, a status changing): only a
# hang should reach it on a loaded 2-core machine. The ctest timeout (600 s) is the real bound.
SAFETY_NET = 300


def require_environment():
    for name, value in (("ISPQ_SERVER_BINARY", SERVER), ("ISPQ_CLI", CLI), ("ISPQ_TEST_DATA", DATA)):
        if not value or not os.path.exists(value):
            raise RuntimeError(f"{name} is not set to an existing path (got {value!r}): run through ctest")


def exchange(connection, method, path, body=None, headers=None):
    """(status, headers, body text) of one request on `connection` (HTTP or HTTPS), closed after."""
    try:
        connection.request(method, path, body=body, headers=headers or {})
        response = connection.getresponse()
        return response.status, dict(response.getheaders()), response.read().decode()
    finally:
        connection.close()


class Server:
    """ispq-server on 127.0.0.1:0 for both gRPC and HTTP; stopped with SIGTERM on exit."""

    def __init__(self, *flags, timeout=SAFETY_NET):
        require_environment()
        self.directory = tempfile.mkdtemp(prefix="ispq-http-py-")
        grpc_port_file = os.path.join(self.directory, "port")
        http_port_file = os.path.join(self.directory, "http_port")
        self.log_path = os.path.join(self.directory, "server.log")
        self.log = open(self.log_path, "w")
        self.process = subprocess.Popen(
            [SERVER, "--listen=127.0.0.1:0", f"--port_file={grpc_port_file}",
             "--http_listen=127.0.0.1:0", f"--http_port_file={http_port_file}", *flags],
            stdout=self.log, stderr=self.log, preexec_fn=die_with_parent())
        deadline = time.monotonic() + timeout
        self.port = self.http_port = 0
        while time.monotonic() < deadline and not self.http_port:
            if self.process.poll() is not None:
                log = self.read_log()
                self.log.close()
                raise RuntimeError(f"ispq-server exited: {log}")
            try:
                with open(grpc_port_file) as f:
                    self.port = int(f.read())
                with open(http_port_file) as f:
                    self.http_port = int(f.read())
            except (OSError, ValueError):
                time.sleep(0.02)
        if not self.http_port:
            self.stop()
            raise RuntimeError(f"ispq-server did not listen within {timeout} s: {self.read_log()}")
        self.address = f"127.0.0.1:{self.port}"

    def read_log(self):
        self.log.flush()
        with open(self.log_path) as f:
            return f.read()

    def stop(self, keep_log=False):
        """Stops the server and removes its directory, unless `keep_log` (its path is printed)."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=40)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.log.close()
        if keep_log:
            print(f"ispq-server's log: {self.log_path}", file=sys.stderr)
        else:
            shutil.rmtree(self.directory, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *exc):
        self.stop(keep_log=exc_type is not None)  # a failed test keeps the log to read

    # ---- HTTP ----

    def request(self, method, path, body=None, headers=None, timeout=120):
        """(status, headers, body text) of one request on a fresh connection."""
        return exchange(http.client.HTTPConnection("127.0.0.1", self.http_port, timeout=timeout),
                        method, path, body, headers)

    def json(self, method, path, body=None):
        status, _, text = self.request(method, path, body=body, headers=JSON)
        if status != 200:
            raise AssertionError(f"{method} {path}: {status} {text}")
        return json.loads(text)

    def submit(self, mesh_text, level, **fields):
        """POST /v1/jobs with the T-mesh JSON text at a resolution level; the Job."""
        extra = "".join(f",{json.dumps(k)}:{json.dumps(v)}" for k, v in fields.items())
        body = ('{"mesh":' + mesh_text + ',"options":{"scaling":{"levelPercent":' + str(level) +
                '}}' + extra + '}')
        return self.json("POST", "/v1/jobs", body)

    def metric(self, sample):
        """The value of one /metrics sample, e.g. 'ispq_http_refused_total{status="415"}'."""
        status, _, text = self.request("GET", "/metrics")
        assert status == 200, (status, text)
        for line in text.splitlines():
            name, _, value = line.rpartition(" ")
            if name == sample:
                return float(value)
        raise KeyError(sample)

    def wait_done(self, name, timeout=300):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            job = self.json("GET", f"/v1/{name}")
            if job["state"] in ("SUCCEEDED", "FAILED", "CANCELLED"):
                return job
            time.sleep(0.05)
        raise AssertionError(f"{name} did not end within {timeout} s")


def bundled(name):
    with open(os.path.join(DATA, name)) as f:
        return f.read()


def validate(mesh_path, result, level):
    """The product's validator (`ispq validate`) on a result; its verdict as a dict."""
    with tempfile.NamedTemporaryFile("w", suffix=".result.json", delete=False) as f:
        json.dump(result, f)
        result_path = f.name
    try:
        run = subprocess.run([CLI, "validate", mesh_path, "--result", result_path, "--level",
                              str(level), "--json"], capture_output=True, text=True, timeout=120)
        verdict = json.loads(run.stdout) if run.stdout.strip() else {}
        verdict["exit_code"] = run.returncode
        verdict["stderr"] = run.stderr
        return verdict
    finally:
        os.unlink(result_path)
