# SPDX-License-Identifier: Apache-2.0
"""IspqError: what a failed call or job raises, with the gRPC status code and the server's message
(which names the offending element of a refused mesh or option)."""
from typing import Optional

import grpc


class IspqError(Exception):
    """A call the server refused or a job that ended with an error.

    `code` is a grpc.StatusCode (INVALID_ARGUMENT: the request is wrong and will stay wrong;
    RESOURCE_EXHAUSTED and UNAVAILABLE: the same call may succeed later, after `retry_after`
    seconds when the server said so); `message` is the server's text; `job` the job's name when
    the error belongs to a job that ran."""

    def __init__(self, code: grpc.StatusCode, message: str, *, job: str = "",
                 retry_after: Optional[float] = None):
        super().__init__(f"{code.name}: {message}" + (f" ({job})" if job else ""))
        self.code = code
        self.message = message
        self.job = job
        self.retry_after = retry_after

    @classmethod
    def from_rpc_error(cls, error: grpc.RpcError) -> "IspqError":
        """The error of a failed call, with the server's retry hint (grpc-retry-pushback-ms)."""
        retry_after = None
        trailers = error.trailing_metadata() if hasattr(error, "trailing_metadata") else None
        for key, value in trailers or ():
            if key == "grpc-retry-pushback-ms":
                try:
                    retry_after = int(value) / 1000.0
                except ValueError:
                    pass
        return cls(error.code(), error.details() or "", retry_after=retry_after)

    @classmethod
    def from_job_error(cls, job: str, code: int, message: str) -> "IspqError":
        """The error event of a job (a google.rpc.Code value)."""
        status = next((c for c in grpc.StatusCode if c.value[0] == code), grpc.StatusCode.UNKNOWN)
        return cls(status, message, job=job)
