# SPDX-License-Identifier: Apache-2.0
"""Generates ispq.v1 (the messages and gRPC stubs of ../../proto) when the package is built, so
that the package never carries a stale copy of the schema. The metadata is in pyproject.toml."""
import os
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
PROTO_ROOT = os.environ.get("ISPQ_PROTO_DIR", os.path.join(HERE, "..", "..", "proto"))
PROTOS = ["tmesh.proto", "mesh_stats.proto", "quantization.proto", "service.proto"]


def generate_stubs(out_dir):
    """protoc + grpc_python_plugin into out_dir/ispq/v1/."""
    plugin = shutil.which("grpc_python_plugin")
    if plugin is None or shutil.which("protoc") is None:
        raise RuntimeError("protoc and grpc_python_plugin are needed to build the ispq package "
                           "(Debian: apt install protobuf-compiler protobuf-compiler-grpc)")
    sources = [os.path.join(PROTO_ROOT, "ispq", "v1", name) for name in PROTOS]
    subprocess.run(["protoc", f"-I{PROTO_ROOT}", f"--python_out={out_dir}",
                    f"--grpc_python_out={out_dir}", f"--plugin=protoc-gen-grpc_python={plugin}",
                    *sources], check=True)
    open(os.path.join(out_dir, "ispq", "v1", "__init__.py"), "a").close()


class BuildWithStubs(build_py):
    def run(self):
        super().run()
        os.makedirs(os.path.join(self.build_lib, "ispq", "v1"), exist_ok=True)
        generate_stubs(self.build_lib)


setup(cmdclass={"build_py": BuildWithStubs})
