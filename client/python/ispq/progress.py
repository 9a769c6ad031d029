# SPDX-License-Identifier: Apache-2.0
"""Progress: what an on_progress callback receives while a job runs (a progress event, or an
intermediate quantization with its q)."""
from dataclasses import dataclass
from typing import List, Optional

from ispq.v1 import quantization_pb2, service_pb2


@dataclass(frozen=True)
class Progress:
    job: str                # "jobs/{id}"
    phase: str              # LAYERS, GREEDY, SEPARATION, FAILSAFE, FINAL or EXACT
    objective: float
    separating: bool        # the current q separates every critical entity
    violated_constraints: int
    lp_solves: int
    elapsed_seconds: float
    lower_bound: Optional[float] = None  # exact mode: the bound proven so far
    q: Optional[List[int]] = None        # an intermediate quantization (requested with
                                         # intermediate_interval), per arc

    @classmethod
    def from_event(cls, event: service_pb2.QuantizeEvent) -> Optional["Progress"]:
        """The progress of a progress or intermediate event; None for any other event."""
        kind = event.WhichOneof("kind")
        if kind == "progress":
            progress, q = event.progress, None
        elif kind == "intermediate":
            progress, q = event.intermediate.progress, list(event.intermediate.q)
        else:
            return None
        return cls(job=event.job, phase=quantization_pb2.Phase.Name(progress.phase),
                   objective=progress.objective, separating=progress.separating,
                   violated_constraints=progress.violated_constraints,
                   lp_solves=progress.lp_solves, elapsed_seconds=progress.elapsed_seconds,
                   lower_bound=progress.lower_bound if progress.HasField("lower_bound") else None,
                   q=q)
