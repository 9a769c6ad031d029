#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Clang's thread-safety analysis over every translation unit of the server, the client, core
and their threaded tests: the ABSL_GUARDED_BY / ABSL_EXCLUSIVE_LOCKS_REQUIRED / ABSL_LOCKS_EXCLUDED
annotations of the code are checked, not just written (GCC, which builds everything else,
ignores them).

Each TU whose code can hold a diagnostic of the analysis is compiled by clang++ with -fsyntax-only (no code generation, nothing written) and the
very flags and includes of the release build, read from its compile_commands.json; every
warning but the thread-safety ones is turned off, and those are errors. The generated protobuf
and gRPC headers come from that build, so it has to exist (tests/run.sh builds it first).

A TU can only have such a diagnostic if it or a file of the checkout it includes, directly or
not, holds a capability or an annotation: a lock (absl/synchronization/, std::mutex), an ABSL_
thread-safety macro, or clang's attributes themselves. The others (all of core/, most of the
client) are skipped by default, which more than halves the cost; --all checks them too (same
diagnostics, as this check's own test of that filter showed when it was written).

  check_thread_safety.py [--build DIR] [--jobs N] [--all] [FILE_SUBSTRING ...]

  --build DIR       the build whose compile_commands.json is read (default build/release)
  --jobs N          parallel clang processes (default 2: the machines have 2 cores)
  --all             also the TUs that include no lock or annotation
  FILE_SUBSTRING    only the TUs whose path (relative to the checkout) contains one of these

Prints every diagnostic once (file:line: ...) and exits 1 if there is any, or if clang fails on
a TU for another reason (then that TU was not checked).
"""
import argparse
import concurrent.futures
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# The checked trees. tests/unit, tests/bench and tests/differential hold single-threaded tests
# of core/ and tools; the generated protobuf sources are not ours.
CHECKED = ("server/", "client/", "core/", "tests/server/", "tests/client/", "tests/integration/",
           "tests/support/", "tests/load/")

# Off: every other warning (GCC's -Wall -Wextra -Werror build covers them; clang's own opinions
# would only make this check fail for reasons it is not about). On, as errors: the analysis of
# the annotations, including -Wthread-safety-reference (passing a guarded member by reference)
# and -Wthread-safety-beta (the analysis of e.g. guarded members' accesses through pointers and
# of the lock's scope in more cases; clean on this tree, see README).
CLANG_WARNINGS = [
    "-Wno-everything",
    "-Wthread-safety",
    "-Wthread-safety-reference",
    "-Wthread-safety-beta",
    "-Werror=thread-safety",
    "-Werror=thread-safety-reference",
    "-Werror=thread-safety-beta",
]


# What makes a file relevant to the analysis (see above). Matched on the text of the TU and of
# every file of the checkout it includes with #include "...".
CAPABILITY = re.compile(
    r"absl/synchronization/|absl/base/thread_annotations\.h|std::(recursive_|shared_|timed_)?mutex"
    r"|\bABSL_[A-Z_]*(GUARDED_BY|LOCKS_REQUIRED|LOCKS_EXCLUDED|LOCKABLE|LOCK_FUNCTION"
    r"|LOCK_RETURNED|ACQUIRED_BEFORE|ACQUIRED_AFTER|ASSERT_[A-Z_]*LOCK|THREAD_SAFETY_ANALYSIS)\b"
    r"|__attribute__\s*\(\(\s*(capability|lockable|scoped_lockable|guarded_by|pt_guarded_by"
    r"|requires_capability|acquire_capability|release_capability|locks_excluded)\b")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def reaches_capability(path, memo):
    """Whether `path` or a file of the checkout it includes mentions a capability."""
    if path in memo:
        return memo[path]
    memo[path] = False  # include cycles: the first visit decides
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
    except OSError:
        return False
    found = bool(CAPABILITY.search(text))
    for name in INCLUDE.findall(text):
        for base in (ROOT, os.path.dirname(path)):
            candidate = os.path.join(base, name)
            if os.path.exists(candidate):
                found = reaches_capability(os.path.realpath(candidate), memo) or found
                break
    memo[path] = found
    return found


def clang_command(entry, clang):
    """The TU's own compile command, made a clang syntax-only pass of the analysis."""
    args = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
    out = [clang]
    skip = False
    for arg in args[1:]:
        if skip:
            skip = False
            continue
        if arg == "-o":
            skip = True
            continue
        if arg == "-c" or (arg.startswith("-W") and not arg.startswith("-Wl,")):
            continue
        out.append(arg)
    return out + ["-fsyntax-only"] + CLANG_WARNINGS


def check(entry, clang):
    command = clang_command(entry, clang)
    started = time.monotonic()
    result = subprocess.run(command, cwd=entry["directory"], capture_output=True, text=True)
    return entry["file"], result.returncode, result.stderr, time.monotonic() - started


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--all", action="store_true")
    parser.add_argument("only", nargs="*")
    options = parser.parse_args()

    clang = shutil.which("clang++")
    if clang is None:
        sys.exit("check_thread_safety: clang++ not found (deploy/install-deps.sh installs it)")
    database = os.path.join(options.build, "compile_commands.json")
    if not os.path.exists(database):
        sys.exit(f"check_thread_safety: no {database}: configure and build the release preset "
                 "first (cmake --preset release && cmake --build --preset release)")
    generated = os.path.join(options.build, "proto", "ispq", "v1", "service.grpc.pb.h")
    if not os.path.exists(generated):
        sys.exit(f"check_thread_safety: no {generated}: build the release preset first, the "
                 "TUs include its generated protobuf and gRPC headers")

    with open(database, encoding="utf-8") as f:
        entries = json.load(f)
    units = []
    skipped = 0
    memo = {}
    for entry in entries:
        path = os.path.relpath(os.path.realpath(entry["file"]), ROOT)
        if not path.startswith(CHECKED):
            continue
        if options.only and not any(part in path for part in options.only):
            continue
        if not options.all and not reaches_capability(os.path.realpath(entry["file"]), memo):
            skipped += 1
            continue
        units.append(entry)
    if not units:
        sys.exit("check_thread_safety: no translation unit to check")

    started = time.monotonic()
    cpu_started = os.times()
    diagnostics = []  # in first-seen order; a header's are reported once for all its TUs
    seen = set()
    failed = []
    slowest = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=options.jobs) as pool:
        for file, code, stderr, seconds in pool.map(lambda e: check(e, clang), units):
            slowest.append((seconds, file))
            relative = os.path.relpath(file, ROOT)
            has_diagnostic = False
            block = []
            for line in stderr.splitlines():
                # A diagnostic starts a block; notes and source excerpts belong to it.
                if re.match(r"^\S.*:\d+:\d+: (warning|error): ", line):
                    if block:
                        key = block[0]
                        if key not in seen:
                            seen.add(key)
                            diagnostics.append("\n".join(block))
                    block = [line.replace(ROOT + "/", "")]
                    has_diagnostic = True
                elif block and not re.match(r"^\d+ (warning|error)s? generated\.$", line):
                    block.append(line.replace(ROOT + "/", ""))
            if block and block[0] not in seen:
                seen.add(block[0])
                diagnostics.append("\n".join(block))
            if code != 0 and not has_diagnostic:
                failed.append((relative, stderr))
    wall = time.monotonic() - started
    cpu_ended = os.times()
    cpu = (cpu_ended.children_user - cpu_started.children_user +
           cpu_ended.children_system - cpu_started.children_system)

    for text in diagnostics:
        print(text)
    for relative, stderr in failed:
        print(f"check_thread_safety: clang could not check {relative}:\n{stderr}")
    slowest.sort(reverse=True)
    print(f"check_thread_safety: {len(units)} translation units checked ({skipped} skipped: no "
          f"lock or annotation in reach), {len(diagnostics)} "
          f"diagnostics, {len(failed)} not checked; {wall:.0f} s wall, {cpu:.0f} s CPU "
          f"(slowest: {os.path.relpath(slowest[0][1], ROOT)}, {slowest[0][0]:.1f} s)")
    return 1 if diagnostics or failed else 0


if __name__ == "__main__":
    sys.exit(main())
