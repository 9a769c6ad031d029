#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The server's layers (server/CMakeLists.txt) hold: every `#include "server/..."` under server/
names a header of the including file's own layer or of a layer below it, never one above or
beside it; gRPC's headers (grpcpp/, grpc/, generated *.grpc.pb.h) are included only in the
layers of GRPC_LAYERS (the gRPC transport and the wiring), so that everything else, the HTTP
transport and the service included, is free of gRPC; and the top level of server/ keeps at most
MAX_TOP_LEVEL_FILES files (the wiring).

LAYERS below is the one table of the layering. Each layer is a folder with a CMake library of
its own, and that library links exactly the layers listed here as directly below it (checked
too, so that the table and the build cannot drift apart); what a layer may include is its own
headers and those of every layer below it, directly or through others.

  check_server_layers.py    report every violation (file:line); exit 1 if there is any
"""
import os
import re
import sys

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# folder: (CMake library, the layers directly below it). A file belongs to the longest folder
# that contains it; "server" is the top level (main, config, readiness: the wiring).
LAYERS = {
    "server/auth": ("ispq_server_auth", []),
    "server/logging": ("ispq_server_logging", []),
    "server/metrics": ("ispq_server_metrics", []),
    "server/memory": ("ispq_server_memory", []),
    "server/model": ("ispq_server_model", ["server/memory"]),
    "server/store": ("ispq_server_store", ["server/model"]),
    "server/store/postgres": ("ispq_server_store_postgres", ["server/store", "server/logging"]),
    "server/jobs": ("ispq_server_jobs", ["server/store", "server/metrics", "server/logging"]),
    "server/admission": ("ispq_server_admission", ["server/jobs", "server/auth"]),
    "server/service": ("ispq_server_service", ["server/admission"]),
    "server/grpc": ("ispq_server_grpc", ["server/service"]),
    "server/http": ("ispq_server_http", ["server/service"]),
    "server": ("ispq_server", ["server/grpc", "server/http", "server/store/postgres"]),
}
# The only layers whose files may include gRPC's headers.
GRPC_LAYERS = {"server/grpc", "server"}
MAX_TOP_LEVEL_FILES = 12  # CMakeLists.txt included

SOURCES = (".h", ".cc")
INCLUDE = re.compile(r'^\s*#\s*include\s+"(server/[^"]+)"')
GRPC_INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]((?:grpcpp|grpc)/[^">]+|[^">]*\.grpc\.pb\.h)[">]')
LINKS = re.compile(r"target_link_libraries\(\s*([A-Za-z0-9_-]+)([^)]*)\)", re.S)


def layer_of(path):
    """The layer (a key of LAYERS) of a path relative to ROOT, or None if it is in no layer."""
    folder = os.path.dirname(path)
    while folder:
        if folder in LAYERS:
            return folder
        folder = os.path.dirname(folder)
    return None


def below(layer):
    """Every layer below `layer`, directly or through others."""
    seen = set()
    todo = list(LAYERS[layer][1])
    while todo:
        lower = todo.pop()
        if lower not in seen:
            seen.add(lower)
            todo.extend(LAYERS[lower][1])
    return seen


def check_table():
    problems = []
    for layer in GRPC_LAYERS - set(LAYERS):
        problems.append(f"GRPC_LAYERS: {layer} is no layer")
    for layer, (_, lowers) in LAYERS.items():
        for lower in lowers:
            if lower not in LAYERS:
                problems.append(f"LAYERS: {layer} names {lower}, which is no layer")
    for layer in LAYERS:
        if layer in below(layer):
            problems.append(f"LAYERS: {layer} is below itself (a cycle)")
    return problems


def check_folders():
    """Every folder under server/ that holds sources is a layer of LAYERS, with its own library."""
    problems = []
    for folder, _, files in os.walk(os.path.join(ROOT, "server")):
        rel = os.path.relpath(folder, ROOT)
        if not any(f.endswith(SOURCES) for f in files):
            continue
        if rel not in LAYERS:
            problems.append(f"{rel}/: a folder of sources that is no layer of LAYERS in "
                            f"{os.path.relpath(__file__, ROOT)}; add it there, with its place")
        elif "CMakeLists.txt" not in files:
            problems.append(f"{rel}/: a layer without a CMakeLists.txt of its own")
    return problems


def check_includes():
    problems = []
    for folder, _, files in os.walk(os.path.join(ROOT, "server")):
        for name in sorted(files):
            if not name.endswith(SOURCES):
                continue
            path = os.path.relpath(os.path.join(folder, name), ROOT)
            layer = layer_of(path)
            if os.path.dirname(path) != layer:
                continue  # in a folder that is no layer, reported by check_folders
            allowed = below(layer) | {layer}
            with open(os.path.join(ROOT, path), encoding="utf-8") as f:
                for number, line in enumerate(f, 1):
                    grpc = GRPC_INCLUDE.match(line)
                    if grpc and layer not in GRPC_LAYERS:
                        problems.append(
                            f"{path}:{number}: includes gRPC's {grpc.group(1)}; only "
                            f"{', '.join(f'{layer}/' for layer in sorted(GRPC_LAYERS))} may (the others are free of gRPC)")
                        continue
                    match = INCLUDE.match(line)
                    if not match:
                        continue
                    header = match.group(1)
                    if not os.path.isfile(os.path.join(ROOT, header)):
                        problems.append(f"{path}:{number}: includes {header}, which does not exist")
                        continue
                    target = layer_of(header)
                    if target not in allowed:
                        problems.append(
                            f"{path}:{number}: includes {header} of layer {target}/, which is not "
                            f"below {layer}/ (it may include {', '.join(sorted(allowed))})")
    return problems


def check_links():
    """Each layer's library links exactly the layers LAYERS puts directly below it."""
    problems = []
    libraries = {library for library, _ in LAYERS.values()}
    for layer, (library, lowers) in LAYERS.items():
        cmake = os.path.join(layer, "CMakeLists.txt")
        try:
            with open(os.path.join(ROOT, cmake), encoding="utf-8") as f:
                text = re.sub(r"#[^\n]*", "", f.read())
        except FileNotFoundError:
            problems.append(f"{cmake}: missing (layer {layer}/ builds {library})")
            continue
        links = None
        for match in LINKS.finditer(text):
            if match.group(1) == library:
                links = set(match.group(2).split()) & libraries
        if links is None:
            problems.append(f"{cmake}: no target_link_libraries({library} ...)")
            continue
        expected = {LAYERS[lower][0] for lower in lowers}
        for extra in sorted(links - expected):
            problems.append(f"{cmake}: {library} links {extra}, not a layer directly below "
                            f"{layer}/ in LAYERS of {os.path.relpath(__file__, ROOT)}")
        for absent in sorted(expected - links):
            problems.append(f"{cmake}: {library} does not link {absent}, which LAYERS puts "
                            f"directly below {layer}/")
    return problems


def check_top_level():
    top = os.path.join(ROOT, "server")
    files = sorted(f for f in os.listdir(top)
                   if os.path.isfile(os.path.join(top, f)) and not f.startswith("."))
    if len(files) > MAX_TOP_LEVEL_FILES:
        return [f"server/: {len(files)} files at the top level, at most {MAX_TOP_LEVEL_FILES} "
                f"(the wiring); move the others into their layer: {' '.join(files)}"]
    return []


def main():
    problems = check_table() + check_folders() + check_includes() + check_links()
    problems += check_top_level()
    for problem in problems:
        print(problem)
    if problems:
        print(f"{len(problems)} layering problem(s); the layers are in LAYERS of "
              f"{os.path.relpath(__file__, ROOT)}")
        return 1
    print(f"server/: {len(LAYERS)} layers, every include downwards, gRPC only in "
          f"{', '.join(f'{layer}/' for layer in sorted(GRPC_LAYERS))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
