# SPDX-License-Identifier: Apache-2.0
"""run_batch: many meshes (and levels) through a server with bounded concurrency, as `ispq batch`.

Directories are searched recursively for .tmesh.json/.tmesh.pb/.tmesh.binpb files; each mesh is
run at each level (or at the one scaling given) and its valid result written to
OUT/<path relative to the input>.L<level>.result.json (the same file `ispq batch` writes, and the
same JSON as `ispq quantize --out`). A valid result file already there is kept and its job not run
again, so an interrupted batch resumes by running it again. Each job is submitted with a request
id derived from its request and result file, and followed to its end; a broken or refused call is
retried with backoff until `patience` seconds pass without an answer, and a job the server no
longer knows (a restart without a shared store) is submitted again under the same id. OUT/summary.tsv
lists every job."""
import concurrent.futures
import hashlib
import os
import threading
import time
from dataclasses import dataclass
from typing import Callable, List, Optional, Sequence

import grpc
from google.protobuf import json_format

from ispq.errors import IspqError
from ispq.results import QuantizeResult
from ispq.tmesh_files import load_tmesh
from ispq.v1 import quantization_pb2

MESH_EXTENSIONS = (".tmesh.json", ".tmesh.pb", ".tmesh.binpb")
# Codes after which the same call may work later: the server is away, restarting or full.
_MAY_WORK_LATER = {grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.RESOURCE_EXHAUSTED,
                   grpc.StatusCode.DEADLINE_EXCEEDED, grpc.StatusCode.ABORTED,
                   grpc.StatusCode.INTERNAL, grpc.StatusCode.UNKNOWN}


@dataclass
class BatchEntry:
    """One job of a batch and how it ended."""
    name: str                  # "hex-me/s07c_notch L25"
    mesh_path: str
    scaling: dict              # the keyword given to submit: {"level": 25}, {"scaling": 2.0}, ...
    result_path: str
    result: Optional[QuantizeResult] = None  # a valid result (also one kept from an earlier run)
    kept: bool = False         # the result file was there already
    job: str = ""              # "jobs/{id}" on the server that ran it
    error: Optional[Exception] = None

    @property
    def ok(self) -> bool:
        return self.error is None and self.result is not None and self.result.valid


def _find_meshes(inputs: Sequence[str]):
    found = []
    for given in inputs:
        given = os.fspath(given)
        if os.path.isdir(given):
            before = len(found)
            for root, _, files in os.walk(given):
                for file in files:
                    if file.endswith(MESH_EXTENSIONS):
                        path = os.path.join(root, file)
                        found.append((path, _stem(os.path.relpath(path, given))))
            if len(found) == before:
                raise ValueError(f"{given}: no T-mesh files in it ({', '.join(MESH_EXTENSIONS)})")
        elif os.path.isfile(given) and given.endswith(MESH_EXTENSIONS):
            found.append((given, _stem(os.path.basename(given))))
        else:
            raise ValueError(f"{given}: not a T-mesh file ({', '.join(MESH_EXTENSIONS)}) or a "
                             "directory")
    return sorted(found, key=lambda mesh: mesh[1])


def _stem(relative: str) -> str:
    relative = relative.replace(os.sep, "/")
    for extension in MESH_EXTENSIONS:
        if relative.endswith(extension):
            return relative[:-len(extension)]
    return relative


def _label(scaling: dict) -> str:
    if "level" in scaling:
        return f"L{scaling['level']}"
    if "scaling" in scaling:
        return f"s{scaling['scaling']:g}"
    if "target_hexes" in scaling:
        return f"h{scaling['target_hexes']}"
    return "default"


def _kept_result(path: str) -> Optional[QuantizeResult]:
    try:
        with open(path, encoding="utf-8") as f:
            proto = json_format.Parse(f.read(), quantization_pb2.QuantizationResult())
    except (OSError, json_format.ParseError):
        return None
    return QuantizeResult.from_proto("", proto) if proto.valid else None


def plan_batch(inputs: Sequence[str], out_dir: str, *, levels: Optional[Sequence[int]] = None,
               scaling: Optional[float] = None,
               target_hexes: Optional[int] = None) -> List[BatchEntry]:
    """The jobs of a batch, by mesh name and then level; ValueError naming a bad input."""
    if levels is not None and (scaling is not None or target_hexes is not None):
        raise ValueError("give levels, or one scaling or target_hexes, not both")
    variants = ([{"level": level} for level in levels] if levels is not None else
                [{"scaling": scaling}] if scaling is not None else
                [{"target_hexes": target_hexes}] if target_hexes is not None else [{}])
    entries, seen = [], set()
    for path, stem in _find_meshes(inputs):
        for variant in variants:
            label = _label(variant)
            result_path = os.path.join(out_dir, f"{stem}.{label}.result.json")
            if result_path in seen:
                raise ValueError(f"{path}: another input has the same name ({stem}): both would "
                                 f"write {result_path}")
            seen.add(result_path)
            entries.append(BatchEntry(f"{stem} {label}", path, variant, result_path))
    return entries


def run_batch(client, inputs: Sequence[str], out_dir: str, *,
              levels: Optional[Sequence[int]] = None, scaling: Optional[float] = None,
              target_hexes: Optional[int] = None, concurrency: int = 4, patience: float = 600,
              on_job_end: Optional[Callable[[BatchEntry], None]] = None,
              **options) -> List[BatchEntry]:
    """Runs every job of plan_batch(...) on `client`'s server, `concurrency` at a time, and returns
    the entries (check `entry.ok`); `options` go to Client.submit (method, time_limit, ...).
    on_job_end is called (from a worker thread) as each job ends."""
    if concurrency < 1:
        raise ValueError("concurrency must be at least 1")
    entries = plan_batch(inputs, out_dir, levels=levels, scaling=scaling,
                         target_hexes=target_hexes)
    os.makedirs(out_dir, exist_ok=True)
    report = threading.Lock()

    def run(entry: BatchEntry) -> None:
        try:
            _run_one(client, entry, patience, options)
        except Exception as error:  # noqa: BLE001: one job's failure must not stop the batch
            entry.error = error
        if on_job_end is not None:
            with report:
                on_job_end(entry)

    with concurrent.futures.ThreadPoolExecutor(max_workers=concurrency) as pool:
        list(pool.map(run, entries))
    _write_summary(os.path.join(out_dir, "summary.tsv"), entries)
    return entries


def _run_one(client, entry: BatchEntry, patience: float, options: dict) -> None:
    kept = _kept_result(entry.result_path)
    if kept is not None:
        entry.result, entry.kept = kept, True
        return
    mesh = load_tmesh(entry.mesh_path)
    request_key = hashlib.sha256(mesh.SerializeToString() + repr(
        (sorted(entry.scaling.items()), sorted(options.items()),
         os.path.abspath(entry.result_path))).encode()).hexdigest()[:40]
    request_id = f"batch-{request_key}"
    # A large mesh is uploaded once and its jobs sent by name, so that every submission of the
    # job is the same request (its request id would be refused for a different one).
    large = mesh.ByteSize() > client.upload_above_bytes
    stored = ""
    last_answer, backoff = time.monotonic(), 0.1
    try:
        while True:
            try:
                if not entry.job:
                    if large and not stored:
                        stored = client.upload_mesh(mesh).name
                    entry.job = client.submit(stored or mesh, request_id=request_id, retries=0,
                                              **entry.scaling, **options).name
                # A job keeps only its accepted, latest progress and terminal events: watching
                # again from the start after a broken stream costs next to nothing.
                entry.result = client.watch(entry.job)
                break
            except IspqError as error:
                if error.job:  # the job itself ended with an error: final
                    raise
                if error.code == grpc.StatusCode.NOT_FOUND and (entry.job or stored):
                    # The server lost the job, or the uploaded mesh before the job was made:
                    # send it again (the job under the same request id).
                    if entry.job:
                        entry.job = ""
                    else:
                        stored = ""
                    last_answer = time.monotonic()
                    continue
                if error.code not in _MAY_WORK_LATER or time.monotonic() - last_answer > patience:
                    raise
                time.sleep(backoff)
                backoff = min(backoff * 2, 5.0)
    finally:
        if stored:
            try:
                client.delete_mesh(stored)
            except IspqError:
                pass  # the server evicts it when it needs room
    if not entry.result.valid:
        raise IspqError(grpc.StatusCode.FAILED_PRECONDITION, "the result is not valid",
                        job=entry.job)
    os.makedirs(os.path.dirname(entry.result_path) or ".", exist_ok=True)
    with open(entry.result_path, "w", encoding="utf-8") as f:
        f.write(entry.result.to_json())


def _write_summary(path: str, entries: Sequence[BatchEntry]) -> None:
    with open(path, "w", encoding="utf-8") as f:
        f.write("mesh\tscaling\tstate\tobjective\thexes\tsolve_seconds\tjob\tresult_or_error\n")
        for e in entries:
            if e.ok:
                r = e.result
                f.write(f"{e.mesh_path}\t{_label(e.scaling)}\t{'KEPT' if e.kept else 'SUCCEEDED'}\t"
                        f"{r.objective!r}\t{r.hexes}\t{r.stats.solve_seconds:.3f}\t{e.job}\t"
                        f"{e.result_path}\n")
            else:
                message = str(e.error).replace("\t", " ").replace("\n", " ")
                f.write(f"{e.mesh_path}\t{_label(e.scaling)}\tFAILED\t\t\t\t{e.job}\t{message}\n")
