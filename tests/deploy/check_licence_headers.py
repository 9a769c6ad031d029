#!/usr/bin/env python3
"""Every source file of the repository says its licence in its first lines:
`SPDX-License-Identifier: Apache-2.0` (see LICENSE; NOTICE covers the bundled data).

Source files are the tracked C++, protobuf, Python, shell, CMake, YAML, JavaScript, CSS and HTML
files, plus .ci/run and deploy/Dockerfile. Data (tests/data, benchmark results), JSON and
Markdown carry no header. The licence line may follow a shebang, an HTML doctype, or a YAML
document marker.

  check_licence_headers.py           report files without the line; exit 1 if any
  check_licence_headers.py --add     add the line where it is missing (in the file's comment style)
"""
import os
import subprocess
import sys

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
IDENTIFIER = "SPDX-License-Identifier: Apache-2.0"
SLASHES = (".cc", ".h", ".proto", ".js", ".css")
HASHES = (".py", ".sh", ".cmake", ".yaml", ".yml")
HASH_FILES = ("CMakeLists.txt", ".ci/run", "deploy/Dockerfile")
EXEMPT_PREFIXES = ("tests/data/", "tests/bench/large/results/")
# A first line that must stay first.
KEEP_FIRST = ("#!", "<!doctype", "<!DOCTYPE", "---")


def comment(path):
    if path.endswith(SLASHES):
        return f"// {IDENTIFIER}\n"
    if path.endswith(HASHES) or path.endswith(HASH_FILES):
        return f"# {IDENTIFIER}\n"
    if path.endswith(".html"):
        return f"<!-- {IDENTIFIER} -->\n"
    return None


def source_files():
    listed = subprocess.run(["git", "-C", ROOT, "ls-files", "-z"], check=True,
                            capture_output=True).stdout.decode().split("\0")
    for path in listed:
        if path and not path.startswith(EXEMPT_PREFIXES) and comment(path) is not None:
            yield path


def has_header(lines):
    return any(IDENTIFIER in line for line in lines[:3])


def main():
    add = "--add" in sys.argv[1:]
    missing = []
    for path in source_files():
        full = os.path.join(ROOT, path)
        with open(full, encoding="utf-8") as f:
            lines = f.readlines()
        if has_header(lines):
            continue
        missing.append(path)
        if add:
            at = 1 if lines and lines[0].startswith(KEEP_FIRST) else 0
            lines.insert(at, comment(path))
            with open(full, "w", encoding="utf-8") as f:
                f.writelines(lines)
    if missing and not add:
        print(f"check_licence_headers: {len(missing)} source files lack '{IDENTIFIER}':")
        for path in missing:
            print(f"  {path}")
        print("add it with: tests/deploy/check_licence_headers.py --add")
        return 1
    print(f"check_licence_headers: {'added to ' + str(len(missing)) if add else 'every'} "
          f"source file{'s' if add else ''} {'' if add else 'says its licence'}".rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main())
