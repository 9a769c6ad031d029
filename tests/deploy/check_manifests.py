#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Offline checks of the Kubernetes manifests in deploy/kubernetes.

Renders every overlay with `kubectl kustomize` (the kubectl the machines carry; without it the
check fails, it never skips), lints the sources with yamllint, and checks what the replicas
need: several replicas spread over nodes and zones, a headless and a normal Service, a
PodDisruptionBudget, an HPA on CPU and on the queue length, probes that work with TLS on and
sane thresholds, no service-account token, the job store's URI from a Secret, dual-stack listen,
a pinned image, and a termination grace period that covers the server's shutdown. Then it checks
that a deliberately broken copy of each rule is caught, so that the checks themselves work.
"""
import copy
import os
import re
import subprocess
import sys

import yaml

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
KUBERNETES = os.path.join(ROOT, "deploy", "kubernetes")
OVERLAYS = ["in-cluster-postgres", "production"]


def render(overlay):
    result = subprocess.run(["kubectl", "kustomize", os.path.join(KUBERNETES, "overlays", overlay)],
                            capture_output=True, text=True, timeout=120)
    if result.returncode != 0:
        raise SystemExit(f"kubectl kustomize {overlay} failed:\n{result.stderr}")
    return [doc for doc in yaml.safe_load_all(result.stdout) if doc]


def flag_value(args, name):
    for arg in args:
        if arg.startswith(f"--{name}="):
            return arg.split("=", 1)[1]
    return None


def problems(docs, pinned_by_digest=False):
    """The list of rules `docs` break (empty when all hold)."""
    found = []
    by_kind = {}
    for doc in docs:
        by_kind.setdefault(doc["kind"], []).append(doc)
    deployments = [d for d in by_kind.get("Deployment", []) if d["metadata"]["name"] == "ispq-server"]
    if len(deployments) != 1:
        return ["exactly one Deployment ispq-server"]
    deployment = deployments[0]
    spec = deployment["spec"]
    pod = spec["template"]["spec"]
    if spec.get("replicas", 1) < 2:
        found.append("Deployment: at least 2 replicas")
    if pod.get("automountServiceAccountToken") is not False:
        found.append("Deployment: automountServiceAccountToken must be false")
    keys = {c.get("topologyKey") for c in pod.get("topologySpreadConstraints", [])}
    if not {"kubernetes.io/hostname", "topology.kubernetes.io/zone"} <= keys:
        found.append("Deployment: topology spread over hostname and zone")
    if not pod.get("securityContext", {}).get("runAsNonRoot"):
        found.append("Deployment: runAsNonRoot")
    container = pod["containers"][0]
    args = container.get("args", [])
    listen = flag_value(args, "listen") or ""
    if not listen.startswith("[::]"):
        found.append("ispq-server: --listen=[::]:PORT (dual stack)")
    image = container["image"]
    if pinned_by_digest and not re.search(r"@sha256:[0-9a-f]{64}$", image):
        found.append(f"image {image} must be pinned by digest")
    if not re.search(r"(:[\w.-]+|@sha256:[0-9a-f]{64})$", image) or image.endswith(":latest"):
        found.append(f"image {image} needs an explicit tag or a digest")
    env = {e["name"]: e for e in container.get("env", [])}
    if "secretKeyRef" not in env.get("ISPQ_JOB_STORE", {}).get("valueFrom", {}):
        found.append("ispq-server: ISPQ_JOB_STORE from a Secret")
    secrets = {v["secret"]["secretName"] for v in pod.get("volumes", []) if "secret" in v}
    if not {"ispq-auth", "ispq-tls"} <= secrets:
        found.append("ispq-server: the token and the TLS material mounted from Secrets")
    tls_on = flag_value(args, "tls_cert") is not None
    for name in ["readinessProbe", "livenessProbe"]:
        probe = container.get(name)
        if probe is None:
            found.append(f"ispq-server: {name}")
            continue
        if tls_on and "grpc" in probe:
            found.append(f"{name}: the kubelet's gRPC probe speaks plaintext, TLS is on")
        if probe.get("timeoutSeconds", 1) < 3:
            found.append(f"{name}: timeoutSeconds of at least 3")
        if probe.get("failureThreshold", 3) < 2:
            found.append(f"{name}: failureThreshold of at least 2")
    readiness = container.get("readinessProbe", {})
    if "readiness" not in str(readiness):
        found.append("readinessProbe: asks the readiness health service")
    grace = float(flag_value(args, "shutdown_grace_seconds") or 25)
    pre_stop = 0
    command = container.get("lifecycle", {}).get("preStop", {}).get("exec", {}).get("command", [])
    if command[:1] == ["sleep"]:
        pre_stop = float(command[1])
    if pod.get("terminationGracePeriodSeconds", 30) < pre_stop + grace + 2:
        found.append("terminationGracePeriodSeconds must cover preStop + --shutdown_grace_seconds")
    if flag_value(args, "job_lease_seconds") is None:
        found.append("ispq-server: --job_lease_seconds set explicitly")
    services = by_kind.get("Service", [])
    headless = [s for s in services if s["spec"].get("clusterIP") == "None"
                and s["spec"]["selector"] == spec["selector"]["matchLabels"]]
    normal = [s for s in services if s["spec"].get("clusterIP") != "None"
              and s["spec"]["selector"] == spec["selector"]["matchLabels"]]
    if not headless or not normal:
        found.append("a headless Service (client balancing) and a normal one")
    if not by_kind.get("PodDisruptionBudget"):
        found.append("a PodDisruptionBudget")
    hpas = by_kind.get("HorizontalPodAutoscaler", [])
    metric_types = {m["type"] for h in hpas for m in h["spec"].get("metrics", [])}
    if not {"Resource", "Pods"} <= metric_types:
        found.append("an HPA on CPU and on the queue length (Pods metric)")
    return found


def check_the_checks(docs):
    """Each rule must catch a copy that breaks it."""
    breakers = {
        "token": lambda d: d["spec"]["template"]["spec"].pop("automountServiceAccountToken"),
        "replicas": lambda d: d["spec"].__setitem__("replicas", 1),
        "spread": lambda d: d["spec"]["template"]["spec"].pop("topologySpreadConstraints"),
        "grace": lambda d: d["spec"]["template"]["spec"].__setitem__(
            "terminationGracePeriodSeconds", 10),
        "probe": lambda d: d["spec"]["template"]["spec"]["containers"][0].__setitem__(
            "readinessProbe", {"grpc": {"port": 50051}, "failureThreshold": 1,
                               "timeoutSeconds": 1}),
        "image": lambda d: d["spec"]["template"]["spec"]["containers"][0].__setitem__(
            "image", "ispq-server:latest"),
    }
    failures = []
    for name, breaker in breakers.items():
        broken = copy.deepcopy(docs)
        for doc in broken:
            if doc["kind"] == "Deployment" and doc["metadata"]["name"] == "ispq-server":
                breaker(doc)
        if not problems(broken):
            failures.append(f"a copy with broken '{name}' passed the checks")
    return failures


def main():
    if subprocess.run(["kubectl", "version", "--client"], capture_output=True).returncode != 0:
        raise SystemExit("kubectl is needed for `kubectl kustomize` (the machines carry it)")
    lint = subprocess.run(["yamllint", "-d", "{extends: relaxed, rules: {line-length: {max: 100}}}",
                           KUBERNETES], capture_output=True, text=True)
    if lint.returncode != 0:
        raise SystemExit(f"yamllint:\n{lint.stdout}{lint.stderr}")
    failures = []
    for overlay in OVERLAYS:
        docs = render(overlay)
        failures += [f"{overlay}: {p}" for p in
                     problems(docs, pinned_by_digest=(overlay == "production"))]
        failures += [f"{overlay}: {p}" for p in check_the_checks(docs)]
        print(f"{overlay}: {len(docs)} objects: " +
              ", ".join(sorted(f"{d['kind']}/{d['metadata']['name']}" for d in docs)))
    for path in sorted(os.listdir(os.path.join(KUBERNETES, "overlays", "in-cluster-postgres"))):
        if path.endswith(".yaml"):
            with open(os.path.join(KUBERNETES, "overlays", "in-cluster-postgres", path)) as file:
                list(yaml.safe_load_all(file))
    if failures:
        print("\n".join(failures))
        sys.exit(1)
    print("manifests: all checks hold")


if __name__ == "__main__":
    main()
