#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Offline checks of the Kubernetes manifests in deploy/kubernetes.

Renders every overlay with `kubectl kustomize` (the kubectl the machines carry; without it the
check fails, it never skips), lints the sources with yamllint, and checks what the replicas
need: several replicas spread over nodes and zones, a headless and a normal Service, a
PodDisruptionBudget, an HPA on CPU and on the queue length (or KEDA's ScaledObject), probes on
the HTTP side's /healthz and /readyz over HTTPS with sane thresholds, a Service port for the HTTP
side, a NetworkPolicy that lets only the gRPC and HTTP ports in, Prometheus scraping (annotations
or a ServiceMonitor), an Ingress whose host the server answers, no service-account token, the job
store's URI from a Secret, dual-stack listen, a pinned image, and a termination grace period that
covers the server's shutdown.

Every rendered document (and every Secret of secrets.example.yaml) is validated against its
schema first, strictly (an unknown field is an error, as with `kubectl apply --validate=strict`),
and a document whose kind has no schema is a problem, so that no new kind slips through
unchecked. Core kinds (Deployment, StatefulSet, Service, NetworkPolicy, Ingress,
PodDisruptionBudget, HorizontalPodAutoscaler, Secret, ...) against Kubernetes' own OpenAPI v3
schema of 1.27, the oldest release deploy/README.md supports, and of 1.35 (the definitions they
reach, extracted from Kubernetes' api/openapi-spec/v3 into tests/deploy/schemas/
kubernetes-core.json by schemas/extract_core_schemas.py; openapi_schema.py). Custom resources
against their CRDs' schemas (tests/deploy/schemas, copied from KEDA and the Prometheus Operator with
their provenance; crd_schema.py): KEDA's ScaledObject and TriggerAuthentication, the
ServiceMonitor. The rules above hold valid objects to more than a schema can say. Beyond KEDA's
schema: the postgresql trigger counts the queue with the server's own query
(PostgresJobStore::QueuedCount) and reads the job store's URI from the Secret the Deployment reads
it from, a cpu trigger is there, and no second HPA targets the Deployment.

Then it checks that a deliberately broken copy of each rule is caught, so that the checks
themselves work.
"""
import copy
import os
import re
import subprocess
import sys

import yaml

import crd_schema
import openapi_schema

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
KUBERNETES = os.path.join(ROOT, "deploy", "kubernetes")
# overlay: pinned by digest
OVERLAYS = {"in-cluster-postgres": False, "production": True, "production-with-operators": True}
SCHEMAS = {}  # (apiVersion, kind): openAPIV3Schema of a custom resource
for _file in sorted(f for f in os.listdir(os.path.join(HERE, "schemas")) if f.endswith(".yaml")):
    _api, _kind, _schema = crd_schema.load_crd_schema(os.path.join(HERE, "schemas", _file))
    SCHEMAS[(_api, _kind)] = _schema
# Kubernetes version: openapi_schema.CoreSchemas of the core kinds
CORE_SCHEMAS = openapi_schema.load(os.path.join(HERE, "schemas", "kubernetes-core.json"))
# The keys KEDA's postgresql scaler reads from a trigger's metadata (pkg/scalers/
# postgresql_scaler.go, postgreSQLMetadata, at the commit of schemas/); anything else is a typo.
POSTGRESQL_METADATA = {"query", "targetQueryValue", "activationTargetQueryValue", "host", "port",
                       "userName", "dbName", "sslmode"}


def whitespace_normalized(text):
    return " ".join(text.split())


def server_queue_query():
    """The SQL with which the server counts its queue (what ispq_queue_length reports), from
    PostgresJobStore::QueuedCount: the KEDA trigger must count the same jobs."""
    with open(os.path.join(ROOT, "server", "store", "postgres", "postgres_job_store.cc")) as f:
        source = f.read()
    body = source[source.index("int PostgresJobStore::QueuedCount()"):]
    body = body[:body.index("\n}\n")]
    pieces = re.findall(r'"((?:[^"\\]|\\.)*)"', body)
    query = "".join(p for p in pieces if p)
    if not query.startswith("SELECT count(*) FROM ispq_jobs"):
        raise SystemExit(f"cannot find the queue's query in QueuedCount: {query!r}")
    return whitespace_normalized(query)


def queued_state_number():
    """JobState QUEUED's number in proto/ispq/v1/service.proto (the state column holds it)."""
    with open(os.path.join(ROOT, "proto", "ispq", "v1", "service.proto")) as f:
        return int(re.search(r"^\s*QUEUED = (\d+);", f.read(), re.M).group(1))


def exported_gauges():
    """The metric names /metrics exports (server/http/prometheus_text.cc)."""
    with open(os.path.join(ROOT, "server", "http", "prometheus_text.cc")) as f:
        return set(re.findall(r'"(ispq_[a-z_]+)"', f.read()))


def render(overlay):
    result = subprocess.run(["kubectl", "kustomize", os.path.join(KUBERNETES, "overlays", overlay)],
                            capture_output=True, text=True, timeout=120)
    if result.returncode != 0:
        raise SystemExit(f"kubectl kustomize {overlay} failed:\n{result.stderr}")
    return [doc for doc in yaml.safe_load_all(result.stdout) if doc]


def flag_value(args, name):
    """The flag's value as the server sees it: the last occurrence wins."""
    value = None
    for arg in args:
        if arg.startswith(f"--{name}="):
            value = arg.split("=", 1)[1]
    return value


def port_of(address):
    return int(address.rsplit(":", 1)[1]) if address and ":" in address else None


def names_port(container, port_ref, number):
    """Whether a probe's or a Service's port reference (a name or a number) is `number` in
    `container`'s ports."""
    if port_ref == number:
        return True
    return any(p.get("name") == port_ref and p.get("containerPort") == number
               for p in container.get("ports", []))


def host_allowed(host, allowed):
    """Whether --http_allowed_hosts lets a browser's `Host: host` (no port: 443) through."""
    for entry in allowed:
        if entry == "*" or entry == host or entry == f"{host}:443":
            return True
    return False


def problems(docs, pinned_by_digest=False):
    """The list of rules `docs` break (empty when all hold)."""
    found = schema_problems(docs)
    if found:
        return found  # the rules below need objects of the right shape
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
    http_port = port_of(flag_value(args, "http_listen"))
    http_tls = http_port is not None and (
        flag_value(args, "http_tls_cert") is not None or tls_on) and \
        flag_value(args, "http_plaintext") not in ("", "true")
    if http_port is None:
        found.append("ispq-server: --http_listen (the probes, /metrics and the web view)")
    elif not any(p.get("containerPort") == http_port for p in container.get("ports", [])):
        found.append(f"ispq-server: a containerPort for the HTTP side's {http_port}")
    paths = {"startupProbe": "/healthz", "readinessProbe": "/readyz", "livenessProbe": "/healthz"}
    for name, path in paths.items():
        probe = container.get(name)
        if probe is None:
            found.append(f"ispq-server: {name}")
            continue
        if tls_on and "grpc" in probe:
            found.append(f"{name}: the kubelet's gRPC probe speaks plaintext, TLS is on")
        get = probe.get("httpGet")
        if get is None:
            found.append(f"{name}: an httpGet probe on the HTTP side's {path}")
        else:
            if get.get("path") != path:
                found.append(f"{name}: httpGet path {path}, got {get.get('path')}")
            if http_port is None or not names_port(container, get.get("port"), http_port):
                found.append(f"{name}: httpGet on the HTTP side's port ({http_port})")
            scheme = "HTTPS" if http_tls else "HTTP"
            if get.get("scheme", "HTTP") != scheme:
                found.append(f"{name}: scheme {scheme} (the HTTP side is {scheme})")
        if name != "startupProbe" and probe.get("timeoutSeconds", 1) < 3:
            found.append(f"{name}: timeoutSeconds of at least 3")
        if name != "startupProbe" and probe.get("failureThreshold", 3) < 2:
            found.append(f"{name}: failureThreshold of at least 2")
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
    for service in normal:
        if http_port is not None and not any(
                names_port(container, p.get("targetPort"), http_port)
                for p in service["spec"].get("ports", [])):
            found.append(f"Service {service['metadata']['name']}: a port for the HTTP side")
    found += network_policy_problems(by_kind, spec, container, http_port)
    found += scrape_problems(by_kind, spec["template"], container, http_port, http_tls)
    found += ingress_problems(by_kind, container, args, http_port)
    found += database_connection_problems(by_kind, spec, args)
    target = {"apiVersion": "apps/v1", "kind": "Deployment", "name": "ispq-server"}
    hpas = [h for h in by_kind.get("HorizontalPodAutoscaler", [])
            if h["spec"]["scaleTargetRef"] == target]
    scaled = [o for o in by_kind.get("ScaledObject", [])
              if o["spec"]["scaleTargetRef"].get("name") == "ispq-server"]
    if scaled:
        found += keda_problems(by_kind, scaled, hpas, container)
    else:
        metrics = [m for h in hpas for m in h["spec"].get("metrics", [])]
        if not {"Resource", "Pods"} <= {m["type"] for m in metrics}:
            found.append("an HPA on CPU and on the queue length (Pods metric)")
        for metric in metrics:
            if metric["type"] == "Pods" and \
                    metric["pods"]["metric"]["name"] not in exported_gauges():
                found.append(f"HPA: Pods metric {metric['pods']['metric']['name']} is not one "
                             "that /metrics exports")
    return found


def schema_problems(docs):
    """Every document against its schema: a custom resource against its CRD's, a core kind against
    Kubernetes' of each version of CORE_SCHEMAS; a kind with neither is a problem."""
    found = []
    for doc in docs:
        api_version, kind = doc.get("apiVersion"), doc.get("kind")
        name = f"{kind} {(doc.get('metadata') or {}).get('name')}"
        if (api_version, kind) in SCHEMAS:
            schema = SCHEMAS[(api_version, kind)]
            found += [f"{name}: {e}" for e in crd_schema.validate(doc, schema)]
            continue
        versions = {}  # error: the Kubernetes versions whose schema reports it
        known = [core for core in CORE_SCHEMAS.values() if core.knows(api_version, kind)]
        for core in known:
            for error in core.validate_document(doc):
                versions.setdefault(error, []).append(core.version)
        found += [f"{name}: {e} (Kubernetes {', '.join(v)})" for e, v in versions.items()]
        if not known:
            found.append(f"{name}: no schema for {api_version} {kind} (a CRD's in tests/deploy/"
                         "schemas, or add the kind to schemas/extract_core_schemas.py)")
    return found


def database_connection_problems(by_kind, spec, args):
    """The in-cluster PostgreSQL takes the connections of the most replicas the autoscaler (HPA
    or ScaledObject) may run, plus a rollout's surge: each holds --workers + 8 (OpenStores in
    server/quantizer_server.cc: a pool of workers + 6, the listener, the reachability probe)."""
    database = [s for s in by_kind.get("StatefulSet", [])
                if s["metadata"]["name"] == "ispq-postgres"]
    if not database:
        return []
    most = max([h["spec"]["maxReplicas"] for h in by_kind.get("HorizontalPodAutoscaler", [])] +
               [o["spec"].get("maxReplicaCount", 100) for o in by_kind.get("ScaledObject", [])] +
               [spec.get("replicas", 1)])
    surge = spec.get("strategy", {}).get("rollingUpdate", {}).get("maxSurge", 1)
    needed = (most + surge) * (int(flag_value(args, "workers") or 1) + 8) + 10
    container = database[0]["spec"]["template"]["spec"]["containers"][0]
    arguments = " ".join(container.get("args", []))
    match = re.search(r"max_connections=(\d+)", arguments)
    have = int(match.group(1)) if match else 100
    found = []
    if have < needed:
        found.append(f"ispq-postgres: max_connections {have} < {needed} for {most} + {surge} "
                     "replicas")
    return found + database_network_policy_problems(by_kind, database[0], spec)


def database_network_policy_problems(by_kind, database, spec):
    """A NetworkPolicy on the in-cluster database lets in the replicas, on its port alone."""
    labels = database["spec"]["selector"]["matchLabels"]
    policies = [p for p in by_kind.get("NetworkPolicy", [])
                if p["spec"].get("podSelector", {}).get("matchLabels") == labels]
    if not policies:
        return ["a NetworkPolicy on ispq-postgres (only the replicas connect)"]
    container = database["spec"]["template"]["spec"]["containers"][0]
    ports = {p["containerPort"] for p in container.get("ports", [])}
    found = []
    for policy in policies:
        name = policy["metadata"]["name"]
        if "Ingress" not in policy["spec"].get("policyTypes", []):
            found.append(f"NetworkPolicy {name}: policyTypes Ingress")
        for rule in policy["spec"].get("ingress", []):
            sources = rule.get("from", [])
            if not sources or any(s != {"podSelector": {"matchLabels":
                                                         spec["selector"]["matchLabels"]}}
                                  for s in sources):
                found.append(f"NetworkPolicy {name}: a rule lets in more than the replicas")
            allowed = {next((p["containerPort"] for p in container.get("ports", [])
                             if port.get("port") in (p.get("name"), p.get("containerPort"))),
                            port.get("port")) for port in rule.get("ports", [])}
            if allowed != ports:
                found.append(f"NetworkPolicy {name}: lets in ports {sorted(map(str, allowed))}, "
                             f"not the database's {sorted(map(str, ports))}")
    return found


def network_policy_problems(by_kind, spec, container, http_port):
    """A NetworkPolicy on the replicas lets in the gRPC and HTTP ports and nothing else."""
    labels = spec["selector"]["matchLabels"]
    policies = [p for p in by_kind.get("NetworkPolicy", [])
                if p["spec"].get("podSelector", {}).get("matchLabels") == labels]
    if not policies:
        return ["a NetworkPolicy on the replicas"]
    grpc_port = port_of(flag_value(container.get("args", []), "listen"))
    wanted = {grpc_port, http_port}
    found = []
    for policy in policies:
        name = policy["metadata"]["name"]
        if "Ingress" not in policy["spec"].get("policyTypes", []):
            found.append(f"NetworkPolicy {name}: policyTypes Ingress")
        allowed = set()
        for rule in policy["spec"].get("ingress", []):
            if not rule.get("ports"):
                found.append(f"NetworkPolicy {name}: a rule without ports lets every port in")
                continue
            for port in rule["ports"]:
                number = next((p["containerPort"] for p in container.get("ports", [])
                               if port.get("port") in (p.get("name"), p.get("containerPort"))),
                              port.get("port"))
                allowed.add(number)
        if allowed != wanted:
            found.append(f"NetworkPolicy {name}: lets in ports {sorted(map(str, allowed))}, "
                         f"not exactly gRPC and HTTP {sorted(map(str, wanted))}")
    return found


def scrape_problems(by_kind, template, container, http_port, http_tls):
    """Prometheus can scrape /metrics: the pods' prometheus.io annotations, and a ServiceMonitor
    (if any) on a Service port that is the HTTP side, with the HTTP side's scheme."""
    found = []
    scheme = "https" if http_tls else "http"
    annotations = template.get("metadata", {}).get("annotations", {})
    if annotations.get("prometheus.io/scrape") != "true":
        found.append("pod annotation prometheus.io/scrape: \"true\"")
    elif (annotations.get("prometheus.io/port") != str(http_port) or
          annotations.get("prometheus.io/scheme", "http") != scheme or
          annotations.get("prometheus.io/path", "/metrics") != "/metrics"):
        found.append(f"pod annotations: prometheus.io/port {http_port}, scheme {scheme}, "
                     "path /metrics")
    services = by_kind.get("Service", [])
    for monitor in by_kind.get("ServiceMonitor", []):
        name = monitor["metadata"]["name"]
        selected = [s for s in services if monitor["spec"]["selector"]["matchLabels"].items() <=
                    s["metadata"].get("labels", {}).items()]
        for endpoint in monitor["spec"].get("endpoints", []):
            ports = [p for s in selected for p in s["spec"].get("ports", [])
                     if p.get("name") == endpoint.get("port")]
            if len(ports) != 1 or not names_port(container, ports[0].get("targetPort"), http_port):
                found.append(f"ServiceMonitor {name}: port {endpoint.get('port')} must be the "
                             "HTTP side's, on exactly one selected Service")
            if endpoint.get("scheme", "http") != scheme or endpoint.get("path") != "/metrics":
                found.append(f"ServiceMonitor {name}: scheme {scheme}, path /metrics")
            if http_tls and "ca" not in endpoint.get("tlsConfig", {}):
                found.append(f"ServiceMonitor {name}: tlsConfig.ca to verify the replicas")
    return found


def ingress_problems(by_kind, container, args, http_port):
    """An Ingress reaches the HTTP side, and its hosts are ones the server answers."""
    found = []
    allowed = (flag_value(args, "http_allowed_hosts") or "").split(",")
    services = {s["metadata"]["name"]: s for s in by_kind.get("Service", [])}
    for ingress in by_kind.get("Ingress", []):
        name = ingress["metadata"]["name"]
        annotations = ingress["metadata"].get("annotations", {})
        if annotations.get("nginx.ingress.kubernetes.io/backend-protocol") != "HTTPS" and \
                annotations.get("nginx.ingress.kubernetes.io/ssl-passthrough") != "true":
            found.append(f"Ingress {name}: re-encrypt (backend-protocol HTTPS) or passthrough")
        for rule in ingress["spec"].get("rules", []):
            if not host_allowed(rule.get("host", ""), allowed):
                found.append(f"Ingress {name}: host {rule.get('host')} is not in "
                             "--http_allowed_hosts (the server would answer 421)")
            for path in rule.get("http", {}).get("paths", []):
                backend = path["backend"]["service"]
                service = services.get(backend["name"])
                port = backend["port"].get("name", backend["port"].get("number"))
                if service is None or not any(
                        port in (p.get("name"), p.get("port")) and
                        names_port(container, p.get("targetPort"), http_port)
                        for p in service["spec"].get("ports", [])):
                    found.append(f"Ingress {name}: backend {backend} is not the HTTP side")
    return found


def keda_problems(by_kind, scaled, hpas, container):
    """KEDA's objects validate against their CRDs and count what the server counts."""
    found = []  # problems() has validated them against their schemas already
    if hpas:
        found.append("an HPA beside the ScaledObject: KEDA makes its own, two would fight")
    env = {e["name"]: e for e in container.get("env", [])}
    store_secret = env.get("ISPQ_JOB_STORE", {}).get("valueFrom", {}).get("secretKeyRef", {})
    authentications = {a["metadata"]["name"]: a for a in by_kind.get("TriggerAuthentication", [])}
    cpu_requested = "cpu" in container.get("resources", {}).get("requests", {})
    for scaled_object in scaled:
        name = scaled_object["metadata"]["name"]
        spec = scaled_object["spec"]
        # The CRD's CEL rule, which crd_schema does not evaluate.
        if spec.get("minReplicaCount", 0) > spec.get("maxReplicaCount", 100):
            found.append(f"ScaledObject {name}: minReplicaCount must be <= maxReplicaCount")
        if spec.get("minReplicaCount", 0) < 1:
            found.append(f"ScaledObject {name}: minReplicaCount >= 1 (a replica must be there "
                         "to accept submissions)")
        types = [t["type"] for t in spec["triggers"]]
        if "postgresql" not in types or "cpu" not in types:
            found.append(f"ScaledObject {name}: a postgresql trigger (the queue) and a cpu one")
        for trigger in spec["triggers"]:
            metadata = trigger.get("metadata", {})
            if trigger["type"] == "cpu":
                if trigger.get("metricType") not in ("Utilization", "AverageValue") or \
                        "value" not in metadata:
                    found.append(f"ScaledObject {name}: cpu trigger needs metricType and value")
                if not cpu_requested:
                    found.append(f"ScaledObject {name}: a cpu trigger needs CPU requests")
            if trigger["type"] != "postgresql":
                continue
            unknown = set(metadata) - POSTGRESQL_METADATA
            if unknown:
                found.append(f"ScaledObject {name}: postgresql metadata {sorted(unknown)} unknown")
            query = whitespace_normalized(metadata.get("query", ""))
            if query != server_queue_query():
                found.append(f"ScaledObject {name}: the query {query!r} is not the server's "
                             f"queue count {server_queue_query()!r}")
            if f"state = {queued_state_number()}" not in query:
                found.append(f"ScaledObject {name}: the query must count state QUEUED "
                             f"({queued_state_number()})")
            try:
                target_ok = float(metadata.get("targetQueryValue", "0")) > 0
            except ValueError:
                target_ok = False
            if not target_ok:
                found.append(f"ScaledObject {name}: targetQueryValue must be a positive number")
            reference = trigger.get("authenticationRef", {})
            authentication = authentications.get(reference.get("name"))
            if reference.get("kind", "TriggerAuthentication") != "TriggerAuthentication" or \
                    authentication is None:
                found.append(f"ScaledObject {name}: authenticationRef {reference} names no "
                             "TriggerAuthentication of the manifests")
                continue
            # The same Secret; another key of it is allowed (a URI whose sslrootcert path
            # KEDA's operator pod lacks needs one of its own: deploy/README.md).
            sources = {(r["parameter"], r["name"])
                       for r in authentication["spec"].get("secretTargetRef", [])}
            if ("connection", store_secret.get("name")) not in sources:
                found.append(f"TriggerAuthentication {reference['name']}: connection from the "
                             f"Deployment's job store Secret {store_secret.get('name')}")
    return found


def _container(docs):
    return _one(docs, "Deployment", "ispq-server")["spec"]["template"]["spec"]["containers"][0]


def _one(docs, kind, name=None):
    """The first document of `kind` (and `name`), or None."""
    return next((d for d in docs if d["kind"] == kind and
                 (name is None or d["metadata"]["name"] == name)), None)


def _trigger(docs, kind):
    return next(t for t in _one(docs, "ScaledObject")["spec"]["triggers"] if t["type"] == kind)


# name: (the kind that must be in the overlay for the rule to apply, what breaks it[, a piece of
# the problem that must be reported, e.g. the field's path])
BREAKERS = {
    # Kubernetes' schema of the core kinds: an unknown field, a type, a required field, a kind
    # without a schema...
    "container unknown field": ("Deployment", lambda d: _container(d).__setitem__(
        "imagePullPolicyy", "IfNotPresent"),
        "Deployment ispq-server: $.spec.template.spec.containers[0].imagePullPolicyy: unknown "
        "field (Kubernetes 1.27, 1.35)"),
    "replicas type": ("Deployment", lambda d: _one(d, "Deployment")["spec"].__setitem__(
        "replicas", "3"), "$.spec.replicas: '3' is not of type integer"),
    "container name required": ("Deployment", lambda d: _container(d).pop("name"),
                                "$.spec.template.spec.containers[0].name: missing (required)"),
    "int-or-string": ("Deployment", lambda d: _container(d)["readinessProbe"]["httpGet"]
                      .__setitem__("port", 8443.5),
                      "$.spec.template.spec.containers[0].readinessProbe.httpGet.port: 8443.5 "
                      "is not exactly one of integer or string"),
    "duplicate container port": ("Deployment", lambda d: _container(d)["ports"].append(
        dict(_container(d)["ports"][0])), "duplicate key (containerPort, protocol)"),
    "service port type": ("Service", lambda d: _one(d, "Service", "ispq-server")["spec"]["ports"]
                          [0].__setitem__("port", str(_one(d, "Service", "ispq-server")["spec"]
                                                     ["ports"][0]["port"])),
                          "Service ispq-server: $.spec.ports[0].port: "),
    "network policy unknown field": ("NetworkPolicy", lambda d: _one(d, "NetworkPolicy", "ispq-server")["spec"]
                                     ["ingress"][0]["ports"][0].__setitem__("protocl", "TCP"),
                                     "NetworkPolicy ispq-server: $.spec.ingress[0].ports[0]"
                                     ".protocl: unknown field"),
    "pdb int-or-string": ("PodDisruptionBudget", lambda d: _one(d, "PodDisruptionBudget")["spec"]
                          .__setitem__("minAvailable", True), "$.spec.minAvailable: True"),
    "hpa type": ("HorizontalPodAutoscaler", lambda d: _one(d, "HorizontalPodAutoscaler")["spec"]
                 .__setitem__("maxReplicas", "10"), "$.spec.maxReplicas: '10' is not of type"),
    "ingress unknown field": ("Ingress", lambda d: _one(d, "Ingress")["spec"].__setitem__(
        "ingressClass", "nginx"), "Ingress ispq-web: $.spec.ingressClass: unknown field"),
    "statefulset unknown field": ("StatefulSet", lambda d: _one(d, "StatefulSet")["spec"]
                                  ["template"]["spec"].__setitem__("terminationGracePeriod", 10),
                                  "$.spec.template.spec.terminationGracePeriod: unknown field"),
    "kind without schema": ("Deployment", lambda d: d.append({
        "apiVersion": "v1", "kind": "LimitRange", "metadata": {"name": "ispq"}, "spec": {}}),
        "LimitRange ispq: no schema for v1 LimitRange"),
    "token": ("Deployment", lambda d: _one(d, "Deployment")["spec"]["template"]["spec"].pop(
        "automountServiceAccountToken")),
    "replicas": ("Deployment", lambda d: _one(d, "Deployment")["spec"].__setitem__("replicas", 1)),
    "spread": ("Deployment", lambda d: _one(d, "Deployment")["spec"]["template"]["spec"].pop(
        "topologySpreadConstraints")),
    "grace": ("Deployment", lambda d: _one(d, "Deployment")["spec"]["template"]["spec"]
              .__setitem__("terminationGracePeriodSeconds", 10)),
    "grpc probe": ("Deployment", lambda d: _container(d).__setitem__(
        "readinessProbe", {"grpc": {"port": 50051}, "failureThreshold": 1, "timeoutSeconds": 1})),
    "probe scheme": ("Deployment", lambda d: _container(d)["livenessProbe"]["httpGet"]
                     .__setitem__("scheme", "HTTP")),
    "readiness path": ("Deployment", lambda d: _container(d)["readinessProbe"]["httpGet"]
                       .__setitem__("path", "/healthz")),
    "probe port": ("Deployment", lambda d: _container(d)["startupProbe"]["httpGet"]
                   .__setitem__("port", "grpc")),
    "image": ("Deployment", lambda d: _container(d).__setitem__("image", "ispq-server:latest")),
    "http port": ("Deployment", lambda d: _container(d)["args"].remove(
        next(a for a in _container(d)["args"] if a.startswith("--http_listen=")))),
    "service http port": ("Service", lambda d: _one(d, "Service", "ispq-server")["spec"]
                          .__setitem__("ports", _one(d, "Service", "ispq-server")["spec"]
                                       ["ports"][:1])),
    "network policy ports": ("NetworkPolicy", lambda d: _one(d, "NetworkPolicy", "ispq-server")["spec"]
                             ["ingress"].append({"from": [{"podSelector": {}}]})),
    "network policy port": ("NetworkPolicy", lambda d: _one(d, "NetworkPolicy", "ispq-server")["spec"]
                            ["ingress"][0]["ports"].append({"port": 5432})),
    "no network policy": ("NetworkPolicy",
                          lambda d: d.remove(_one(d, "NetworkPolicy", "ispq-server"))),
    # The in-cluster database's NetworkPolicy: only the replicas, only its port.
    "database policy": ("StatefulSet", lambda d: d.remove(_one(d, "NetworkPolicy",
                                                               "ispq-postgres")),
                        "a NetworkPolicy on ispq-postgres"),
    "database policy source": ("StatefulSet", lambda d: _one(d, "NetworkPolicy", "ispq-postgres")
                               ["spec"]["ingress"][0]["from"].append({"podSelector": {}}),
                               "NetworkPolicy ispq-postgres: a rule lets in more than the "
                               "replicas"),
    "database policy port": ("StatefulSet", lambda d: _one(d, "NetworkPolicy", "ispq-postgres")
                             ["spec"]["ingress"][0]["ports"].append({"port": 8443}),
                             "NetworkPolicy ispq-postgres: lets in ports"),
    "scrape annotation": ("Deployment", lambda d: _one(d, "Deployment")["spec"]["template"]
                          ["metadata"]["annotations"].__setitem__("prometheus.io/port", "50051")),
    "service monitor port": ("ServiceMonitor", lambda d: _one(d, "ServiceMonitor")["spec"]
                             ["endpoints"][0].__setitem__("port", "grpc")),
    "service monitor scheme": ("ServiceMonitor", lambda d: _one(d, "ServiceMonitor")["spec"]
                               ["endpoints"][0].__setitem__("scheme", "http")),
    "service monitor schema": ("ServiceMonitor", lambda d: _one(d, "ServiceMonitor")["spec"]
                               ["endpoints"][0].__setitem__("interval", "15 seconds")),
    "ingress host": ("Ingress", lambda d: _one(d, "Ingress")["spec"]["rules"][0].__setitem__(
        "host", "elsewhere.example.com")),
    "ingress backend": ("Ingress", lambda d: _one(d, "Ingress")["spec"]["rules"][0]["http"]
                        ["paths"][0]["backend"]["service"].__setitem__("port", {"name": "grpc"})),
    "database connections": ("StatefulSet", lambda d: _one(d, "StatefulSet", "ispq-postgres")
                             ["spec"]["template"]["spec"]["containers"][0].pop("args")),
    "hpa metric": ("HorizontalPodAutoscaler", lambda d: _one(d, "HorizontalPodAutoscaler")
                   ["spec"]["metrics"][1]["pods"]["metric"].__setitem__("name",
                                                                        "ispq_queued_jobs")),
    # KEDA: the CRD's schema (an unknown field, a type, a minimum, an enum, a required field)...
    "keda unknown field": ("ScaledObject", lambda d: _one(d, "ScaledObject")["spec"].__setitem__(
        "trigers", _one(d, "ScaledObject")["spec"]["triggers"])),
    "keda type": ("ScaledObject", lambda d: _one(d, "ScaledObject")["spec"].__setitem__(
        "maxReplicaCount", "12")),
    "keda minimum": ("ScaledObject", lambda d: _one(d, "ScaledObject")["spec"].__setitem__(
        "pollingInterval", 0)),
    "keda enum": ("ScaledObject", lambda d: _trigger(d, "postgresql")["authenticationRef"]
                  .__setitem__("kind", "Secret")),
    "keda required": ("ScaledObject", lambda d: _trigger(d, "cpu").pop("type")),
    "keda auth schema": ("TriggerAuthentication", lambda d: _one(d, "TriggerAuthentication")
                         ["spec"]["secretTargetRef"][0].pop("key")),
    # ... and what the schema cannot know.
    "keda min > max": ("ScaledObject", lambda d: _one(d, "ScaledObject")["spec"].__setitem__(
        "minReplicaCount", 20)),
    "keda to zero": ("ScaledObject", lambda d: _one(d, "ScaledObject")["spec"].__setitem__(
        "minReplicaCount", 0)),
    "keda query": ("ScaledObject", lambda d: _trigger(d, "postgresql")["metadata"].__setitem__(
        "query", "SELECT count(*) FROM ispq_jobs WHERE state IN (1, 2) AND NOT bound_to_call")),
    "keda metadata": ("ScaledObject", lambda d: _trigger(d, "postgresql")["metadata"]
                      .__setitem__("targetValue", "4")),
    "keda target": ("ScaledObject", lambda d: _trigger(d, "postgresql")["metadata"].__setitem__(
        "targetQueryValue", "0")),
    "keda auth ref": ("ScaledObject", lambda d: _trigger(d, "postgresql")["authenticationRef"]
                      .__setitem__("name", "missing")),
    "keda auth secret": ("TriggerAuthentication", lambda d: _one(d, "TriggerAuthentication")
                         ["spec"]["secretTargetRef"][0].__setitem__("name", "ispq-postgres")),
    "keda cpu": ("ScaledObject", lambda d: _one(d, "ScaledObject")["spec"]["triggers"].remove(
        _trigger(d, "cpu"))),
    "keda with hpa": ("ScaledObject", lambda d: d.append({
        "apiVersion": "autoscaling/v2", "kind": "HorizontalPodAutoscaler",
        "metadata": {"name": "ispq-server"},
        "spec": {"scaleTargetRef": {"apiVersion": "apps/v1", "kind": "Deployment",
                                    "name": "ispq-server"}, "maxReplicas": 10, "metrics": []}}),
        "an HPA beside the ScaledObject"),
}


def check_the_checks(docs):
    """Each rule that applies to the overlay must catch a copy that breaks it; the names of the
    breakers that applied."""
    failures, applied = [], []
    kinds = {d["kind"] for d in docs}
    for name, (kind, breaker, *expected) in BREAKERS.items():
        if kind not in kinds:
            continue
        broken = copy.deepcopy(docs)
        breaker(broken)
        applied.append(name)
        found = problems(broken)
        if not found:
            failures.append(f"a copy with broken '{name}' passed the checks")
        elif expected and not any(expected[0] in p for p in found):
            failures.append(f"a copy with broken '{name}' was caught, but not as "
                            f"{expected[0]!r}: {found}")
    return failures, applied


def main():
    if subprocess.run(["kubectl", "version", "--client"], capture_output=True).returncode != 0:
        raise SystemExit("kubectl is needed for `kubectl kustomize` (the machines carry it)")
    lint = subprocess.run(["yamllint", "-d", "{extends: relaxed, rules: {line-length: {max: 100}}}",
                           KUBERNETES], capture_output=True, text=True)
    if lint.returncode != 0:
        raise SystemExit(f"yamllint:\n{lint.stdout}{lint.stderr}")
    failures = []
    for overlay, pinned in OVERLAYS.items():
        docs = render(overlay)
        failures += [f"{overlay}: {p}" for p in problems(docs, pinned_by_digest=pinned)]
        caught, applied = check_the_checks(docs)
        failures += [f"{overlay}: {p}" for p in caught]
        print(f"{overlay}: {len(docs)} objects: " +
              ", ".join(sorted(f"{d['kind']}/{d['metadata']['name']}" for d in docs)))
        core = [d for d in docs if any(c.knows(d["apiVersion"], d["kind"])
                                       for c in CORE_SCHEMAS.values())]
        custom = [d for d in docs if (d["apiVersion"], d["kind"]) in SCHEMAS]
        print(f"{overlay}: validated against Kubernetes {', '.join(CORE_SCHEMAS)}'s schema: "
              f"{len(core)} ({', '.join(sorted({d['kind'] for d in core}))}); against a CRD's: "
              f"{len(custom)} ({', '.join(sorted({d['kind'] for d in custom})) or 'none'})")
        print(f"{overlay}: {len(applied)} broken copies caught: {', '.join(applied)}")
    for path in sorted(os.listdir(os.path.join(KUBERNETES, "overlays", "in-cluster-postgres"))):
        if path.endswith(".yaml"):
            with open(os.path.join(KUBERNETES, "overlays", "in-cluster-postgres", path)) as file:
                docs = [doc for doc in yaml.safe_load_all(file) if doc]
            if path != "kustomization.yaml":  # the example Secrets, not part of the overlay
                failures += [f"in-cluster-postgres/{path}: {p}" for p in schema_problems(docs)]
    if failures:
        print("\n".join(failures))
        sys.exit(1)
    print("manifests: all checks hold")


if __name__ == "__main__":
    main()
