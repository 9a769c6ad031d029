# SPDX-License-Identifier: Apache-2.0
"""load_tmesh: a T-mesh file (.tmesh.json, or binary .tmesh.pb / .binpb; proto/README.md) as an ispq.v1.TMesh."""
import os
from typing import Union

from google.protobuf import json_format

from ispq.v1 import tmesh_pb2

PathLike = Union[str, "os.PathLike[str]"]


def is_binary_tmesh_path(path) -> bool:
    """Whether `path` names a binary T-mesh file (.tmesh.pb, .binpb): one that can be sent as it
    is, without parsing it here."""
    return isinstance(path, (str, os.PathLike)) and os.fspath(path).endswith((".pb", ".binpb"))


def load_tmesh(path: PathLike) -> tmesh_pb2.TMesh:
    """Reads a T-mesh file; ValueError naming the file when it is not one. The server validates
    the mesh itself (and names the offending element) when it is sent."""
    path = os.fspath(path)
    mesh = tmesh_pb2.TMesh()
    if path.endswith((".pb", ".binpb")):
        with open(path, "rb") as f:
            data = f.read()
        try:
            mesh.ParseFromString(data)
        except Exception as error:  # DecodeError, or RuntimeWarning-like errors of the C++ parser
            raise ValueError(f"{path}: not a binary T-mesh: {error}") from error
    elif path.endswith(".json"):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        try:
            json_format.Parse(text, mesh)
        except json_format.ParseError as error:
            raise ValueError(f"{path}: not a T-mesh JSON file: {error}") from error
    else:
        raise ValueError(f"{path}: a T-mesh file ends with .tmesh.json or .tmesh.pb")
    return mesh
