# SPDX-License-Identifier: Apache-2.0
"""QuantizeResult: the answer of a job, with its integer arc lengths and the validator's verdict."""
from dataclasses import dataclass
from typing import List, Optional

from google.protobuf import json_format

from ispq.v1 import quantization_pb2


@dataclass(frozen=True)
class QuantizeResult:
    job: str                 # "jobs/{id}"
    q: List[int]             # integer length per arc, in the mesh's arc order
    objective: float         # sum over arcs of (q - s * length)^2
    valid: bool              # consistent, non-negative and separating per the server's validator
    termination: str         # CONVERGED, TIME_LIMIT, INTERRUPTED or OPTIMAL
    scaling: float           # the s used
    hexes: int
    lower_bound: Optional[float]
    gap: Optional[float]     # (objective - lower_bound) / objective
    stats: quantization_pb2.QuantizationStats
    proto: quantization_pb2.QuantizationResult  # everything, as the server sent it

    @classmethod
    def from_proto(cls, job: str, result: quantization_pb2.QuantizationResult) -> "QuantizeResult":
        return cls(job=job, q=list(result.q), objective=result.objective, valid=result.valid,
                   termination=quantization_pb2.Termination.Name(result.termination),
                   scaling=result.scaling, hexes=result.hexes,
                   lower_bound=result.lower_bound if result.HasField("lower_bound") else None,
                   gap=result.gap if result.HasField("gap") else None, stats=result.stats,
                   proto=result)

    def to_json(self) -> str:
        """The result file's JSON, as `ispq quantize --out` writes it (`ispq validate` reads it)."""
        return json_format.MessageToJson(self.proto, including_default_value_fields=True) + "\n"
