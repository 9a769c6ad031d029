# SPDX-License-Identifier: Apache-2.0
"""Client: every call of the ispq.v1.Quantizer service, over one gRPC channel.

Meshes are given as an ispq.v1.TMesh, a path to a T-mesh file, or a stored mesh (the Mesh that
create_mesh returned, or its name "meshes/{id}"); jobs as a Job or its name "jobs/{id}". The
channel retries the idempotent calls on UNAVAILABLE as the C++ client does (gRPC's retry policy);
submit() sends a request_id so that a retried submission returns the same job (AIP-155), and
watch() resumes an interrupted stream from the last event it saw."""
import json
import os
import time
import uuid
from typing import Callable, Iterator, Optional, Union

import grpc
from google.protobuf import duration_pb2

from ispq.batch import run_batch
from ispq.errors import IspqError
from ispq.progress import Progress
from ispq.results import QuantizeResult
from ispq.tmesh_files import is_binary_tmesh_path, load_tmesh
from ispq.v1 import quantization_pb2, service_pb2, service_pb2_grpc, tmesh_pb2

MeshSource = Union[tmesh_pb2.TMesh, service_pb2.Mesh, str, "os.PathLike[str]"]
JobRef = Union[service_pb2.Job, str]
ProgressCallback = Callable[[Progress], None]

# The C++ client's bound on one answer (client/server_connection.cc).
MAX_RECEIVE_MESSAGE_BYTES = 256 << 20
# Meshes larger than this (gRPC's default message limit) are uploaded in chunks (UploadMesh)
# before the job is sent, as the C++ client does.
UPLOAD_ABOVE_BYTES = 4 << 20
UPLOAD_CHUNK_BYTES = 1 << 20
# WatchJob is resumed by watch() itself: under the channel's retry policy, a server-streaming call
# was seen to hang after a server restart (client/server_connection.cc).
_RETRIED_METHODS = ["GetJob", "ListJobs", "CancelJob", "GetMesh", "GetServerStats"]
_METHODS = {"isp": quantization_pb2.METHOD_ISP, "exact": quantization_pb2.METHOD_EXACT}


def _service_config(lb_policy: Optional[str]) -> str:
    config = {"methodConfig": [{
        "name": [{"service": "ispq.v1.Quantizer", "method": m} for m in _RETRIED_METHODS],
        "retryPolicy": {"maxAttempts": 4, "initialBackoff": "0.1s", "maxBackoff": "2s",
                        "backoffMultiplier": 2, "retryableStatusCodes": ["UNAVAILABLE"]}}]}
    if lb_policy:
        if lb_policy not in ("round_robin", "pick_first"):
            raise ValueError(f'load-balancing policy "{lb_policy}" is not one of round_robin, '
                             "pick_first")
        config["loadBalancingConfig"] = [{lb_policy: {}}]
    return json.dumps(config)


def _list_authority(target: str) -> str:
    """The first address of an address list (ipv4:A,B or ipv6:A,B), else "". gRPC would take the
    whole list as the channel's authority, the name TLS checks the server's certificate against,
    and refuse every server ("Peer name A,B is not in peer certificate"), as the C++ client did
    (client/server_connection.h, ChannelAuthority)."""
    for scheme in ("ipv4:", "ipv6:"):
        if target.startswith(scheme):
            addresses = target[len(scheme):]
            if addresses.startswith("//"):
                addresses = addresses[2:]
            return addresses.split(",")[0] if "," in addresses else ""
    return ""


def _read(path: Optional[str]) -> Optional[bytes]:
    if path is None:
        return None
    with open(path, "rb") as f:
        return f.read()


def _seconds(value: Optional[float]) -> Optional[duration_pb2.Duration]:
    if value is None:
        return None
    duration = duration_pb2.Duration()
    duration.FromNanoseconds(int(round(value * 1e9)))
    return duration


def _name(ref: Union[JobRef, service_pb2.Mesh]) -> str:
    return ref if isinstance(ref, str) else ref.name


class Client:
    """A connection to an ispq server. Thread-safe; close() (or `with`) releases the channel.

    target: HOST:PORT or any gRPC target URI (dns:///..., ipv4:a:1,b:2).
    token: sent as `authorization: Bearer <token>` on every call.
    tls: True for TLS verified by the system's roots; ca_file for your own roots; cert_file and
    key_file for mutual TLS (any of them turns TLS on)."""

    def __init__(self, target: str = "127.0.0.1:50051", *, token: Optional[str] = None,
                 tls: bool = False, ca_file: Optional[str] = None,
                 cert_file: Optional[str] = None, key_file: Optional[str] = None,
                 lb_policy: Optional[str] = None, upload_above_bytes: int = UPLOAD_ABOVE_BYTES):
        if (cert_file is None) != (key_file is None):
            raise ValueError("cert_file and key_file go together (mutual TLS)")
        options = [("grpc.max_receive_message_length", MAX_RECEIVE_MESSAGE_BYTES),
                   ("grpc.max_send_message_length", -1),  # the server enforces its own limit
                   ("grpc.enable_retries", 1),
                   ("grpc.service_config", _service_config(lb_policy))]
        authority = _list_authority(target)
        if authority:
            options.append(("grpc.default_authority", authority))
        if tls or ca_file or cert_file:
            credentials = grpc.ssl_channel_credentials(_read(ca_file), _read(key_file),
                                                       _read(cert_file))
            self._channel = grpc.secure_channel(target, credentials, options)
        else:
            self._channel = grpc.insecure_channel(target, options)
        self._metadata = (("authorization", f"Bearer {token}"),) if token else ()
        self._stub = service_pb2_grpc.QuantizerStub(self._channel)
        self._upload_above_bytes = upload_above_bytes

    @property
    def upload_above_bytes(self) -> int:
        """Meshes larger than this are uploaded in chunks before their job is sent."""
        return self._upload_above_bytes

    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ---- jobs ----

    def quantize(self, mesh: MeshSource, *, level: Optional[int] = None,
                 scaling: Optional[float] = None, target_hexes: Optional[int] = None,
                 method: str = "isp", time_limit: Optional[float] = None,
                 lower_bound: Optional[bool] = None,
                 on_progress: Optional[ProgressCallback] = None,
                 progress_interval: Optional[float] = None,
                 intermediate_interval: Optional[float] = None,
                 timeout: Optional[float] = None) -> QuantizeResult:
        """Runs a job to its end in one call (Quantize) and returns its result. The job belongs to
        the call: an exception in on_progress, a KeyboardInterrupt or `timeout` (seconds) cancels
        it. Scaling: at most one of level (percent: 0, 1, 5, 10, 17, 25, 50, 100), scaling (the
        factor s) and target_hexes. time_limit in seconds. A mesh larger than upload_above_bytes
        is uploaded first (and deleted after). IspqError when the server refuses the request or
        the job fails."""
        request = self._request(level, scaling, target_hexes, method, time_limit, lower_bound,
                                progress_interval, intermediate_interval)
        uploaded = self._attach_mesh(request, mesh)
        try:
            events = self._stub.Quantize(request, metadata=self._metadata, timeout=timeout)
            return self._follow(events, on_progress)
        except grpc.RpcError as error:
            raise IspqError.from_rpc_error(error) from None
        finally:
            if uploaded:
                try:
                    self.delete_mesh(uploaded)  # the job is over
                except IspqError:
                    pass  # the server evicts it when it needs room

    def submit(self, mesh: MeshSource, *, level: Optional[int] = None,
               scaling: Optional[float] = None, target_hexes: Optional[int] = None,
               method: str = "isp", time_limit: Optional[float] = None,
               lower_bound: Optional[bool] = None, request_id: Optional[str] = None,
               progress_interval: Optional[float] = None,
               intermediate_interval: Optional[float] = None,
               retries: int = 3) -> service_pb2.Job:
        """Accepts a job that runs whether or not anyone watches it (SubmitJob); returns it QUEUED.
        A request_id (a fresh UUID unless given) makes the call safe to retry: on UNAVAILABLE it
        is sent again up to `retries` times and the server returns the job it already made. A mesh
        larger than upload_above_bytes is uploaded first and stays stored for the job."""
        request = self._request(level, scaling, target_hexes, method, time_limit, lower_bound,
                                progress_interval, intermediate_interval)
        self._attach_mesh(request, mesh)
        request.request_id = request_id or str(uuid.uuid4())
        return self._with_retries(lambda: self._stub.SubmitJob(request, metadata=self._metadata),
                                  retries)

    def watch(self, job: JobRef, *, on_progress: Optional[ProgressCallback] = None,
              from_event: int = 0, retries: int = 3) -> QuantizeResult:
        """Follows a job to its end (WatchJob) and returns its result; resumes after the last event
        seen when the stream breaks with UNAVAILABLE (a replica or the server going away), up to
        `retries` times in a row. Cancelling a watch does not cancel the job. IspqError when the
        job ends with an error (its code and message) or the server refuses the watch."""
        name = _name(job)
        seen = [from_event - 1]

        def track(progress_event_sequence: int) -> None:
            seen[0] = max(seen[0], progress_event_sequence)

        failures = 0
        while True:
            request = service_pb2.WatchJobRequest(name=name, from_event=seen[0] + 1)
            try:
                events = self._stub.WatchJob(request, metadata=self._metadata)
                return self._follow(events, on_progress, track)
            except grpc.RpcError as error:
                if error.code() != grpc.StatusCode.UNAVAILABLE or failures >= retries:
                    raise IspqError.from_rpc_error(error) from None
                failures += 1
                time.sleep(min(2.0, 0.1 * 2 ** failures))

    def batch(self, inputs, out_dir: str, **kwargs):
        """Many meshes and levels, `concurrency` jobs at a time, riding out restarts; one result
        file per job and OUT/summary.tsv. See ispq.batch.run_batch for the arguments; returns its
        BatchEntry list (check `entry.ok`)."""
        return run_batch(self, inputs, out_dir, **kwargs)

    def get(self, job: JobRef, *, full: bool = True) -> service_pb2.Job:
        """The job now (GetJob); full=False leaves out the result's q and stats."""
        view = service_pb2.FULL if full else service_pb2.BASIC
        return self._call(self._stub.GetJob, service_pb2.GetJobRequest(name=_name(job), view=view))

    def jobs(self, *, state: Optional[str] = None, full: bool = False,
             page_size: int = 0) -> Iterator[service_pb2.Job]:
        """Every job this principal may see, newest first (ListJobs, page after page); state:
        QUEUED, RUNNING, SUCCEEDED, FAILED or CANCELLED to keep only those."""
        request = service_pb2.ListJobsRequest(
            page_size=page_size, view=service_pb2.FULL if full else service_pb2.BASIC,
            state=service_pb2.JobState.Value(state) if state else service_pb2.JOB_STATE_UNSPECIFIED)
        while True:
            page = self._call(self._stub.ListJobs, request)
            yield from page.jobs
            if not page.next_page_token:
                return
            request.page_token = page.next_page_token

    def cancel(self, job: JobRef) -> service_pb2.Job:
        """Interrupts a running job (its result is the best valid q so far) or drops a queued one;
        the job as it is after the request (CancelJob)."""
        return self._call(self._stub.CancelJob, service_pb2.CancelJobRequest(name=_name(job)))

    # ---- stored meshes ----

    def create_mesh(self, mesh: Union[tmesh_pb2.TMesh, str, "os.PathLike[str]"]) -> service_pb2.Mesh:
        """Validates and stores a mesh for repeated runs; pass the Mesh (or its name) as `mesh` to
        quantize or submit (CreateMesh)."""
        tmesh = mesh if isinstance(mesh, tmesh_pb2.TMesh) else load_tmesh(mesh)
        return self._call(self._stub.CreateMesh, service_pb2.CreateMeshRequest(mesh=tmesh))

    def upload_mesh(self, mesh: Union[tmesh_pb2.TMesh, str, "os.PathLike[str]"], *,
                    chunk_bytes: int = UPLOAD_CHUNK_BYTES) -> service_pb2.Mesh:
        """create_mesh for a mesh of any size: its binary form streamed in chunks (UploadMesh), so
        that no message exceeds the server's limit. quantize and submit do this by themselves for
        meshes above upload_above_bytes."""
        if not isinstance(mesh, tmesh_pb2.TMesh) and is_binary_tmesh_path(mesh):
            return self._upload_file(os.fspath(mesh), chunk_bytes)
        tmesh = mesh if isinstance(mesh, tmesh_pb2.TMesh) else load_tmesh(mesh)
        data = tmesh.SerializeToString()

        def chunks():
            yield service_pb2.UploadMeshRequest(total_bytes=len(data),
                                                chunk=data[:chunk_bytes])
            for offset in range(chunk_bytes, len(data), chunk_bytes):
                yield service_pb2.UploadMeshRequest(chunk=data[offset:offset + chunk_bytes])

        return self._call(self._stub.UploadMesh, chunks())

    def _upload_file(self, path: str, chunk_bytes: int) -> service_pb2.Mesh:
        """A binary T-mesh file streamed from disk as it is, one chunk in memory at a time: a
        million-arc part is never parsed here (3.2 GB of Python objects for a 264 MB file); the
        server parses and validates it, and its refusal is raised naming the file."""
        size = os.path.getsize(path)

        def chunks():
            with open(path, "rb") as f:
                yield service_pb2.UploadMeshRequest(total_bytes=size, chunk=f.read(chunk_bytes))
                while data := f.read(chunk_bytes):
                    yield service_pb2.UploadMeshRequest(chunk=data)

        try:
            return self._call(self._stub.UploadMesh, chunks())
        except IspqError as error:
            raise IspqError(error.code, f"{path}: {error.message}",
                            retry_after=error.retry_after) from None

    def get_mesh(self, mesh: Union[service_pb2.Mesh, str]) -> service_pb2.Mesh:
        return self._call(self._stub.GetMesh, service_pb2.GetMeshRequest(name=_name(mesh)))

    def delete_mesh(self, mesh: Union[service_pb2.Mesh, str]) -> None:
        self._call(self._stub.DeleteMesh, service_pb2.DeleteMeshRequest(name=_name(mesh)))

    def server_stats(self) -> service_pb2.ServerStats:
        """Jobs by state, queue, workers, memory and solve-time histograms (GetServerStats)."""
        return self._call(self._stub.GetServerStats, service_pb2.GetServerStatsRequest())

    # ---- internals ----

    def _call(self, method, request):
        try:
            return method(request, metadata=self._metadata)
        except grpc.RpcError as error:
            raise IspqError.from_rpc_error(error) from None

    def _attach_mesh(self, request: service_pb2.QuantizeRequest, mesh: MeshSource) -> str:
        """Makes the request carry the mesh: inline, or by name when it is stored or when it is
        larger than upload_above_bytes (then uploaded first; a binary file straight from disk).
        Returns the uploaded mesh's name, or "" when nothing was uploaded."""
        if isinstance(mesh, service_pb2.Mesh):
            request.stored_mesh = mesh.name
            return ""
        if isinstance(mesh, str) and mesh.startswith("meshes/") and not os.path.exists(mesh):
            request.stored_mesh = mesh
            return ""
        large_file = (not isinstance(mesh, tmesh_pb2.TMesh) and is_binary_tmesh_path(mesh) and
                      os.path.getsize(mesh) > self._upload_above_bytes)
        if not large_file:
            tmesh = mesh if isinstance(mesh, tmesh_pb2.TMesh) else load_tmesh(mesh)
            if tmesh.ByteSize() <= self._upload_above_bytes:
                request.mesh.CopyFrom(tmesh)
                return ""
            mesh = tmesh
        stored = self.upload_mesh(mesh)
        request.stored_mesh = stored.name
        return stored.name

    def _with_retries(self, call, retries: int):
        for attempt in range(retries + 1):
            try:
                return call()
            except grpc.RpcError as error:
                if error.code() != grpc.StatusCode.UNAVAILABLE or attempt == retries:
                    raise IspqError.from_rpc_error(error) from None
                time.sleep(min(2.0, 0.1 * 2 ** (attempt + 1)))

    @staticmethod
    def _request(level, scaling, target_hexes, method, time_limit, lower_bound,
                 progress_interval, intermediate_interval) -> service_pb2.QuantizeRequest:
        """The request's options (its mesh is _attach_mesh's)."""
        request = service_pb2.QuantizeRequest()
        choices = [c for c in (level, scaling, target_hexes) if c is not None]
        if len(choices) > 1:
            raise ValueError("give at most one of level, scaling and target_hexes")
        if level is not None:
            request.options.scaling.level_percent = level
        elif scaling is not None:
            request.options.scaling.factor = scaling
        elif target_hexes is not None:
            request.options.scaling.target_hexes = target_hexes
        if method not in _METHODS:
            raise ValueError(f'method "{method}" is not one of {", ".join(_METHODS)}')
        request.options.method = _METHODS[method]
        if time_limit is not None:
            request.options.time_limit.CopyFrom(_seconds(time_limit))
        if lower_bound is not None:
            request.options.lower_bound = lower_bound
        if progress_interval is not None:
            request.progress_interval.CopyFrom(_seconds(progress_interval))
        if intermediate_interval is not None:
            request.intermediate_interval.CopyFrom(_seconds(intermediate_interval))
        return request

    @staticmethod
    def _follow(events, on_progress: Optional[ProgressCallback],
                on_event: Optional[Callable[[int], None]] = None) -> QuantizeResult:
        """Reads a job's event stream to its terminal event. An exception in on_progress cancels
        the stream (and with Quantize, the job)."""
        try:
            for event in events:
                if on_event is not None:
                    on_event(event.sequence)
                kind = event.WhichOneof("kind")
                if kind == "result":
                    return QuantizeResult.from_proto(event.job, event.result)
                if kind == "error":
                    raise IspqError.from_job_error(event.job, event.error.code,
                                                   event.error.message)
                progress = Progress.from_event(event)
                if progress is not None and on_progress is not None:
                    on_progress(progress)
        except BaseException:
            events.cancel()
            raise
        raise IspqError(grpc.StatusCode.UNKNOWN, "the event stream ended without a result")
