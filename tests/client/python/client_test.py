# SPDX-License-Identifier: Apache-2.0
"""The Python client (client/python, package ispq) against a live ispq-server: every call of the
service, progress callbacks, errors as IspqError with the server's code and message, bearer
tokens, T-mesh files in both formats, and `pip install` of the package from its sources. Every
result goes through the product's validator (`ispq validate`) and equals `ispq quantize --local`.
Runs with Debian's python3-grpcio and python3-protobuf; the stubs come from this build
(tests/client/python/CMakeLists.txt sets PYTHONPATH)."""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import faulthandler
import grpc

import ispq
from ispq.v1 import tmesh_pb2

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "http"))
from child_processes import die_with_parent  # noqa: E402

SERVER = os.environ.get("ISPQ_SERVER_BINARY", "")
CLI = os.environ.get("ISPQ_CLI", "")
DATA = os.environ.get("ISPQ_TEST_DATA", "")
SOURCE_DIR = os.environ.get("ISPQ_SOURCE_DIR", "")
MAKE_LARGE_TMESH = os.environ.get("ISPQ_MAKE_LARGE_TMESH", "")
SAFETY_NET = 300  # bounds waits on a loaded machine; ctest's timeout is the real bound
NOTCH = "hex-me/s07c_notch.tmesh.json"
PRISM = "hex-me/s02c_prism.tmesh.json"


def mesh_path(name):
    return os.path.join(DATA, name)


class Server:
    """ispq-server on 127.0.0.1:0 (gRPC only; a later --listen flag overrides it); SIGTERM on exit;
    dies with the test."""

    def __init__(self, *flags):
        self.directory = tempfile.mkdtemp(prefix="ispq-python-client-")
        port_file = os.path.join(self.directory, "port")
        self.log = open(os.path.join(self.directory, "server.log"), "w")
        self.process = subprocess.Popen([SERVER, "--listen=127.0.0.1:0", f"--port_file={port_file}",
                                         *flags], stdout=self.log, stderr=self.log,
                                        preexec_fn=die_with_parent())
        deadline = time.monotonic() + SAFETY_NET
        self.address = None
        while self.address is None and time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise RuntimeError(f"ispq-server exited with {self.process.returncode}")
            try:
                with open(port_file) as f:
                    self.address = f"127.0.0.1:{int(f.read())}"
            except (OSError, ValueError):
                time.sleep(0.02)
        if self.address is None:
            self.__exit__()
            raise RuntimeError("ispq-server did not listen")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=40)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.log.close()
        shutil.rmtree(self.directory, ignore_errors=True)


def validate(name, result, level):
    """`ispq validate` on a result; asserts nothing, returns the verdict."""
    with tempfile.NamedTemporaryFile("w", suffix=".result.json", delete=False) as f:
        f.write(result.to_json())
    try:
        run = subprocess.run([CLI, "validate", mesh_path(name), "--result", f.name, "--level",
                              str(level), "--json"], capture_output=True, text=True, timeout=120)
        return json.loads(run.stdout) if run.stdout.strip() else {"stderr": run.stderr}
    finally:
        os.unlink(f.name)


def local_q(name, level):
    """q of `ispq quantize --local` (ISP is deterministic: the server must give the same)."""
    with tempfile.TemporaryDirectory() as directory:
        out = os.path.join(directory, "result.json")
        subprocess.run([CLI, "quantize", mesh_path(name), "--local", "--level", str(level),
                        "--out", out], check=True, capture_output=True, timeout=SAFETY_NET)
        with open(out) as f:
            return [int(x) for x in json.load(f)["q"]]


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for name, value in (("ISPQ_SERVER_BINARY", SERVER), ("ISPQ_CLI", CLI), ("ISPQ_TEST_DATA", DATA),
                            ("ISPQ_MAKE_LARGE_TMESH", MAKE_LARGE_TMESH)):
            if not value or not os.path.exists(value):
                raise RuntimeError(f"{name} is not an existing path ({value!r}): run through ctest")
        cls.server = Server("--workers=2")
        cls.client = ispq.Client(cls.server.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.__exit__()

    def assert_valid_and_local(self, name, result, level):
        verdict = validate(name, result, level)
        self.assertTrue(verdict.get("valid"), verdict)
        self.assertTrue(result.valid)
        self.assertEqual(result.q, local_q(name, level))

    def test_quantize_streams_progress_and_returns_the_local_answer(self):
        seen = []
        result = self.client.quantize(mesh_path(NOTCH), level=25, on_progress=seen.append,
                                      intermediate_interval=0.01)
        self.assert_valid_and_local(NOTCH, result, 25)
        self.assertTrue(result.job.startswith("jobs/"))
        self.assertEqual(result.termination, "CONVERGED")
        self.assertGreater(result.stats.lp_solves, 0)
        self.assertTrue(seen, "no progress reached the callback")
        self.assertTrue(all(p.job == result.job for p in seen))
        self.assertTrue({p.phase for p in seen} <= {"LAYERS", "GREEDY", "SEPARATION", "FAILSAFE",
                                                    "FINAL"}, seen)
        for p in seen:
            if p.q is not None:
                self.assertEqual(len(p.q), len(result.q))

    def test_an_exception_in_the_callback_cancels_the_job(self):
        # A 10k-arc part in exact mode runs for its whole time limit unless cancelled.
        with tempfile.TemporaryDirectory() as directory:
            part = os.path.join(directory, "part.tmesh.pb")
            subprocess.run([MAKE_LARGE_TMESH, "--family=single", "--arcs=10000", f"--out={part}"],
                           check=True, capture_output=True, timeout=SAFETY_NET)
            jobs = []

            def stop(progress):
                jobs.append(progress.job)
                raise KeyboardInterrupt()

            with self.assertRaises(KeyboardInterrupt):
                self.client.quantize(part, level=100, method="exact", time_limit=120,
                                     on_progress=stop)
        deadline = time.monotonic() + SAFETY_NET
        job = self.client.get(jobs[0])
        while not job.done and time.monotonic() < deadline:
            time.sleep(0.05)
            job = self.client.get(jobs[0])
        self.assertEqual(job.state, ispq.v1.service_pb2.CANCELLED, job)

    def test_submit_watch_get_list_cancel(self):
        job = self.client.submit(mesh_path(PRISM), level=50, request_id="python-client-test-1")
        self.assertTrue(job.name.startswith("jobs/"))
        again = self.client.submit(mesh_path(PRISM), level=50, request_id="python-client-test-1")
        self.assertEqual(again.name, job.name, "a retried submission made a second job")
        with self.assertRaises(ispq.IspqError) as refused:  # same id, another request
            self.client.submit(mesh_path(PRISM), level=25, request_id="python-client-test-1")
        self.assertEqual(refused.exception.code, grpc.StatusCode.ALREADY_EXISTS)

        result = self.client.watch(job)
        self.assert_valid_and_local(PRISM, result, 50)
        stored = self.client.get(job.name)
        self.assertEqual(stored.state, ispq.v1.service_pb2.SUCCEEDED)
        self.assertEqual(list(stored.result.q), result.q)
        self.assertEqual(len(self.client.get(job, full=False).result.q), 0)
        self.assertIn(job.name, [j.name for j in self.client.jobs(state="SUCCEEDED")])
        self.assertNotIn(job.name, [j.name for j in self.client.jobs(state="FAILED")])
        # A watch from the job's last event on still ends with the result.
        self.assertEqual(self.client.watch(job, from_event=stored.event_count - 1).q, result.q)
        after = self.client.cancel(job)  # ended: nothing changes
        self.assertEqual(after.state, ispq.v1.service_pb2.SUCCEEDED)

    def test_stored_meshes(self):
        mesh = self.client.create_mesh(mesh_path(NOTCH))
        self.assertTrue(mesh.name.startswith("meshes/"))
        self.assertEqual(self.client.get_mesh(mesh.name).mesh_stats, mesh.mesh_stats)
        for source in (mesh, mesh.name):
            self.assert_valid_and_local(NOTCH, self.client.quantize(source, level=10), 10)
        self.client.delete_mesh(mesh)
        with self.assertRaises(ispq.IspqError) as gone:
            self.client.get_mesh(mesh)
        self.assertEqual(gone.exception.code, grpc.StatusCode.NOT_FOUND)

    def test_server_stats_count_the_jobs(self):
        before = self.client.server_stats()
        self.client.quantize(mesh_path(PRISM), level=5)
        after = self.client.server_stats()
        self.assertEqual(after.workers, 2)
        self.assertGreaterEqual(after.accepted_total, before.accepted_total + 1)

    def test_a_refused_mesh_raises_with_the_servers_message(self):
        mesh = ispq.load_tmesh(mesh_path(PRISM))
        mesh.arcs[3].length = -1.0
        with self.assertRaises(ispq.IspqError) as refused:
            self.client.quantize(mesh, level=25)
        self.assertEqual(refused.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertIn("arc 3", refused.exception.message)
        with self.assertRaises(ispq.IspqError) as missing:
            self.client.get("jobs/does-not-exist")
        self.assertEqual(missing.exception.code, grpc.StatusCode.NOT_FOUND)

    def test_arguments_are_checked_before_anything_is_sent(self):
        with self.assertRaises(ValueError):
            self.client.quantize(mesh_path(PRISM), level=25, scaling=2.0)
        with self.assertRaises(ValueError):
            self.client.quantize(mesh_path(PRISM), level=25, method="simulated-annealing")
        with self.assertRaises(ValueError):
            ispq.Client("127.0.0.1:1", lb_policy="random")
        with self.assertRaises(ValueError):
            ispq.Client("127.0.0.1:1", cert_file="client.pem")

    def test_a_large_mesh_is_uploaded_in_chunks(self):
        # upload_above_bytes lowered so that a small real mesh takes the path a 1M-arc one takes.
        size = ispq.load_tmesh(mesh_path(NOTCH)).ByteSize()
        with ispq.Client(self.server.address, upload_above_bytes=size // 3) as client:
            stored_before = client.server_stats().stored_meshes
            result = client.quantize(mesh_path(NOTCH), level=50)
            self.assert_valid_and_local(NOTCH, result, 50)
            self.assertEqual(client.server_stats().stored_meshes, stored_before,
                             "quantize deletes the mesh it uploaded")
            mesh = client.upload_mesh(mesh_path(NOTCH), chunk_bytes=1000)
            self.assertEqual(mesh.mesh_stats, client.create_mesh(mesh_path(NOTCH)).mesh_stats)
            job = client.submit(mesh_path(NOTCH), level=5)
            self.assertTrue(job.stored_mesh.startswith("meshes/"), job)
            self.assert_valid_and_local(NOTCH, client.watch(job), 5)

    def test_a_large_binary_file_is_streamed_from_disk_unparsed(self):
        # A binary file above upload_above_bytes goes to the server as it is: never loaded here
        # (load_tmesh made to fail), one chunk in memory at a time; the server's refusal of a
        # file that is no T-mesh names the file.
        from ispq import client as client_module
        tmesh = ispq.load_tmesh(mesh_path(NOTCH))
        with tempfile.TemporaryDirectory() as directory:
            binary = os.path.join(directory, "notch.tmesh.pb")
            with open(binary, "wb") as f:
                f.write(tmesh.SerializeToString())
            broken = os.path.join(directory, "broken.tmesh.pb")
            with open(broken, "wb") as f:
                f.write(b"\xff" * 5000)
            loader = client_module.load_tmesh

            def must_not_parse(path):
                raise AssertionError(f"{path} was parsed on the client")

            client_module.load_tmesh = must_not_parse
            try:
                with ispq.Client(self.server.address,
                                 upload_above_bytes=tmesh.ByteSize() // 3) as client:
                    self.assert_valid_and_local(NOTCH, client.quantize(binary, level=25), 25)
                    job = client.submit(binary, level=10)
                    self.assertTrue(job.stored_mesh.startswith("meshes/"), job)
                    self.assert_valid_and_local(NOTCH, client.watch(job), 10)
                    mesh = client.upload_mesh(binary, chunk_bytes=700)
                    self.assertEqual(mesh.mesh_stats.arcs, len(tmesh.arcs))
                    with self.assertRaises(ispq.IspqError) as refused:
                        client.quantize(broken, level=25)
                    self.assertEqual(refused.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
                    self.assertIn(broken, refused.exception.message)
            finally:
                client_module.load_tmesh = loader

    def test_tls_to_an_address_list_checks_the_certificate_of_each_server(self):
        # Two TLS servers with one certificate for 127.0.0.1, named as an address list: the
        # certificate is checked against each address, not against the list as one name; a client
        # without the CA is refused.
        with tempfile.TemporaryDirectory() as directory:
            def openssl(*args):
                subprocess.run(["openssl", *args], cwd=directory, check=True,
                               capture_output=True, timeout=120)
            openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj",
                    "/CN=test CA", "-keyout", "ca.key", "-out", "ca.crt")
            openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=localhost", "-keyout",
                    "server.key", "-out", "server.csr")
            with open(os.path.join(directory, "server.ext"), "w") as f:
                f.write("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
            openssl("x509", "-req", "-in", "server.csr", "-CA", "ca.crt", "-CAkey", "ca.key",
                    "-CAcreateserial", "-days", "2", "-extfile", "server.ext", "-out", "server.crt")
            tls = [f"--tls_cert={directory}/server.crt", f"--tls_key={directory}/server.key"]
            with Server(*tls) as first, Server(*tls) as second:
                target = f"ipv4:{first.address},{second.address}"
                ca = os.path.join(directory, "ca.crt")
                with ispq.Client(target, ca_file=ca, lb_policy="round_robin") as client:
                    for _ in range(2):  # round robin: one job on each server
                        self.assert_valid_and_local(PRISM, client.quantize(mesh_path(PRISM),
                                                                           level=25), 25)
                with ispq.Client(target, tls=True) as untrusted:
                    with self.assertRaises(ispq.IspqError) as refused:
                        untrusted.quantize(mesh_path(PRISM), level=25, timeout=30)
                    self.assertEqual(refused.exception.code, grpc.StatusCode.UNAVAILABLE)

    def test_tmesh_files_in_both_formats(self):
        from_json = ispq.load_tmesh(mesh_path(NOTCH))
        self.assertGreater(len(from_json.arcs), 0)
        with tempfile.TemporaryDirectory() as directory:
            binary = os.path.join(directory, "notch.tmesh.pb")
            with open(binary, "wb") as f:
                f.write(from_json.SerializeToString())
            self.assertEqual(ispq.load_tmesh(binary), from_json)
            self.assert_valid_and_local(NOTCH, self.client.quantize(binary, level=17), 17)
            broken = os.path.join(directory, "broken.tmesh.json")
            with open(broken, "w") as f:
                f.write('{"arcs": [{"lenght": 1}]}')
            with self.assertRaisesRegex(ValueError, "broken.tmesh.json"):
                ispq.load_tmesh(broken)
            with self.assertRaisesRegex(ValueError, "tmesh.json or .tmesh.pb"):
                ispq.load_tmesh(os.path.join(directory, "notch.obj"))


class TokenTest(unittest.TestCase):
    def test_calls_carry_the_bearer_token(self):
        with Server("--auth_token=python-secret") as server:
            with ispq.Client(server.address) as anonymous:
                with self.assertRaises(ispq.IspqError) as refused:
                    anonymous.server_stats()
                self.assertEqual(refused.exception.code, grpc.StatusCode.UNAUTHENTICATED)
            with ispq.Client(server.address, token="python-secret") as client:
                result = client.quantize(mesh_path(PRISM), level=25)
                self.assertTrue(validate(PRISM, result, 25).get("valid"))


class BatchTest(unittest.TestCase):
    def test_a_batch_rides_out_a_server_restart_and_a_rerun_keeps_its_results(self):
        levels = [0, 10, 25, 100]
        directory = tempfile.mkdtemp(prefix="ispq-python-batch-")
        self.addCleanup(shutil.rmtree, directory, ignore_errors=True)
        inputs = os.path.join(DATA, "hex-me")
        expected = len(ispq.plan_batch([inputs], directory, levels=levels))
        server = Server("--workers=2")
        port = server.address.rsplit(":", 1)[1]
        outcome = {}
        # Half the meshes go up in chunks (UploadMesh), as a cluster's large parts would.
        with ispq.Client(server.address, upload_above_bytes=17_000) as client:
            batch = threading.Thread(target=lambda: outcome.update(entries=client.batch(
                [inputs], directory, levels=levels, concurrency=3)))
            batch.start()
            deadline = time.monotonic() + SAFETY_NET
            while (count_results(directory) < expected // 3 and batch.is_alive()
                   and time.monotonic() < deadline):
                time.sleep(0.005)
            self.assertTrue(batch.is_alive(), "the batch ended before the restart")
            server.process.kill()  # SIGKILL: the jobs it had are lost with it
            server.__exit__()
            server = Server("--workers=2", f"--listen=127.0.0.1:{port}")
            batch.join(SAFETY_NET)
            self.assertFalse(batch.is_alive())
            entries = outcome["entries"]
            self.assertEqual(len(entries), expected)
            failed = [(e.name, str(e.error)) for e in entries if not e.ok]
            self.assertEqual(failed, [])
            for entry in entries:
                level = entry.scaling["level"]
                with open(entry.result_path) as f:
                    saved = json.load(f)
                self.assertEqual([int(x) for x in saved["q"]], entry.result.q)
                mesh = os.path.relpath(entry.mesh_path, DATA)
                self.assertTrue(validate(mesh, entry.result, level).get("valid"), entry.name)
            # Equal to --local on a sample (each is a process start; the C++ batch test compares all).
            for entry in entries[::7]:
                self.assertEqual(entry.result.q, local_q(os.path.relpath(entry.mesh_path, DATA),
                                                         entry.scaling["level"]), entry.name)
        with ispq.Client(server.address) as client:
            accepted = client.server_stats().accepted_total
            again = client.batch([inputs], directory, levels=levels)
            self.assertTrue(all(e.ok and e.kept for e in again))
            self.assertEqual(client.server_stats().accepted_total, accepted)
            ids = [j.request_id for j in client.jobs()]
            self.assertEqual(len(ids), len(set(ids)), "a job was run twice by the new server")
        server.__exit__()
        with open(os.path.join(directory, "summary.tsv")) as f:
            self.assertEqual(len(f.read().splitlines()), expected + 1)

    def test_bad_inputs_are_named_before_anything_runs(self):
        with tempfile.TemporaryDirectory() as directory:
            with self.assertRaisesRegex(ValueError, "notch.obj"):
                ispq.plan_batch([os.path.join(directory, "notch.obj")], directory, levels=[5])
            with self.assertRaisesRegex(ValueError, "no T-mesh files"):
                ispq.plan_batch([directory], directory, levels=[5])


def count_results(directory):
    return sum(name.endswith(".result.json") for _, _, files in os.walk(directory)
               for name in files)


class PipInstallTest(unittest.TestCase):
    def test_pip_installs_the_package_with_its_generated_stubs(self):
        """`pip install client/python` (no network: Debian's grpcio and protobuf are present)."""
        if not SOURCE_DIR:
            raise RuntimeError("ISPQ_SOURCE_DIR is not set: run through ctest")
        with tempfile.TemporaryDirectory() as directory:
            sources = os.path.join(directory, "src")  # pip builds in place: keep the tree clean
            shutil.copytree(os.path.join(SOURCE_DIR, "client", "python"), sources)
            target = os.path.join(directory, "site")
            environment = dict(os.environ, ISPQ_PROTO_DIR=os.path.join(SOURCE_DIR, "proto"),
                               PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
            environment.pop("PYTHONPATH", None)
            subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
                            "--no-build-isolation", "--target", target, sources], check=True,
                           env=environment, capture_output=True, timeout=SAFETY_NET)
            check = ("import ispq, ispq.v1.service_pb2_grpc as s; "
                     "assert ispq.__file__.startswith(%r), ispq.__file__; "
                     "print(s.QuantizerStub.__name__)" % target)
            run = subprocess.run([sys.executable, "-c", check], env=dict(environment,
                                 PYTHONPATH=target), capture_output=True, text=True, timeout=60)
            self.assertEqual(run.returncode, 0, run.stderr)
            self.assertEqual(run.stdout.strip(), "QuantizerStub")


if __name__ == "__main__":
    # A hang shows where every thread waits, before ctest's timeout (600 s) kills the test mute.
    faulthandler.dump_traceback_later(500, exit=True)
    unittest.main()
