#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The repository stands on its own: nothing in it refers to a path outside the checkout.

A clone in a folder with nothing beside it must build, test and benchmark (issue 25). That held
only by accident while a folder of shared data and tools sat beside every developer's checkout:
a reference to it (a path baked into the build, a script reading the reference results there, a
path joined from "..", ".." and the folder's name) passes every test on such a machine and fails
on anyone else's. So this check reads every file of the tree (tracked or new, not ignored) and
fails on:

  - that sibling folder, and its data, reference, tools, oracle and hooks by name;
  - absolute paths into the development machines' /work (sibling checkouts, shared data);
  - path joins that climb to that folder ("..", then its name);
  - ${PROJECT_SOURCE_DIR}/.. or ${CMAKE_SOURCE_DIR}/.., which leave the source tree;
  - a path relative to a file's own folder ($(dirname "$0"), ${CMAKE_CURRENT_SOURCE_DIR},
    os.path.dirname(__file__)) that climbs more folders than the file is deep.

Exempt: the differential harness against the upstream research code (tests/differential/), a
documented by-hand tool that needs upstream's code and MC3D-samples' .hexex files, neither of
which is in the repository; and this file, which spells the patterns. Citations of the
specification documents that used to live beside the checkout (shared/tmesh-format.md,
shared/separation.md, the paper in shared/paper) fail the check too: the specifications are
proto/README.md and core/README.md now.

Before reading the tree, every rule is run on a line it must catch and one it must let pass, so
that a rule that can no longer fire fails here rather than passing silently.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SELF = os.path.relpath(os.path.abspath(__file__), ROOT)
EXEMPT_PREFIXES = ("tests/differential/",)
# The sibling folder's name and the development machines' root, in pieces, so that this file
# does not spell the references it looks for (a plain git grep for them finds only the harness).
SIBLING = "sha" + "red"
WORK = "/wo" + "rk/"

# Citations of the old specification documents fail: proto/README.md and core/README.md replace
# them.
DOCUMENT_CITATIONS_FAIL = True

# (name, pattern, a line it must catch, a line it must let pass)
RULES = [
    ("the sibling folder", re.compile(r"\.\./" + SIBLING + r"\b"),
     f'ISPQ_DIR="${{PROJECT_SOURCE_DIR}}/../{SIBLING}/data/tmesh"',
     "see tests/data/reference/README.md"),
    ("the sibling folder's contents",
     re.compile(r"(?<![\w-])" + SIBLING + r"/(data|reference|tools|oracle|hooks)\b"),
     f"// compared with {SIBLING}/reference/qgp3d-isp.tsv", "// a shared job store"),
    ("an absolute path into the development machines' root",
     re.compile(r"(?<![\w.~-])" + WORK), f"cp {WORK}{SIBLING}/data/x.json .", "WORKDIR /src"),
    ("a path join climbing to the sibling folder",
     re.compile(r"""["']\.\.["']\s*,\s*["']""" + SIBLING + r"""["']"""),
     f'os.path.join(DATA, "..", "..", "..", "{SIBLING}", "data")',
     'os.path.join(DATA, "hex-me", NAME)'),
    ("a path above the source root", re.compile(r"\$\{(PROJECT|CMAKE)_SOURCE_DIR\}/\.\."),
     "set(DATA ${PROJECT_SOURCE_DIR}/../data)", "set(DATA ${PROJECT_SOURCE_DIR}/tests/data)"),
]
DOCUMENT_CITATION = re.compile(
    r"(?<![\w-])" + SIBLING + r"/(tmesh-format\.md|separation\.md|paper)\b")

# Paths relative to the file's own folder: group 1 holds the climbing part.
RELATIVE_TO_FILE = [
    re.compile(r"""\$\(dirname\s+["']?\$(?:0|\{BASH_SOURCE\[0\]\})["']?\)((?:/\.\.)+)"""),
    re.compile(r"\$\{CMAKE_CURRENT_(?:SOURCE|LIST)_DIR\}((?:/\.\.)+)"),
    re.compile(r"""os\.path\.dirname\((?:os\.path\.(?:abspath|realpath)\()?__file__\)?\)"""
               r"""((?:\s*,\s*["']\.\.["'])+)"""),
]


def climbs_out(relative_path, line):
    """The first path in `line` relative to the file's folder that climbs above the root."""
    depth = relative_path.count("/")  # folders between the root and the file
    for pattern in RELATIVE_TO_FILE:
        for match in pattern.finditer(line):
            if match.group(1).count("..") > depth:
                return match.group(0)
    return None


def self_test():
    failures = []
    for name, pattern, bad, good in RULES:
        if not pattern.search(bad):
            failures.append(f"rule '{name}' misses: {bad}")
        if pattern.search(good):
            failures.append(f"rule '{name}' flags: {good}")
    if not DOCUMENT_CITATION.search(f"// the rules of {SIBLING}/tmesh-format.md section 7"):
        failures.append("the document-citation rule misses a citation")
    cases = [
        ("tests/bench/report/make_report.sh", 'cd "$(dirname "$0")/../../.."', False),
        ("tests/bench/report/make_report.sh", 'cd "$(dirname "$0")/../../../..', True),
        ("tests/run.sh", 'cd "$(dirname "$0")/../.."', True),
        ("tests/deploy/CMakeLists.txt", "${CMAKE_CURRENT_SOURCE_DIR}/../../deploy", False),
        ("tests/deploy/CMakeLists.txt", "${CMAKE_CURRENT_SOURCE_DIR}/../../../data", True),
        ("tests/deploy/x.py",
         'os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")', False),
        ("tests/deploy/x.py",
         'os.path.join(os.path.dirname(__file__), "..", "..", "..", "data")', True),
    ]
    for path, line, escapes in cases:
        if (climbs_out(path, line) is not None) != escapes:
            failures.append(f"relative-path rule is wrong on {path}: {line}")
    return failures


def tree_files():
    """Tracked and new files, without what .gitignore ignores (build trees); a walk without git."""
    try:
        listed = subprocess.run(
            ["git", "-C", ROOT, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            capture_output=True, check=True, timeout=60).stdout.decode()
        return sorted(set(path for path in listed.split("\0") if path))
    except (OSError, subprocess.CalledProcessError, subprocess.TimeoutExpired):
        files = []
        for folder, dirs, names in os.walk(ROOT):
            dirs[:] = [d for d in dirs if d != ".git" and d != "out" and not d.startswith("build")]
            files += [os.path.relpath(os.path.join(folder, n), ROOT) for n in names]
        return sorted(files)


def text_of(path):
    try:
        with open(os.path.join(ROOT, path), "rb") as f:
            data = f.read()
    except OSError:  # deleted but still listed, or not a regular file
        return None
    if b"\0" in data[:8192]:
        return None  # binary: images, protobuf files
    return data.decode("utf-8", errors="replace")


def main():
    failures = self_test()
    if failures:
        print("check_standalone: the checks themselves are broken:\n  " + "\n  ".join(failures))
        return 1
    problems, citations, scanned = [], [], 0
    for path in tree_files():
        if path == SELF or path.startswith(EXEMPT_PREFIXES):
            continue
        text = text_of(path)
        if text is None:
            continue
        scanned += 1
        for number, line in enumerate(text.splitlines(), 1):
            for name, pattern, _, _ in RULES:
                if pattern.search(line):
                    problems.append(f"{path}:{number}: {name}: {line.strip()[:120]}")
            escape = climbs_out(path, line)
            if escape:
                problems.append(f"{path}:{number}: climbs above the checkout: {escape}")
            if DOCUMENT_CITATION.search(line):
                citations.append(f"{path}:{number}: {line.strip()[:120]}")
    if scanned < 100:
        problems.append(f"only {scanned} files read under {ROOT}: is this the repository?")
    if citations:
        verdict = "fail" if DOCUMENT_CITATIONS_FAIL else "are reported only, until issue 25 lands"
        print(f"{len(citations)} citations of documents outside the checkout ({verdict}):")
        print("  " + "\n  ".join(citations[:20]) + ("\n  ..." if len(citations) > 20 else ""))
        if DOCUMENT_CITATIONS_FAIL:
            problems += citations
    if problems:
        print(f"{len(problems)} references outside the checkout:\n  " + "\n  ".join(problems))
        return 1
    print(f"check_standalone: {scanned} files, nothing refers outside the checkout")
    return 0


if __name__ == "__main__":
    sys.exit(main())
