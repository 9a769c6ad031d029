#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Writes kubernetes-core.json beside this file: the parts of Kubernetes' own OpenAPI v3 documents
(api/openapi-spec/v3 of github.com/kubernetes/kubernetes, Apache-2.0, (c) The Kubernetes Authors)
that the offline manifest check (tests/deploy/check_manifests.py, validator openapi_schema.py)
needs: for each Kubernetes version asked for, the schemas of the core kinds in KINDS and every
definition they reach through $ref, without descriptions, defaults and the patch-strategy
annotations (which validation does not read). Nothing else is changed.

Run by hand when moving to other Kubernetes versions (never by the test, which stays offline),
from a git directory holding the documents (KUBECTL_VALIDATE_GIT_DIR: what the search tool's
`fetch github:kubernetes-sigs/kubectl-validate` gives):

  # kubernetes-sigs/kubectl-validate keeps release-1.N's api/openapi-spec/v3, byte for byte as
  # its cmd/download-builtin-schemas took them, as
  # pkg/openapiclient/builtins/1.N/{api,apis/GROUP}/VERSION.json
  python3 tests/deploy/schemas/extract_core_schemas.py \
      --kubectl-validate KUBECTL_VALIDATE_GIT_DIR \
      --commit a97ccfaca20b164819afdae780392496f6ed6bbd 1.27 1.35

  # or straight from a kubernetes/kubernetes clone, one release tag per version
  python3 tests/deploy/schemas/extract_core_schemas.py --kubernetes KUBERNETES_GIT_DIR \
      v1.27.16 v1.35.0

This is how the committed kubernetes-core.json was made (the first form: the kubernetes/kubernetes
repository is too large for the fetch tool). Add a kind to KINDS when the manifests start to use
one; check_manifests.py reports a kind that has no schema.
"""
import argparse
import json
import os
import subprocess

# (apiVersion, kind) the manifests use or are likely to (a kind the overlays do not render costs
# only its own definitions: the pod template's closure is shared).
KINDS = [
    ("v1", "ConfigMap"), ("v1", "Namespace"), ("v1", "PersistentVolumeClaim"), ("v1", "Secret"),
    ("v1", "Service"), ("v1", "ServiceAccount"),
    ("apps/v1", "Deployment"), ("apps/v1", "StatefulSet"),
    ("autoscaling/v2", "HorizontalPodAutoscaler"),
    ("networking.k8s.io/v1", "Ingress"), ("networking.k8s.io/v1", "NetworkPolicy"),
    ("policy/v1", "PodDisruptionBudget"),
]
# Annotations validation does not read; everything else of a schema is kept.
DROPPED = {"description", "default", "example", "x-kubernetes-patch-strategy",
           "x-kubernetes-patch-merge-key", "x-kubernetes-map-type", "x-kubernetes-unions",
           "x-kubernetes-group-version-kind"}
REF = "#/components/schemas/"
OUTPUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "kubernetes-core.json")


def document_paths(api_version, layout, version):
    """The path of the OpenAPI v3 document of `api_version` in the source's tree."""
    group, _, gv_version = api_version.rpartition("/")
    if layout == "kubectl-validate":
        prefix = f"pkg/openapiclient/builtins/{version}/"
        return prefix + (f"apis/{group}/{gv_version}.json" if group else f"api/{gv_version}.json")
    prefix = "api/openapi-spec/v3/"
    return prefix + (f"apis__{group}__{gv_version}_openapi.json" if group
                     else f"api__{gv_version}_openapi.json")


def git_show(git_dir, revision, path):
    return subprocess.run(["git", "--git-dir", git_dir, "show", f"{revision}:{path}"],
                          check=True, capture_output=True).stdout


def strip(schema):
    """`schema` without the annotations of DROPPED, recursively (the names under `properties` are
    field names, not keywords, and stay)."""
    if isinstance(schema, list):
        return [strip(s) for s in schema]
    if not isinstance(schema, dict):
        return schema
    out = {}
    for key, value in schema.items():
        if key in DROPPED:
            continue
        if key == "properties":
            out[key] = {name: strip(s) for name, s in value.items()}
        elif key in ("items", "additionalProperties", "allOf", "oneOf", "anyOf", "not"):
            out[key] = strip(value)
        else:
            out[key] = value
    return out


def references(schema):
    if isinstance(schema, dict):
        for key, value in schema.items():
            if key == "$ref":
                yield value[len(REF):]
            else:
                yield from references(value)
    elif isinstance(schema, list):
        for value in schema:
            yield from references(value)


def extract(read, version):
    """{"kinds": {"apiVersion kind": definition}, "schemas": {definition: schema}} of one
    version; `read(api_version)` gives that group-version's document."""
    kinds, schemas, sources = {}, {}, {}
    for api_version in sorted({a for a, _ in KINDS}):
        document = json.loads(read(api_version))
        sources[api_version] = document["components"]["schemas"]
    for api_version, kind in KINDS:
        definitions = sources[api_version]
        group, _, gv_version = api_version.rpartition("/")
        names = [n for n, d in definitions.items()
                 if {"group": group, "version": gv_version, "kind": kind}
                 in d.get("x-kubernetes-group-version-kind", [])]
        if len(names) != 1:
            raise SystemExit(f"{version}: {api_version} {kind}: definitions {names}")
        kinds[f"{api_version} {kind}"] = names[0]
        pending = [names[0]]
        while pending:
            name = pending.pop()
            if name not in definitions:
                raise SystemExit(f"{version}: {name} (from {api_version}) is not defined")
            if name in schemas:
                if schemas[name] != strip(definitions[name]):  # the documents share definitions
                    raise SystemExit(f"{version}: {name} differs between the documents")
                continue
            schemas[name] = strip(definitions[name])
            pending += references(schemas[name])
    return {"kinds": kinds, "schemas": dict(sorted(schemas.items()))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--kubectl-validate", metavar="GIT_DIR",
                        help="a kubernetes-sigs/kubectl-validate git directory")
    source.add_argument("--kubernetes", metavar="GIT_DIR",
                        help="a kubernetes/kubernetes git directory")
    parser.add_argument("--commit", default="HEAD",
                        help="the kubectl-validate commit (with --kubectl-validate)")
    parser.add_argument("versions", nargs="+",
                        help="1.N (with --kubectl-validate) or release tags vX.Y.Z")
    args = parser.parse_args()
    git_dir = args.kubectl_validate or args.kubernetes
    layout = "kubectl-validate" if args.kubectl_validate else "kubernetes"
    output = {"provenance": {
        "source": "github.com/kubernetes/kubernetes, api/openapi-spec/v3 "
                  "(api__v1_openapi.json, apis__GROUP__VERSION_openapi.json)",
        "licence": "Apache-2.0, (c) The Kubernetes Authors",
        "copied": "the definitions reachable from the kinds listed, without description, "
                  "default, example and x-kubernetes-{patch-strategy,patch-merge-key,map-type,"
                  "unions,group-version-kind}; nothing else changed",
        "generator": "tests/deploy/schemas/extract_core_schemas.py (its docstring: how it was run)",
    }, "versions": {}}
    if layout == "kubectl-validate":
        commit = subprocess.run(["git", "--git-dir", git_dir, "rev-parse", args.commit], check=True,
                                capture_output=True, text=True).stdout.strip()
        output["provenance"]["via"] = (
            "github.com/kubernetes-sigs/kubectl-validate at commit " + commit +
            ", pkg/openapiclient/builtins/1.N/ (release-1.N's api/openapi-spec/v3, unchanged)")
    for version in args.versions:
        revision = args.commit if layout == "kubectl-validate" else version
        key = version.lstrip("v").rsplit(".", 1)[0] if layout == "kubernetes" else version
        extracted = extract(
            lambda a: git_show(git_dir, revision, document_paths(a, layout, version)), version)
        extracted["from"] = sorted({document_paths(a, layout, version) for a, _ in KINDS})
        if layout == "kubectl-validate":  # when kubectl-validate took release-1.N's documents
            extracted["release branch as of"] = subprocess.run(
                ["git", "--git-dir", git_dir, "log", "-1", "--format=%cs", revision, "--",
                 *extracted["from"]],
                check=True, capture_output=True, text=True).stdout.strip()
        if layout == "kubernetes":
            extracted["tag"] = version
        output["versions"][key] = extracted
    # One definition a line: small, and a refresh's diff stays readable.
    lines = ["{", f'"provenance": {json.dumps(output["provenance"], indent=1)},', '"versions": {']
    for i, (version, extracted) in enumerate(output["versions"].items()):
        lines.append(f'{json.dumps(version)}: {{')
        for key in ("from", "release branch as of", "tag", "kinds"):
            if key in extracted:
                lines.append(f'{json.dumps(key)}: {json.dumps(extracted[key], sort_keys=True)},')
        lines.append('"schemas": {')
        items = list(extracted["schemas"].items())
        for j, (name, schema) in enumerate(items):
            comma = "," if j < len(items) - 1 else ""
            lines.append(f"{json.dumps(name)}: "
                         f"{json.dumps(schema, sort_keys=True, separators=(',', ':'))}{comma}")
        lines.append("}}" + ("," if i < len(output["versions"]) - 1 else ""))
    lines.append("}}")
    text = "\n".join(lines) + "\n"
    assert json.loads(text) == json.loads(json.dumps(output))
    with open(OUTPUT, "w") as f:
        f.write(text)
    print(f"{OUTPUT}: {len(text)} bytes, " + ", ".join(
        f"{v}: {len(e['schemas'])} definitions" for v, e in output["versions"].items()))


if __name__ == "__main__":
    main()
