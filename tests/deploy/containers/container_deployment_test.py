#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The product deployed the way deploy/kubernetes deploys it, with real containers (podman).

Builds the image from deploy/Dockerfile (podman's layer cache makes a second run reuse it; the
base images come from make_base_image.sh, debootstrap from the machine's Debian mirror), starts
PostgreSQL in a container (postgres/, the stand-in for the image components/postgres names) on a
podman network and three ispq-server containers configured from the rendered Deployment of
overlays/in-cluster-postgres: its args, its env (Secrets as podman secrets), its Secret volumes as
read-only files (mode and group as the kubelet makes them), read-only root without tmpfs,
non-root user and fsGroup, no capabilities, no privilege escalation, its memory and CPU limits,
TLS on gRPC and HTTPS. Its probes (startup, readiness, liveness: path, port, scheme, timeout,
period, failure threshold) are polled against every replica throughout.

Then three batches of real T-meshes (bundled samples and disjoint copies of them, 6 meshes x 2
levels each) go through the host's `ispq batch` over TLS with the token, and during each one:
  1. a replica running a job is killed (podman kill, SIGKILL) and started again;
  2. every replica is replaced in turn: preStop (sleep 5), podman stop -t 30 (the termination
     grace period left), a new container, ready before the next;
  3. the database container is stopped (held down past the readiness failure threshold) and
     started again.
Checked: every batch exits 0; every job of the store ends SUCCEEDED with a result that
`ispq validate` accepts and whose q equals `ispq quantize --local`; one job per submitted job
(0 lost, 0 duplicated: `ispq jobs --json` against the batches' summaries); the killed job ran
again elsewhere; the probes answer what the manifests expect (started within the startup budget,
ready replicas 200 on /readyz, a killed replica answers nothing, a stopping one never 200 on
/readyz again, every replica 503 on /readyz while the database is down but 200 on /healthz,
liveness never failing long enough to restart a live replica); the image's HEALTHCHECK, run as the
image declares it, passes over TLS given the CA in its environment and fails without it. Last,
headless Chromium, trusting the deployment's certificate alone, opens the live view where
deploy/README.md says, https://localhost:8443/ through a port-forward to the Service's https port
(Chromium's host rules forward it to a replica's published port), uploads the notch with the token,
follows it to its end in the 3-D view (q equal to --local's) and reads /metrics, asking nothing of
any other host; the same port under another name is refused (421).

Everything made here (containers, network, volume, podman secrets, files) is removed at the end,
also when the test is killed (a guard process, die_with_parent); the images stay cached. Bounded
by a safety timeout (ISPQ_CONTAINER_TEST_TIMEOUT, default 1700 s, below CTest's). Durations go to
stdout and to test-artifacts/container-deployment.json.
"""
import http.client
import json
import os
import re
import secrets
import shutil
import signal
import socket
import ssl
import subprocess
import sys
import tempfile
import threading
import time

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "http"))
from child_processes import die_with_parent  # noqa: E402
from devtools_pipe import Browser, trust_certificate_flag  # noqa: E402
from tmesh_copies import disjoint_copies  # noqa: E402

CLI = os.environ.get("ISPQ_CLI", os.path.join(ROOT, "build", "release", "client", "ispq"))
DATA = os.path.join(ROOT, "tests", "data", "tmesh")
ARTIFACTS = os.environ.get("ISPQ_TEST_ARTIFACTS", tempfile.gettempdir())
SAFETY_SECONDS = float(os.environ.get("ISPQ_CONTAINER_TEST_TIMEOUT", "1700"))
CONTAINERS_CONF = os.path.join(HERE, "containers.conf")
IMAGE = "localhost/ispq-server:container-test"
BUILD_STAGE_IMAGE = "localhost/ispq-server-build:container-test"  # the next build's cache
POSTGRES_IMAGE = "localhost/ispq-test-postgres:15"
OVERLAY = os.path.join(ROOT, "deploy", "kubernetes", "overlays", "in-cluster-postgres")
LABEL = "io.ispq.test"  # =container-deployment on everything made here
OWNER = "io.ispq.test.owner"  # =the pid of the test that made it
# Service names the replicas reach PostgreSQL by, and the certificate names (deploy/README.md).
POSTGRES_HOST = "ispq-postgres.ispq.svc"
CERT_NAMES = ["ispq-server", "ispq-server.ispq.svc", "ispq-server.ispq.svc.cluster.local",
              "ispq-server-headless.ispq.svc.cluster.local", "localhost"]
LEVELS = [50, 100]
FEMUR = "metamesh-guided-hexalab/2017_-_Explicit_Cylindrical_Maps_for_General_Tubular_Shapes_femur_shell1.tmesh.json"
# Bundled samples, and disjoint copies of them (long jobs, so that faults hit running jobs).
MESHES = ["hex-me/s07c_notch.tmesh.json", "singularity-constrained-fields/prisma.tmesh.json",
          FEMUR, "metamesh-guided-hexalab/2019_-_Selective_Padding_for_Polycube‐Based_Hexahedral_Meshing_Wrench.tmesh.json"]
# About 7 s and 15 s at level 100 in a replica: long enough to outlast preStop's 5 s.
COPIES = [(FEMUR, 20, "femur_shell1_x20"), (FEMUR, 30, "femur_shell1_x30")]
LONG = "x30"  # in the display name of the longest job

START = time.monotonic()
DEADLINE = START + SAFETY_SECONDS
DURATIONS = {}


class SafetyTimeout(Exception):
    pass


def remaining(cap=None):
    left = DEADLINE - time.monotonic()
    if left <= 0:
        raise SafetyTimeout(f"safety timeout of {SAFETY_SECONDS:.0f} s reached")
    return left if cap is None else min(cap, left)


def log(message):
    print(f"[{time.monotonic() - START:7.1f} s] {message}", flush=True)


def podman_env():
    env = dict(os.environ)
    env["CONTAINERS_CONF"] = CONTAINERS_CONF
    return env


def podman(*args, timeout=120, check=True, input=None):
    """podman ARGS; its CompletedProcess (text). Fails the test on a non-zero exit if `check`."""
    run = subprocess.run(["podman", *args], capture_output=True, text=True, input=input,
                         timeout=remaining(timeout), env=podman_env(), preexec_fn=die_with_parent())
    if check and run.returncode != 0:
        raise AssertionError(f"podman {' '.join(args)}: exit {run.returncode}\n{run.stdout}{run.stderr}")
    return run


# ---- cleanup, also after the test process is killed ----

def cleanup(owner):
    """Removes every container, network, volume and podman secret that test process `owner`
    made; the images stay. Idempotent."""
    env = podman_env()

    def quiet(*args):
        return subprocess.run(["podman", *args], capture_output=True, text=True, timeout=120,
                              env=env)

    label = f"label={OWNER}={owner}"
    ids = quiet("ps", "-a", "-q", "--filter", label).stdout.split()
    if ids:
        quiet("rm", "-f", "-t", "0", *ids)
    for name in quiet("network", "ls", "-q", "--filter", label).stdout.split():
        quiet("network", "rm", "-f", name)
    for name in quiet("volume", "ls", "-q", "--filter", label).stdout.split():
        quiet("volume", "rm", "-f", name)
    for name in quiet("secret", "ls", "--format", "{{.Name}}").stdout.split():
        if name.startswith(f"ispq-ct{owner}-"):
            quiet("secret", "rm", name)


def guard(owner):
    """Runs in a child process: waits for the test process to die (SIGTERM by PR_SET_PDEATHSIG,
    or SIGTERM from the test itself), then removes what it made."""
    def finish(*_):
        cleanup(owner)
        os._exit(0)
    signal.signal(signal.SIGTERM, finish)
    if not os.path.exists(f"/proc/{owner}"):
        finish()
    while True:
        signal.pause()


def remove_leftovers():
    """What earlier runs killed before their guard could act left behind (their pid is gone)."""
    listed = podman("ps", "-a", "--filter", f"label={LABEL}=container-deployment", "--format",
                    "{{.Labels}}", check=False).stdout
    owners = set(re.findall(rf"{re.escape(OWNER)}:(\d+)", listed))
    for owner in owners:
        if not os.path.exists(f"/proc/{owner}"):
            log(f"removing what test process {owner} left behind")
            cleanup(owner)


# ---- images ----

def build_images():
    t = time.monotonic()
    run = subprocess.run(["bash", os.path.join(HERE, "make_base_image.sh")], capture_output=True,
                         text=True, timeout=remaining(900), env=podman_env(),
                         preexec_fn=die_with_parent())
    if run.returncode != 0:
        raise AssertionError(f"make_base_image.sh failed:\n{run.stdout}{run.stderr}")
    log(run.stdout.strip())
    DURATIONS["base_images_seconds"] = round(time.monotonic() - t, 1)
    for key, (dockerfile, ignore, context, tag) in {
        "ispq_image_build_seconds": (os.path.join(ROOT, "deploy", "Dockerfile"),
                                     os.path.join(ROOT, "deploy", "Dockerfile.dockerignore"), ROOT,
                                     IMAGE),
        "postgres_image_build_seconds": (os.path.join(HERE, "postgres", "Dockerfile"), None,
                                         os.path.join(HERE, "postgres"), POSTGRES_IMAGE),
    }.items():
        t = time.monotonic()
        # --format docker: the OCI format drops HEALTHCHECK; --pull=never: the base is local.
        args = ["build", "--pull=never", "--format", "docker", "--layers", "-f", dockerfile,
                "-t", tag]
        if ignore:
            args += ["--ignorefile", ignore]
        build_log = os.path.join(ARTIFACTS, f"podman-build-{tag.split('/')[-1].split(':')[0]}.log")
        with open(build_log, "w") as out:
            run = subprocess.run(["nice", "-n", "10", "podman", *args, context], stdout=out,
                                 stderr=subprocess.STDOUT, timeout=remaining(1500),
                                 env=podman_env(), preexec_fn=die_with_parent())
        if run.returncode != 0:
            with open(build_log) as f:
                raise AssertionError(f"podman build of {tag} failed:\n{f.read()[-4000:]}")
        DURATIONS[key] = round(time.monotonic() - t, 1)
        with open(build_log) as f:
            steps = f.read()
        DURATIONS[key.replace("_seconds", "_cached_steps")] = steps.count("Using cache")
        log(f"built {tag} in {DURATIONS[key]} s ({steps.count('Using cache')} cached steps)")
    healthcheck = podman("image", "inspect", IMAGE, "--format", "{{.Config.Healthcheck}}").stdout
    assert "ispq" in healthcheck, f"the image lost its HEALTHCHECK: {healthcheck!r}"
    prune_earlier_builds()


def prune_earlier_builds():
    """Each source change leaves the previous server image and build stage (about 1.2 GB)
    untagged. The build stage just used is tagged (every step cached) so that it stays as the
    next run's cache; then untagged images of either stage, by their title label, are removed."""
    podman("build", "--pull=never", "--format", "docker", "--layers", "--target", "build",
           "-f", os.path.join(ROOT, "deploy", "Dockerfile"), "--ignorefile",
           os.path.join(ROOT, "deploy", "Dockerfile.dockerignore"), "-t", BUILD_STAGE_IMAGE, ROOT,
           timeout=600)
    before = podman("images", "--filter", "dangling=true", "--format", "{{.ID}}").stdout.split()
    for title in ("ispq-server", "ispq-server-build"):
        podman("image", "prune", "--force", "--filter",
               f"label=org.opencontainers.image.title={title}", check=False)
    after = podman("images", "--filter", "dangling=true", "--format", "{{.ID}}").stdout.split()
    DURATIONS["earlier_images_pruned"] = len(before) - len(after)


# ---- the manifests ----

def rendered(kind, name):
    run = subprocess.run(["kubectl", "kustomize", OVERLAY], capture_output=True, text=True,
                         timeout=remaining(120))
    if run.returncode != 0:
        raise AssertionError(f"kubectl kustomize {OVERLAY}:\n{run.stderr}")
    for doc in yaml.safe_load_all(run.stdout):
        if doc and doc.get("kind") == kind and doc["metadata"]["name"] == name:
            return doc
    raise AssertionError(f"no {kind} {name} in {OVERLAY}")


def quantity_bytes(text):
    units = {"Ki": 1 << 10, "Mi": 1 << 20, "Gi": 1 << 30, "k": 10**3, "M": 10**6, "G": 10**9}
    for unit, factor in units.items():
        if str(text).endswith(unit):
            return int(float(str(text)[:-len(unit)]) * factor)
    return int(text)


def cpus(text):
    text = str(text)
    return float(text[:-1]) / 1000 if text.endswith("m") else float(text)


class PodSpec:
    """One container of a pod template, as podman arguments: what the kubelet would do with it."""

    HANDLED_CONTAINER = {"name", "image", "args", "env", "ports", "startupProbe", "readinessProbe",
                         "livenessProbe", "lifecycle", "resources", "securityContext",
                         "volumeMounts"}

    def __init__(self, pod_template, prefix, secret_data, secret_dir, volume_claims=()):
        spec = pod_template["spec"]
        (container,) = spec["containers"]
        unknown = set(container) - self.HANDLED_CONTAINER
        assert not unknown, f"the test does not know how to honour {sorted(unknown)}"
        self.container = container
        self.spec = spec
        self.prefix = prefix
        self.args = [str(a) for a in container.get("args", [])]
        self.ports = {p["name"]: p["containerPort"] for p in container.get("ports", [])}
        self.grace = spec.get("terminationGracePeriodSeconds", 30)
        pod_security = spec.get("securityContext", {})
        security = container.get("securityContext", {})
        self.user = f"{pod_security['runAsUser']}:{pod_security.get('runAsGroup', pod_security['runAsUser'])}"
        self.fs_group = pod_security.get("fsGroup")
        flags = ["--user", self.user, "--no-healthcheck"]  # the kubelet ignores HEALTHCHECK
        if self.fs_group is not None:
            flags += ["--group-add", str(self.fs_group)]
        if security.get("readOnlyRootFilesystem"):
            flags += ["--read-only", "--read-only-tmpfs=false"]  # no /tmp, as in a pod
        for capability in security.get("capabilities", {}).get("drop", []):
            flags += ["--cap-drop", capability]
        if security.get("allowPrivilegeEscalation") is False:
            flags += ["--security-opt", "no-new-privileges"]
        limits = container.get("resources", {}).get("limits", {})
        if "memory" in limits:
            memory = quantity_bytes(limits["memory"])
            flags += ["--memory", str(memory), "--memory-swap", str(memory)]
        if "cpu" in limits:
            flags += ["--cpus", str(cpus(limits["cpu"]))]
        for env in container.get("env", []):
            if "value" in env:
                flags += ["--env", f"{env['name']}={env['value']}"]
            else:
                ref = env["valueFrom"]["secretKeyRef"]
                secret = f"{prefix}-{ref['name']}-{ref['key']}".replace(".", "-")
                flags += ["--secret", f"{secret},type=env,target={env['name']}"]
                self.podman_secrets = getattr(self, "podman_secrets", {})
                self.podman_secrets[secret] = secret_data[ref["name"]][ref["key"]]
        volumes = {v["name"]: v for v in spec.get("volumes", [])}
        for mount in container.get("volumeMounts", []):
            name = mount["name"]
            if name in volumes and "secret" in volumes[name]:
                source = volumes[name]["secret"]
                directory = os.path.join(secret_dir, f"{prefix}-{source['secretName']}")
                os.makedirs(directory, exist_ok=True)
                os.chmod(directory, 0o755)
                for key, value in secret_data[source["secretName"]].items():
                    path = os.path.join(directory, key)
                    with open(path, "w") as f:
                        f.write(value)
                    os.chown(path, 0, self.fs_group if self.fs_group is not None else 0)
                    os.chmod(path, source.get("defaultMode", 0o644))
                flags += ["-v", f"{directory}:{mount['mountPath']}:ro"]
            elif name in volumes and "emptyDir" in volumes[name]:
                flags += ["--tmpfs", f"{mount['mountPath']}:U"]  # writable by the pod's user
            elif name in volume_claims:
                flags += ["-v", f"{volume_claims[name]}:{mount['mountPath']}"]
            else:
                raise AssertionError(f"the test does not know volume {name}")
        self.flags = flags

    def make_secrets(self):
        for name, value in getattr(self, "podman_secrets", {}).items():
            if podman("secret", "inspect", name, check=False).returncode != 0:
                podman("secret", "create", name, "-", input=value)

    def probe(self, kind):
        probe = self.container.get(kind)
        if not probe:
            return None
        get = probe["httpGet"]
        port = get["port"]
        return {"path": get["path"], "port": self.ports.get(port, port),
                "https": get.get("scheme", "HTTP") == "HTTPS",
                "period": probe.get("periodSeconds", 10), "timeout": probe.get("timeoutSeconds", 1),
                "failures": probe.get("failureThreshold", 3)}


# ---- certificates and Secrets ----

def openssl(*args, cwd):
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True,
                   timeout=remaining(120))


def make_secrets(directory):
    """The four Secrets of deploy/README.md, section 3, made as it says."""
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj", "/CN=ispq CA",
            "-keyout", "ca.key", "-out", "ca.crt", cwd=directory)
    openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=ispq-server.ispq.svc",
            "-keyout", "tls.key", "-out", "tls.csr", cwd=directory)
    with open(os.path.join(directory, "san.ext"), "w") as f:
        names = ",".join(f"DNS:{n}" for n in CERT_NAMES)
        f.write(f"subjectAltName={names},IP:127.0.0.1\n")
    openssl("x509", "-req", "-in", "tls.csr", "-CA", "ca.crt", "-CAkey", "ca.key",
            "-CAcreateserial", "-days", "2", "-extfile", "san.ext", "-out", "tls.crt",
            cwd=directory)

    def read(name):
        with open(os.path.join(directory, name)) as f:
            return f.read()
    token = secrets.token_hex(32)
    password = secrets.token_hex(24)
    return {
        "ispq-auth": {"token": token + "\n"},
        "ispq-tls": {"tls.crt": read("tls.crt"), "tls.key": read("tls.key"), "ca.crt": read("ca.crt")},
        "ispq-job-store": {"uri": f"postgresql://ispq:{password}@{POSTGRES_HOST}:5432/ispq"},
        "ispq-postgres": {"password": password},
    }, token


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# ---- probes ----

class Prober(threading.Thread):
    """Polls /healthz and /readyz of every replica (as the manifests' probes: HTTPS, their
    timeout) twice a second and keeps every answer: (start time, replica, path, answer), answer an
    HTTP status or "refused"/"timeout"/"error"."""

    def __init__(self, replicas, ca_file, paths):
        super().__init__(daemon=True)
        self.replicas = replicas
        self.context = ssl.create_default_context(cafile=ca_file)
        self.paths = paths  # path: timeout
        self.answers = []
        self.lock = threading.Lock()
        self.stopping = threading.Event()

    def ask(self, port, path, timeout):
        connection = http.client.HTTPSConnection("127.0.0.1", port, context=self.context,
                                                 timeout=timeout)
        try:
            connection.request("GET", path)
            return connection.getresponse().status
        except ConnectionRefusedError:
            return "refused"
        except (socket.timeout, TimeoutError):
            return "timeout"
        except (OSError, http.client.HTTPException) as e:
            return f"error:{type(e).__name__}"
        finally:
            connection.close()

    def run(self):
        while not self.stopping.is_set():
            for index, replica in enumerate(self.replicas):
                for path, timeout in self.paths.items():
                    t = time.monotonic()
                    answer = self.ask(replica.http_port, path, timeout)
                    with self.lock:
                        self.answers.append((t, index, path, answer))
            self.stopping.wait(0.5)

    def between(self, index, path, t0, t1):
        with self.lock:
            return [(t, a) for t, i, p, a in self.answers if i == index and p == path and t0 <= t <= t1]

    def longest_failure(self, index, path, t0, t1):
        """The longest time from a failed answer to the next 200 (or t1) within [t0, t1]."""
        longest, failing_since = 0.0, None
        for t, answer in self.between(index, path, t0, t1):
            if answer == 200:
                if failing_since is not None:
                    longest = max(longest, t - failing_since)
                failing_since = None
            elif failing_since is None:
                failing_since = t
        if failing_since is not None:
            longest = max(longest, t1 - failing_since)
        return longest


# ---- the deployment ----

class Replica:
    def __init__(self, index, name):
        self.index = index
        self.name = name
        self.grpc_port = free_port()
        self.http_port = free_port()
        self.generation = 0


class Deployment:
    def __init__(self, workdir):
        self.pid = os.getpid()
        self.prefix = f"ispq-ct{self.pid}"
        self.workdir = workdir
        self.labels = ["--label", f"{LABEL}=container-deployment", "--label", f"{OWNER}={self.pid}"]
        self.saved_logs = []  # logs of replaced containers

    def set_up(self):
        secret_data, self.token = make_secrets(self.workdir)
        self.ca_file = os.path.join(self.workdir, "ca.crt")
        secret_dir = os.path.join(self.workdir, "secrets")
        os.makedirs(secret_dir)
        deployment = rendered("Deployment", "ispq-server")
        statefulset = rendered("StatefulSet", "ispq-postgres")
        self.replica_count = deployment["spec"]["replicas"]
        self.server = PodSpec(deployment["spec"]["template"], self.prefix, secret_data, secret_dir)
        self.volume = f"{self.prefix}-pgdata"
        claims = {t["metadata"]["name"]: self.volume
                  for t in statefulset["spec"].get("volumeClaimTemplates", [])}
        self.postgres = PodSpec(statefulset["spec"]["template"], self.prefix, secret_data,
                                secret_dir, claims)
        self.server.make_secrets()
        self.postgres.make_secrets()
        self.network = f"{self.prefix}-net"
        podman("network", "create", *self.labels, self.network)
        subnet = podman("network", "inspect", self.network, "--format",
                        "{{range .Subnets}}{{.Subnet}}{{end}}").stdout.strip()
        base = subnet.split("/")[0].rsplit(".", 1)[0]
        self.postgres_ip = f"{base}.10"
        podman("volume", "create", *self.labels, self.volume)
        self.replicas = [Replica(i, f"{self.prefix}-r{i}") for i in range(self.replica_count)]
        self.probes = {kind: self.server.probe(kind)
                       for kind in ("startupProbe", "readinessProbe", "livenessProbe")}
        for kind, probe in self.probes.items():
            assert probe and probe["https"] and probe["port"] == self.server.ports["https"], (kind, probe)
        paths = {}
        for probe in self.probes.values():
            paths[probe["path"]] = probe["timeout"]
        self.prober = Prober(self.replicas, self.ca_file, paths)

    # -- PostgreSQL --
    def start_postgres(self):
        name = f"{self.prefix}-postgres"
        self.postgres_name = name
        # The pod's network namespace, held by a container of its own (a pod's "pause"
        # container): restarting PostgreSQL's container keeps its address, and while it is down
        # connections are refused at once, as in a pod whose container the kubelet restarts (a
        # container with a network of its own would take its address away, and connections to it
        # would hang until libpq's connect timeout).
        podman("run", "-d", "--name", f"{name}-pod", "--hostname", "ispq-postgres-0", *self.labels,
               "--network", self.network, "--ip", self.postgres_ip, "--user", "65534:65534",
               "--read-only", "--cap-drop", "ALL", "--no-healthcheck",
               "docker.io/library/debian:bookworm-slim", "sleep", "infinity")
        podman("run", "-d", "--name", name, *self.labels, "--network", f"container:{name}-pod",
               *self.postgres.flags, POSTGRES_IMAGE, *self.postgres.args)
        self.wait_postgres_ready()

    def wait_postgres_ready(self, timeout=120):
        """The StatefulSet's readiness probe (exec pg_isready ...), until it passes."""
        command = self.postgres.container["readinessProbe"]["exec"]["command"]
        deadline = time.monotonic() + remaining(timeout)
        while time.monotonic() < deadline:
            if podman("exec", self.postgres_name, *command, check=False).returncode == 0:
                return
            time.sleep(0.5)
        raise AssertionError(f"PostgreSQL not ready within {timeout} s:\n"
                             + podman("logs", self.postgres_name, check=False).stderr[-3000:])

    # -- the replicas --
    def run_replica(self, replica):
        replica.generation += 1
        podman("run", "-d", "--name", replica.name, "--hostname", replica.name, *self.labels,
               "--network", self.network, "--add-host", f"{POSTGRES_HOST}:{self.postgres_ip}",
               "-p", f"127.0.0.1:{replica.grpc_port}:{self.server.ports['grpc']}",
               "-p", f"127.0.0.1:{replica.http_port}:{self.server.ports['https']}",
               *self.server.flags, IMAGE, *self.server.args)

    def probe_once(self, replica, kind):
        probe = self.probes[kind]
        return self.prober.ask(replica.http_port, probe["path"], probe["timeout"])

    def wait_started_and_ready(self, replica):
        """The startup probe must pass within period x failures; then readiness within its own
        period x failures after that (a replica that starts must become ready)."""
        t0 = time.monotonic()
        startup = self.probes["startupProbe"]
        budget = startup["period"] * startup["failures"]
        while self.probe_once(replica, "startupProbe") != 200:
            if time.monotonic() - t0 > budget:
                raise AssertionError(f"{replica.name}: startup probe {startup['path']} failed for "
                                     f"{budget} s:\n{self.logs(replica)[-3000:]}")
            time.sleep(remaining(0.2))
        started = time.monotonic() - t0
        readiness = self.probes["readinessProbe"]
        budget = readiness["period"] * readiness["failures"] * 2
        t1 = time.monotonic()
        while (answer := self.probe_once(replica, "readinessProbe")) != 200:
            if time.monotonic() - t1 > budget:
                raise AssertionError(f"{replica.name}: {readiness['path']} answered {answer} for "
                                     f"{budget} s after starting:\n{self.logs(replica)[-3000:]}")
            time.sleep(remaining(0.2))
        return started, time.monotonic() - t0

    def logs(self, replica):
        run = podman("logs", replica.name, check=False)
        return run.stdout + run.stderr

    def all_logs(self):
        return "".join(self.saved_logs) + "".join(self.logs(r) for r in self.replicas)

    def running_jobs(self, replica):
        """(job, mesh, scaling) of the jobs `replica` has started and not ended or handed back,
        from its log."""
        text = self.logs(replica)
        text = text[text.rfind("event=server_start"):]  # this run of the container
        started = re.findall(
            r"event=job_start job=(\S+) mesh=\"([^\"]*)\" arcs=\S+ blocks=\S+ scaling=(\S+)", text)
        ended = set(re.findall(r"event=job_(?:end|released|lease_lost) job=(\S+)", text))
        return [(job, mesh, float(scaling)) for job, mesh, scaling in started if job not in ended]

    def client(self, *args, timeout=120):
        servers = ",".join(f"127.0.0.1:{r.grpc_port}" for r in self.replicas)
        env = dict(os.environ, ISPQ_AUTH_TOKEN=self.token)
        return subprocess.run([CLI, *args, "--server", servers, "--lb_policy", "round_robin",
                               "--tls-ca", self.ca_file], capture_output=True, text=True,
                              env=env, timeout=remaining(timeout), preexec_fn=die_with_parent())

    def start_batch(self, inputs, out_dir, log_path):
        servers = ",".join(f"127.0.0.1:{r.grpc_port}" for r in self.replicas)
        env = dict(os.environ, ISPQ_AUTH_TOKEN=self.token)
        out = open(log_path, "w")
        process = subprocess.Popen(
            [CLI, "batch", inputs, "--levels", ",".join(map(str, LEVELS)), "--out-dir", out_dir,
             "--server", servers, "--lb_policy", "round_robin", "--tls-ca", self.ca_file,
             "--concurrency", "4", "--patience", "600"],
            stdout=out, stderr=subprocess.STDOUT, env=env, preexec_fn=die_with_parent())
        process.out = out
        return process


# ---- the test ----

def prepare_meshes(directory):
    os.makedirs(directory)
    for relative in MESHES:
        shutil.copy(os.path.join(DATA, relative), os.path.join(directory, os.path.basename(relative)))
    for relative, copies, name in COPIES:
        with open(os.path.join(DATA, relative)) as f:
            mesh = disjoint_copies(json.load(f), copies)
        with open(os.path.join(directory, f"{name}.tmesh.json"), "w") as f:
            json.dump(mesh, f)
    return sorted(os.path.join(directory, f) for f in os.listdir(directory))


def reference_results(meshes, directory):
    """q of `ispq quantize --local` for every mesh and level."""
    os.makedirs(directory)
    reference = {}
    for mesh in meshes:
        for level in LEVELS:
            out = os.path.join(directory, f"{os.path.basename(mesh)}.L{level}.json")
            run = subprocess.run([CLI, "quantize", mesh, "--local", "--level", str(level), "--out",
                                  out], capture_output=True, text=True, timeout=remaining(300),
                                 preexec_fn=die_with_parent())
            assert run.returncode == 0, f"--local {mesh} L{level}: {run.stderr}"
            with open(out) as f:
                reference[(os.path.realpath(mesh), f"L{level}")] = json.load(f)["q"]
    return reference


def wait_batch(process, timeout=900):
    try:
        code = process.wait(timeout=remaining(timeout))
    except subprocess.TimeoutExpired:
        process.kill()
        raise AssertionError(f"the batch did not end within {timeout} s")
    process.out.close()
    return code


def wait_for_running_job(deployment, batch, prefer=LONG, timeout=120, only_preferred=False,
                         scaling=None):
    """(replica, job, mesh) of a job some replica runs now, preferring a long one: mesh `prefer`
    (at scaling s = `scaling`, if given; after 20 s any job will do, unless `only_preferred`)."""
    deadline = time.monotonic() + remaining(timeout)
    seen = None
    while time.monotonic() < deadline:
        if batch.poll() is not None:
            with open(batch.args[batch.args.index("--out-dir") + 1] + ".log") as f:
                raise AssertionError(f"the batch ended (exit {batch.returncode}) before a replica "
                                     f"was seen running a job:\n{f.read()[-3000:]}")
        for replica in deployment.replicas:
            for job, mesh, s in deployment.running_jobs(replica):
                if prefer in mesh and (scaling is None or abs(s - scaling) <= 1e-9 * scaling):
                    return replica, job, mesh
                seen = seen or (replica, job, mesh)
        if seen and not only_preferred and time.monotonic() > deadline - timeout + 20:
            return seen
        time.sleep(0.2)
    with open(batch.args[batch.args.index("--out-dir") + 1] + ".log") as f:
        raise AssertionError(f"no replica was seen running a job within {timeout} s; the "
                             f"batch:\n{f.read()[-3000:]}")


def check_batch(name, out_dir, batch_log, code, reference, failures):
    with open(batch_log) as f:
        text = f.read()
    if code != 0:
        failures.append(f"{name}: ispq batch exited {code}:\n{text[-3000:]}")
    rows = []
    with open(os.path.join(out_dir, "summary.tsv")) as f:
        header = f.readline().rstrip("\n").split("\t")
        for line in f:
            rows.append(dict(zip(header, line.rstrip("\n").split("\t"))))
    if len(rows) != len(reference):
        failures.append(f"{name}: {len(rows)} summary rows, expected {len(reference)}")
    for row in rows:
        key = (os.path.realpath(row["mesh"]), row["scaling"])
        if row["state"] != "SUCCEEDED":
            failures.append(f"{name}: {row}")
            continue
        result_path = row["result_or_error"]
        with open(result_path) as f:
            result = json.load(f)
        if result.get("q") != reference.get(key):
            failures.append(f"{name}: {row['mesh']} {row['scaling']}: q differs from --local")
        validate = subprocess.run([CLI, "validate", row["mesh"], "--result", result_path,
                                   "--level", row["scaling"][1:]], capture_output=True, text=True,
                                  timeout=remaining(120), preexec_fn=die_with_parent())
        if validate.returncode != 0:
            failures.append(f"{name}: ispq validate rejects {result_path}: {validate.stdout}"
                            f"{validate.stderr}")
    return rows


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--guard":
        guard(int(sys.argv[2]))
        return 0
    assert os.path.exists(CLI), f"no ispq client at {CLI}: build it (or run through ctest)"
    os.makedirs(ARTIFACTS, exist_ok=True)

    def on_alarm(*_):
        raise SafetyTimeout(f"safety timeout of {SAFETY_SECONDS:.0f} s reached")
    signal.signal(signal.SIGALRM, on_alarm)
    signal.alarm(int(SAFETY_SECONDS) + 5)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))

    remove_leftovers()
    # The guard removes what this process makes, however it ends (even by SIGKILL).
    guard_process = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--guard",
                                      str(os.getpid())], preexec_fn=die_with_parent(signal.SIGTERM),
                                     start_new_session=True)
    workdir = tempfile.mkdtemp(prefix="ispq-containers-")
    failures = []
    deployment = None
    try:
        t = time.monotonic()
        build_images()
        DURATIONS["images_total_seconds"] = round(time.monotonic() - t, 1)

        meshes = prepare_meshes(os.path.join(workdir, "meshes"))
        t = time.monotonic()
        reference = reference_results(meshes, os.path.join(workdir, "reference"))
        DURATIONS["local_reference_seconds"] = round(time.monotonic() - t, 1)

        deployment = Deployment(workdir)
        deployment.set_up()
        # The scaling s of the longest job (the largest copy at level 100: its s is the smallest
        # but its solve the longest, 10-15 s against 1-2 s at level 50), as --local resolved it:
        # the server logs each job's s.
        with open(os.path.join(workdir, "reference",
                               f"{COPIES[-1][2]}.tmesh.json.L{max(LEVELS)}.json")) as f:
            deployment.longest_scaling = float(json.load(f)["scaling"])
        t = time.monotonic()
        deployment.start_postgres()
        DURATIONS["postgres_ready_seconds"] = round(time.monotonic() - t, 1)
        t = time.monotonic()
        for replica in deployment.replicas:
            deployment.run_replica(replica)
        for replica in deployment.replicas:
            started, ready = deployment.wait_started_and_ready(replica)
            log(f"{replica.name}: started after {started:.1f} s, ready after {ready:.1f} s")
        DURATIONS["replicas_ready_seconds"] = round(time.monotonic() - t, 1)
        deployment.prober.start()
        checks_of_the_pod(deployment, failures)

        phases = [("kill", phase_kill), ("rolling", phase_rolling), ("database", phase_database)]
        all_rows = []
        for name, phase in phases:
            t = time.monotonic()
            out_dir = os.path.join(workdir, f"out-{name}")
            batch_log = out_dir + ".log"
            batch = deployment.start_batch(os.path.join(workdir, "meshes"), out_dir, batch_log)
            phase(deployment, batch, failures)
            code = wait_batch(batch)
            DURATIONS[f"phase_{name}_seconds"] = round(time.monotonic() - t, 1)
            log(f"phase {name}: batch exited {code} after {DURATIONS[f'phase_{name}_seconds']} s")
            shutil.copy(batch_log, os.path.join(ARTIFACTS, f"container-batch-{name}.log"))
            all_rows += check_batch(name, out_dir, batch_log, code, reference, failures)

        check_jobs(deployment, all_rows, failures)
        t = time.monotonic()
        phase_browser(deployment, meshes, reference, failures)
        DURATIONS["phase_browser_seconds"] = round(time.monotonic() - t, 1)
    finally:
        if deployment is not None:
            if deployment.prober.is_alive():
                deployment.prober.stopping.set()
                deployment.prober.join(timeout=30)
            with open(os.path.join(ARTIFACTS, "container-replica-logs.txt"), "w") as f:
                try:
                    f.write(deployment.all_logs())
                except Exception as e:  # noqa: BLE001 - the logs are a courtesy
                    f.write(f"could not read the logs: {e}")
            with open(os.path.join(ARTIFACTS, "container-probes.tsv"), "w") as f:
                for t, i, p, a in deployment.prober.answers:
                    f.write(f"{t - START:.2f}\t{i}\t{p}\t{a}\n")
        t = time.monotonic()
        signal.alarm(0)
        cleanup(os.getpid())
        DURATIONS["cleanup_seconds"] = round(time.monotonic() - t, 1)
        guard_process.kill()
        guard_process.wait()
        shutil.rmtree(workdir, ignore_errors=True)
        DURATIONS["total_seconds"] = round(time.monotonic() - START, 1)
        with open(os.path.join(ARTIFACTS, "container-deployment.json"), "w") as f:
            json.dump(DURATIONS, f, indent=2)
        print(json.dumps(DURATIONS, indent=2))
    if failures:
        print("FAILED:\n" + "\n".join(failures), file=sys.stderr)
        return 1
    print("container deployment: OK")
    return 0


def phase_browser(deployment, meshes, reference, failures):
    """Headless Chromium on the live view over HTTPS, where deploy/README.md (section 7) sends an
    operator, trusting the deployment's certificate alone: with the token, it uploads the notch
    through the page's form, follows the job to its end with the 3-D view drawn, and reads
    /metrics. The job's q must be --local's."""
    replica = deployment.replicas[0]
    # deploy/README.md, section 7: `kubectl port-forward` to the Service's https port, the page at
    # https://localhost:8443/, a Host the base's --http_allowed_hosts lists. Chromium's host
    # rules stand in for the port-forward: the URL (and Host) stay, the connection goes to the
    # replica's published port.
    allowed = next(a.split("=", 1)[1] for a in deployment.server.args
                   if a.startswith("--http_allowed_hosts="))
    forwarded = "localhost:8443"
    if forwarded not in allowed.split(","):
        failures.append(f"browser: {forwarded} (deploy/README.md) is not in {allowed}")
        return
    url = f"https://{forwarded}/"
    notch = next(m for m in meshes if m.endswith("s07c_notch.tmesh.json"))
    expected = reference[(os.path.realpath(notch), "L100")]
    trust = trust_certificate_flag(os.path.join(deployment.workdir, "tls.crt"))
    port_forward = f"--host-rules=MAP {forwarded} 127.0.0.1:{replica.http_port}"
    with Browser(extra_args=[trust]) as browser:
        # Any other name of the same port is refused (DNS rebinding): 421 for the page.
        other = f"https://localhost:{replica.http_port}/"
        browser.call("Page.navigate", {"url": other}, session=True)
        refused = browser.wait_for("document.readyState === 'complete' && "
                                   "document.body.innerText", timeout=remaining(60))
        if "is not a name of" not in refused:
            failures.append(f"browser: {other} was not refused: {refused[:200]!r}")
    with Browser(extra_args=[trust, port_forward]) as browser:
        browser.call("Network.enable", session=True)
        navigated = browser.call("Page.navigate", {"url": url}, session=True)
        if navigated.get("errorText"):
            failures.append(f"browser: {url}: {navigated['errorText']}")
            return
        browser.wait_for("document.readyState === 'complete' && typeof MeshView !== 'undefined' "
                         "&& window.THREE !== undefined", timeout=remaining(60))
        browser.evaluate(f"document.getElementById('token').value = {json.dumps(deployment.token)}")
        browser.set_file_input("#mesh-file", notch)
        browser.evaluate("document.getElementById('level').value = '100';"
                         "document.getElementById('upload-form').requestSubmit()")
        try:
            browser.wait_for("window.ispqView && ispqView.final && "
                             "!document.getElementById('result').hidden", timeout=remaining(180))
        except TimeoutError:
            failures.append("browser: the job never ended in the page: " + browser.evaluate(
                "document.getElementById('job-error').textContent + ' / ' + "
                "document.getElementById('form-message').textContent"))
            return
        state = json.loads(browser.evaluate(
            "JSON.stringify({q: ispqView.q, segments: ispqView.segments, arcs: ispqView.arcs, "
            "valid: document.getElementById('result-valid').textContent, "
            "protocol: location.protocol})"))
        if state["q"] != expected:
            failures.append("browser: the page's final q is not --local's")
        if state["valid"] != "yes" or state["protocol"] != "https:":
            failures.append(f"browser: valid {state['valid']!r} over {state['protocol']}")
        if state["segments"] != state["arcs"] or state["arcs"] != 75:
            failures.append(f"browser: {state['segments']} segments drawn of {state['arcs']} arcs")
        metrics = browser.evaluate("fetch('/metrics').then(r => r.text())", await_promise=True)
        if "ispq_ready 1" not in metrics:
            failures.append(f"browser: /metrics over HTTPS: {metrics[:300]!r}")
        elsewhere = [e["params"]["request"]["url"] for e in browser.events
                     if e.get("method") == "Network.requestWillBeSent"
                     and not e["params"]["request"]["url"].startswith(url)
                     and not e["params"]["request"]["url"].startswith(("blob:", "data:"))]
        if elsewhere:
            failures.append(f"browser: requests that left the server: {elsewhere[:5]}")
        browser.evaluate("document.getElementById('mesh-figure').scrollIntoView()")
        browser.screenshot(os.path.join(ARTIFACTS, "container-web-view.png"))
        log(f"browser: followed the notch over HTTPS on {replica.name}, q equal to --local")


def checks_of_the_pod(deployment, failures):
    """What the pod's settings must make true inside it, the exec probe of deploy/README.md and
    the image's HEALTHCHECK."""
    replica = deployment.replicas[0]
    run = podman("exec", replica.name, "sh", "-c", "id -u; id -G; touch /tmp/x /x 2>&1; true")
    lines = run.stdout.split("\n")
    if lines[0] != "10001":
        failures.append(f"the server runs as uid {lines[0]!r}")
    if "Read-only file system" not in run.stdout:
        failures.append(f"the root file system is writable: {run.stdout}")
    health = podman("exec", replica.name, "ispq", "health", "--server=localhost:50051",
                    "--tls_ca=/etc/ispq/tls/ca.crt", "--health_service=readiness", check=False)
    if health.returncode != 0:
        failures.append(f"exec health probe: {health.returncode} {health.stdout}{health.stderr}")
    # The image's own HEALTHCHECK (podman, Docker), run as the image declares it: with TLS on it
    # passes once given the CA in its environment (deploy/README.md, section 6), and without it
    # it must fail (it would not be checking the server's certificate otherwise).
    check = json.loads(podman("image", "inspect", IMAGE, "--format", "{{json .HealthCheck}}").stdout)
    kind, *command = check["Test"]
    if kind != "CMD":
        failures.append(f"HEALTHCHECK is {check['Test']}, not an exec form")
    else:
        with_ca = podman("exec", "--env", "FLAGS_tls_ca=/etc/ispq/tls/ca.crt", replica.name,
                         *command, check=False)
        if with_ca.returncode != 0:
            failures.append(f"HEALTHCHECK with FLAGS_tls_ca: {with_ca.returncode} "
                            f"{with_ca.stdout}{with_ca.stderr}")
        without = podman("exec", replica.name, *command, check=False)
        if without.returncode == 0:
            failures.append("HEALTHCHECK passed over plaintext against a TLS-only server")
    limit = podman("inspect", replica.name, "--format", "{{.HostConfig.Memory}}").stdout.strip()
    expected = quantity_bytes(deployment.server.container["resources"]["limits"]["memory"])
    if limit != str(expected):
        failures.append(f"memory limit {limit}, expected {expected}")
    # The server sizes its memory budget from the cgroup's limit: the limit is in force.
    budget = re.search(r"event=server_start .*max_memory_bytes=(\d+)", deployment.logs(replica))
    if not budget or int(budget.group(1)) > expected:
        failures.append(f"the server's memory budget ignores the limit {expected}: "
                        f"{budget and budget.group(0)}")


def expect_probe_held(deployment, kind, indices, t0, t1, failures, what):
    """Probe `kind` never fails long enough (period x failures) for the kubelet to act on it."""
    probe = deployment.probes[kind]
    for i in indices:
        longest = deployment.prober.longest_failure(i, probe["path"], t0, t1)
        if longest >= probe["period"] * probe["failures"]:
            failures.append(f"{what}: replica {i} failed {probe['path']} for {longest:.1f} s")


def expect_live(deployment, indices, t0, t1, failures, what):
    """Liveness never fails long enough for the kubelet to restart them."""
    expect_probe_held(deployment, "livenessProbe", indices, t0, t1, failures, what)


def expect_ready(deployment, indices, t0, t1, failures, what):
    """Readiness never fails long enough to take them out of the Service."""
    expect_probe_held(deployment, "readinessProbe", indices, t0, t1, failures, what)


def phase_kill(deployment, batch, failures):
    replica, job, mesh = wait_for_running_job(deployment, batch)
    t0 = time.monotonic()
    podman("kill", replica.name)  # SIGKILL: the pod's node or process dies
    log(f"killed {replica.name} while it ran {job} ({mesh})")
    deployment.killed_job = job
    time.sleep(remaining(3))
    others = [r.index for r in deployment.replicas if r is not replica]
    for kind in ("livenessProbe", "readinessProbe"):
        answer = deployment.probe_once(replica, kind)
        if answer not in ("refused", "timeout") and not str(answer).startswith("error"):
            failures.append(f"kill: the killed replica answered {kind}: {answer}")
    podman("start", replica.name)  # the kubelet restarts the container
    started, ready = deployment.wait_started_and_ready(replica)
    t1 = time.monotonic()
    log(f"{replica.name} restarted: started after {started:.1f} s, ready after {ready:.1f} s")
    DURATIONS["kill_restart_ready_seconds"] = round(ready, 1)
    dead = [a for _, a in deployment.prober.between(replica.index, "/healthz", t0 + 1, t0 + 3)]
    if 200 in dead:
        failures.append(f"kill: the killed replica answered /healthz 200: {dead}")
    expect_live(deployment, others, t0, t1, failures, "kill")
    expect_ready(deployment, others, t0, t1, failures, "kill")


def phase_rolling(deployment, batch, failures):
    # The longest job (the largest copy at level 100, 10-15 s), seen within a second of its
    # start: it is still running when its replica's preStop ends.
    first, _, _ = wait_for_running_job(deployment, batch, timeout=120, only_preferred=True,
                                       scaling=deployment.longest_scaling)
    readiness = deployment.probes["readinessProbe"]
    pending = [first] + [r for r in deployment.replicas if r is not first]
    caught = 0  # replacements that caught a job running at SIGTERM
    while pending:
        # The next to go: one that runs a job, if any does (a rollout does not wait for idle
        # pods; this one makes sure the shutdown's hand-back is exercised).
        replica = next((r for r in pending if deployment.running_jobs(r)), pending[0])
        pending.remove(replica)
        t0 = time.monotonic()
        # preStop, then SIGTERM with the rest of terminationGracePeriodSeconds.
        pre_stop = deployment.server.container.get("lifecycle", {}).get("preStop", {})
        pre_stop_seconds = 0
        if pre_stop:
            t = time.monotonic()
            podman("exec", replica.name, *pre_stop["exec"]["command"], timeout=60)
            pre_stop_seconds = time.monotonic() - t
        running = deployment.running_jobs(replica)
        caught += bool(running)
        t_term = time.monotonic()
        grace = max(1, int(deployment.server.grace - pre_stop_seconds))
        podman("stop", "-t", str(grace), replica.name, timeout=grace + 30)
        stopped = time.monotonic() - t_term
        code = podman("inspect", replica.name, "--format", "{{.State.ExitCode}}").stdout.strip()
        deployment.saved_logs.append(deployment.logs(replica))
        after_term = deployment.prober.between(replica.index, readiness["path"], t_term + 1.0,
                                               time.monotonic())
        if any(a == 200 for _, a in after_term):
            failures.append(f"rolling: {replica.name} answered {readiness['path']} 200 after SIGTERM")
        seen = sorted({str(a) for _, a in after_term})
        if code != "0":
            failures.append(f"rolling: {replica.name} exited {code} on SIGTERM (not gracefully)")
        podman("rm", replica.name)
        deployment.run_replica(replica)
        started, ready = deployment.wait_started_and_ready(replica)
        t1 = time.monotonic()
        others = [r.index for r in deployment.replicas if r is not replica]
        expect_live(deployment, others, t0, t1, failures, f"rolling {replica.name}")
        expect_ready(deployment, others, t0, t1, failures, f"rolling {replica.name}")
        log(f"replaced {replica.name} ({len(running)} jobs running at SIGTERM): stopped "
            f"{stopped:.1f} s after SIGTERM (exit {code}; {readiness['path']} meanwhile: {seen}), "
            f"new one ready after {ready:.1f} s")
        DURATIONS[f"rolling_{replica.index}_stop_seconds"] = round(stopped, 1)
        DURATIONS[f"rolling_{replica.index}_readyz_while_stopping"] = seen
    # The shutdown's hand-back must be exercised: the first replacement stops the longest job.
    DURATIONS["rolling_replacements_with_running_jobs"] = caught
    if not caught:
        failures.append("rolling: no replacement caught a running job")


def phase_database(deployment, batch, failures):
    wait_for_running_job(deployment, batch, timeout=120)
    readiness = deployment.probes["readinessProbe"]
    liveness = deployment.probes["livenessProbe"]
    t0 = time.monotonic()
    podman("stop", "-t", "60", deployment.postgres_name, timeout=90)
    t_down = time.monotonic()
    log(f"PostgreSQL stopped in {t_down - t0:.1f} s")
    # Down past the readiness probe's failure threshold.
    time.sleep(remaining(readiness["period"] * readiness["failures"] + 2))
    t_up = time.monotonic()
    podman("start", deployment.postgres_name)
    deployment.wait_postgres_ready()
    for replica in deployment.replicas:
        answers = [a for _, a in deployment.prober.between(replica.index, readiness["path"],
                                                            t_down + 3, t_up)]
        if 503 not in answers or 200 in answers[-3:]:
            failures.append(f"database: {replica.name} answered {readiness['path']} {answers} "
                            f"while the database was down")
    # Ready again soon after the database is: the server checks it every second, its pool
    # reconnects on demand. Bounded by two readiness periods of the kubelet's.
    t = time.monotonic()
    bound = 2 * readiness["period"] * readiness["failures"]
    for replica in deployment.replicas:
        deadline = t + remaining(bound)
        while deployment.probe_once(replica, "readinessProbe") != 200:
            if time.monotonic() > deadline:
                failures.append(f"database: {replica.name} not ready {bound} s after the database")
                break
            time.sleep(0.2)
    DURATIONS["database_back_to_ready_seconds"] = round(time.monotonic() - t, 1)
    expect_live(deployment, range(len(deployment.replicas)), t0, time.monotonic(), failures,
                "database")
    log(f"PostgreSQL back; replicas ready {DURATIONS['database_back_to_ready_seconds']} s later")
    del liveness


def check_jobs(deployment, rows, failures):
    run = deployment.client("jobs", "--json", "--limit", "0")
    if run.returncode != 0:
        failures.append(f"ispq jobs: {run.returncode} {run.stderr}")
        return
    jobs = json.loads(run.stdout).get("jobs", [])
    names = [j["name"] for j in jobs]
    request_ids = [j.get("requestId") for j in jobs]
    submitted = {row["job"] for row in rows}
    DURATIONS["jobs_in_store"] = len(jobs)
    if len(set(names)) != len(names) or len(set(request_ids)) != len(request_ids):
        failures.append(f"duplicated jobs: {len(names)} jobs, {len(set(request_ids))} request ids")
    if set(names) != submitted:
        failures.append(f"the store has {len(jobs)} jobs, the batches {len(submitted)}: "
                        f"extra {sorted(set(names) - submitted)}, lost {sorted(submitted - set(names))}")
    not_done = [j["name"] for j in jobs if j["state"] != "SUCCEEDED"]
    if not_done:
        failures.append(f"jobs not SUCCEEDED: {not_done}")
    logs = deployment.all_logs()
    ends = {}
    for job in re.findall(r"event=job_end job=(\S+) state=SUCCEEDED", logs):
        ends[job] = ends.get(job, 0) + 1
    claims = {}
    for job, attempt in re.findall(r"event=job_claimed job=(\S+) attempt=(\d+)", logs):
        claims[job] = max(claims.get(job, 0), int(attempt))
    DURATIONS["jobs_run_again"] = sum(1 for a in claims.values() if a > 1)
    DURATIONS["successful_job_ends_logged"] = sum(ends.values())
    killed = getattr(deployment, "killed_job", None)
    if killed and claims.get(killed, 0) < 2:
        failures.append(f"the killed replica's job {killed} was not run again "
                        f"(attempts {claims.get(killed)})")
    missing = [n for n in names if n not in ends]
    if missing:
        failures.append(f"jobs without a successful end in the replicas' logs: {missing}")
    log(f"{len(jobs)} jobs in the store, {len(submitted)} submitted, "
        f"{DURATIONS['jobs_run_again']} run again after a fault")


if __name__ == "__main__":
    sys.exit(main())
