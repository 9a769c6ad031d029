# SPDX-License-Identifier: Apache-2.0
"""Hostile clients of the HTTP side, over raw sockets, as issue 24 tried them: compressed, chunked,
length-less, oversized and deeply nested bodies; floods of header lines, one endless header or
request line; hundreds of slow and idle connections while the probes are polled; cross-site and
mis-addressed requests. Each attack returns what it measured (answers, bytes the server took,
the server's peak resident memory from /proc/PID/status), for the assertions of
bounds_test.py and the table of http_attack_report.py. Every wait is bounded."""
import collections
import json
import multiprocessing
import os
import selectors
import socket
import statistics
import subprocess
import threading
import time
import zlib

import ispq_http_server as ispq

MiB = 1 << 20
BUDGET_FLAG = "--max_memory_bytes=256MiB"  # as the issue ran it
BUDGET = 256 * MiB


# ---- the server's memory ----

def memory_mib(pid):
    """(VmHWM, VmRSS) of `pid` in MiB: the peak resident set since the last reset, and now."""
    values = {}
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            name, _, rest = line.partition(":")
            if name in ("VmHWM", "VmRSS"):
                values[name] = int(rest.split()[0]) / 1024
    return values["VmHWM"], values["VmRSS"]


def reset_peak(pid):
    """Starts VmHWM over from the present resident set, so that each attack has its own peak."""
    with open(f"/proc/{pid}/clear_refs", "w") as f:
        f.write("5")


class Peak:
    """The server's resident memory before an attack and its peak during it."""

    def __init__(self, server):
        self.pid = server.process.pid

    def __enter__(self):
        time.sleep(0.2)  # let the previous attack's memory go
        reset_peak(self.pid)
        self.before = memory_mib(self.pid)[1]
        return self

    def __exit__(self, *exc):
        self.peak = memory_mib(self.pid)[0]


# ---- raw requests ----

def head(server, method, path, headers=(), host=None):
    lines = [f"{method} {path} HTTP/1.1", f"Host: {host or f'127.0.0.1:{server.http_port}'}"]
    lines += [f"{name}: {value}" for name, value in headers]
    return ("\r\n".join(lines) + "\r\n\r\n").encode()


def read_answer(sock, timeout=30):
    """(status, headers dict with lower-case names, body) of the answer on `sock`, or
    (0, {}, b"") if none came; a body is read as far as Content-Length or the close."""
    sock.settimeout(timeout)
    data = b""
    try:
        while b"\r\n\r\n" not in data:
            chunk = sock.recv(65536)
            if not chunk:
                break
            data += chunk
    except OSError:
        pass
    if b"\r\n\r\n" not in data:
        return 0, {}, b""
    raw_head, _, body = data.partition(b"\r\n\r\n")
    lines = raw_head.decode("latin-1").split("\r\n")
    status = int(lines[0].split()[1])
    headers = {}
    for line in lines[1:]:
        name, _, value = line.partition(":")
        headers[name.strip().lower()] = value.strip()
    length = int(headers.get("content-length", "-1"))
    try:
        while length < 0 or len(body) < length:
            chunk = sock.recv(65536)
            if not chunk:
                break
            body += chunk
    except OSError:
        pass
    return status, headers, body


def exchange(server, request_head, body=b"", timeout=30):
    """Sends a head and a body on a fresh connection; the answer as read_answer gives it."""
    with socket.create_connection(("127.0.0.1", server.http_port), timeout=timeout) as sock:
        try:
            sock.sendall(request_head + body)
        except OSError:
            pass  # refused before the body was taken: the answer is there
        return read_answer(sock, timeout)


def push(server, request_head, pieces, timeout=60):
    """Sends a head, then pieces until the server stops taking them. (answer, bytes of pieces
    the socket took): what the server read is at most that."""
    sent = 0
    with socket.create_connection(("127.0.0.1", server.http_port), timeout=timeout) as sock:
        try:
            sock.sendall(request_head)
            for piece in pieces:
                sock.sendall(piece)
                sent += len(piece)
        except OSError:
            pass
        return read_answer(sock, timeout), sent


def post_json(server, path, body, headers=(), host=None):
    all_headers = [("Content-Length", len(body))] + list(headers)
    return exchange(server, head(server, "POST", path, all_headers, host), body)


def jobs_count(server):
    status, _, text = server.request("GET", "/v1/jobs?pageSize=1000")
    assert status == 200, (status, text)
    return len(json.loads(text)["jobs"])


def notch_request(level=10):
    return ('{"mesh":' + ispq.bundled("hex-me/s07c_notch.tmesh.json") +
            ',"options":{"scaling":{"levelPercent":' + str(level) + '}}}').encode()


# ---- the attacks of the table ----

def compressed_body(server, coding, token=None):
    """1 MiB that inflates to 1 GiB, sent as Content-Encoding `coding`."""
    compressor = zlib.compressobj(9, zlib.DEFLATED, 31 if coding == "gzip" else 15)
    zeros = bytes(MiB)
    body = b"".join(compressor.compress(zeros) for _ in range(1024)) + compressor.flush()
    headers = [("Content-Type", "application/json"), ("Content-Encoding", coding),
               ("Content-Length", len(body))]
    if token:
        headers.append(("Authorization", f"Bearer {token}"))
    with Peak(server) as memory:
        status, _, text = exchange(server, head(server, "POST", "/v1/jobs", headers), body)
    return {"status": status, "body": text, "sent_mib": len(body) / MiB,
            "rss_before_mib": memory.before, "peak_mib": memory.peak}


def chunked_body(server, total_mib=512):
    """A chunked JSON body of `total_mib` (the server's limit is far less), 64 KiB a chunk."""
    piece = b"[" * 65536
    chunk = b"%x\r\n" % len(piece) + piece + b"\r\n"
    request = head(server, "POST", "/v1/jobs", [("Content-Type", "application/json"),
                                                ("Transfer-Encoding", "chunked")])
    with Peak(server) as memory:
        (status, _, text), sent = push(server, request, (chunk for _ in range(total_mib * 16)))
    return {"status": status, "body": text, "sent_mib": sent / MiB,
            "rss_before_mib": memory.before, "peak_mib": memory.peak}


def unframed_body(server):
    """A POST with neither Content-Length nor chunked, its body following the head."""
    request = head(server, "POST", "/v1/jobs", [("Content-Type", "application/json")])
    status, _, text = exchange(server, request, notch_request())
    return {"status": status, "body": text}


def concurrent_bodies(server, count=40, size_mib=30):
    """`count` requests of `size_mib` each at once: all heads first, then the bodies of those
    not refused yet. The bodies are a valid small request padded with spaces."""
    body = notch_request()
    body += b" " * (size_mib * MiB - len(body))
    request = head(server, "POST", "/v1/jobs", [("Content-Type", "application/json"),
                                                ("Content-Length", len(body))])
    answers = [None] * count

    def send(index, sock):
        try:
            sock.sendall(body)
        except OSError:
            pass
        answers[index] = read_answer(sock, timeout=120)[0]

    with Peak(server) as memory:
        sockets = [socket.create_connection(("127.0.0.1", server.http_port), timeout=120)
                   for _ in range(count)]
        for sock in sockets:
            sock.sendall(request)
        threads = [threading.Thread(target=send, args=(i, s)) for i, s in enumerate(sockets)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=300)
        for sock in sockets:
            sock.close()
    return {"statuses": dict(collections.Counter(answers)), "rss_before_mib": memory.before,
            "peak_mib": memory.peak}


def nested_json(server, depth):
    body = b'{"mesh":' + b"[" * depth
    status, _, text = post_json(server, "/v1/jobs", body, [("Content-Type", "application/json")])
    return status, text


def nested_bodies(server):
    """Bodies nested 10^3..10^6 deep, then eight 1 MB bodies of `[` at once."""
    with Peak(server) as memory:
        statuses = {depth: nested_json(server, depth)[0] for depth in (10**3, 10**4, 10**5, 10**6)}
        threads, eight = [], []
        for _ in range(8):
            threads.append(threading.Thread(
                target=lambda: eight.append(nested_json(server, 10**6)[0])))
            threads[-1].start()
        for thread in threads:
            thread.join(timeout=120)
    return {"statuses": statuses, "eight": dict(collections.Counter(eight)),
            "rss_before_mib": memory.before, "peak_mib": memory.peak}


def header_floods(server, total_mib=256):
    """256 MiB of header lines, one 256 MiB header, a 256 MiB request line."""
    port_host = f"Host: 127.0.0.1:{server.http_port}\r\n".encode()
    floods = {
        "header lines": (b"GET /healthz HTTP/1.1\r\n" + port_host, b"X-Flood: a\r\n" * 5000),
        "one header": (b"GET /healthz HTTP/1.1\r\n" + port_host + b"X-Flood: ", b"a" * 65536),
        "request line": (b"GET /healthz?flood=", b"a" * 65536),
    }
    results = {}
    for name, (start, piece) in floods.items():
        count = total_mib * MiB // len(piece)
        with Peak(server) as memory:
            (status, headers, text), sent = push(server, start, (piece for _ in range(count)))
        results[name] = {"status": status, "sent_mib": sent / MiB, "json": text.startswith(b"{"),
                         "rss_before_mib": memory.before, "peak_mib": memory.peak}
    return results


# ---- slow and idle clients ----

def _hold_connections(port, slow, idle, slow_bodies, seconds, counts):
    """In a process of its own: keeps `slow` connections sending a header line every ~2 s
    (slowloris), `slow_bodies` sending a chunked body a few bytes every ~2 s, and `idle`
    connections sending nothing, reopening each as the server closes it; for `seconds`."""
    selector = selectors.DefaultSelector()
    host = f"Host: 127.0.0.1:{port}\r\n".encode()
    starts = {"slow": b"GET /healthz HTTP/1.1\r\n" + host,
              "body": (b"POST /v1/jobs HTTP/1.1\r\n" + host +
                       b"Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n"),
              "idle": b""}
    trickle = {"slow": b"X-Slow: a\r\n", "body": b"1\r\n[\r\n", "idle": b""}
    opened = collections.Counter()
    closed = collections.Counter()
    conns = {}

    def open_one(kind, stagger):
        sock = socket.socket()
        sock.setblocking(False)
        sock.connect_ex(("127.0.0.1", port))
        selector.register(sock, selectors.EVENT_READ, kind)
        conns[sock] = [kind, time.monotonic() + stagger, False]
        opened[kind] += 1

    for kind, number in (("slow", slow), ("body", slow_bodies), ("idle", idle)):
        for i in range(number):
            open_one(kind, 2.0 * i / max(number, 1))
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        for key, _ in selector.select(timeout=0.05):
            sock, kind = key.fileobj, key.data
            try:
                sock.recv(4096)
            except BlockingIOError:
                continue
            except OSError:
                pass
            # Closed, or answered (a refusal, then closed): the server let go of it.
            selector.unregister(sock)
            sock.close()
            del conns[sock]
            closed[kind] += 1
            open_one(kind, 0)
        now = time.monotonic()
        for sock, state in list(conns.items()):
            kind, due, started = state
            if kind == "idle" or now < due:
                continue
            try:
                sock.send(trickle[kind] if started else starts[kind])
                state[2] = True
            except BlockingIOError:
                pass
            except OSError:
                pass
            state[1] = now + 2.0
    counts.update({f"opened_{k}": v for k, v in opened.items()})
    counts.update({f"closed_by_server_{k}": v for k, v in closed.items()})
    for sock in conns:
        sock.close()


def _probe(port, path, timeout):
    """(status, seconds) of one probe on a fresh connection, as an orchestrator makes it."""
    start = time.monotonic()
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=timeout) as sock:
            sock.sendall(f"GET {path} HTTP/1.1\r\nHost: 10.0.0.1:{port}\r\n"
                         "Connection: close\r\n\r\n".encode())
            status = read_answer(sock, timeout)[0]
    except OSError:
        status = 0
    return status, time.monotonic() - start


def percentiles(seconds):
    ordered = sorted(seconds)
    if not ordered:
        return {}
    at = lambda q: ordered[min(len(ordered) - 1, int(q * len(ordered)))]  # noqa: E731
    return {"n": len(ordered), "p50_ms": 1000 * statistics.median(ordered),
            "p99_ms": 1000 * at(0.99), "max_ms": 1000 * ordered[-1]}


def slow_and_idle(server, slow=250, slow_bodies=50, idle=300, seconds=30, probe_timeout=5):
    """300 slow connections (250 slowloris heads and 50 chunked uploads trickling) and 300 idle
    ones for `seconds`, while /healthz (every 100 ms), /readyz (200 ms) and /metrics (500 ms) are
    probed and jobs are submitted over HTTP and gRPC. What every probe answered and how fast."""
    manager = multiprocessing.Manager()
    counts = manager.dict()
    holder = multiprocessing.Process(target=_hold_connections, args=(
        server.http_port, slow, idle, slow_bodies, seconds + 4, counts))
    holder.start()
    time.sleep(4)  # all connections open (staggered over 2 s)
    probes = {path: [] for path in ("/healthz", "/readyz", "/metrics")}
    jobs = collections.Counter()
    stop = threading.Event()

    def probe_loop(path, period):
        while not stop.is_set():
            started = time.monotonic()
            probes[path].append(_probe(server.http_port, path, probe_timeout))
            stop.wait(max(0.0, period - (time.monotonic() - started)))

    def http_jobs():
        while not stop.is_set():
            try:
                job = server.submit(ispq.bundled("hex-me/s07c_notch.tmesh.json"), 10)
                jobs["http_" + server.wait_done(job["name"], timeout=60)["state"]] += 1
            except Exception:  # noqa: BLE001
                jobs["http_failed"] += 1
            stop.wait(1)

    def grpc_jobs():
        mesh = os.path.join(ispq.DATA, "hex-me/s07c_notch.tmesh.json")
        while not stop.is_set():
            run = subprocess.run([ispq.CLI, "quantize", mesh, "--server", server.address,
                                  "--level", "10", "--json"], capture_output=True, timeout=120)
            jobs["grpc_valid" if run.returncode == 0 else "grpc_failed"] += 1
            stop.wait(1)

    threads = [threading.Thread(target=probe_loop, args=a)
               for a in (("/healthz", 0.1), ("/readyz", 0.2), ("/metrics", 0.5))]
    threads += [threading.Thread(target=http_jobs), threading.Thread(target=grpc_jobs)]
    with Peak(server) as memory:
        for thread in threads:
            thread.start()
        time.sleep(seconds)
        stop.set()
        for thread in threads:
            thread.join(timeout=180)
    holder.join(timeout=60)
    result = {"jobs": dict(jobs), "connections": dict(counts), "peak_mib": memory.peak,
              "rss_before_mib": memory.before}
    for path, answers in probes.items():
        result[path] = dict(percentiles([s for _, s in answers]),
                            statuses=dict(collections.Counter(status for status, _ in answers)))
    return result


# ---- cross-site, mis-addressed and lenient requests ----

def cross_site(server):
    """A form's text/plain POST (what any page can send), a JSON POST from another origin, and a
    request naming another Host; how many jobs each created."""
    before = jobs_count(server)
    body = notch_request()
    form = post_json(server, "/v1/jobs", body, [("Content-Type", "text/plain"),
                                                ("Origin", "null")])[0]
    foreign = post_json(server, "/v1/jobs", body, [("Content-Type", "application/json"),
                                                   ("Origin", "http://evil.example")])[0]
    rebound = post_json(server, "/v1/jobs", body, [("Content-Type", "application/json")],
                        host=f"evil.example:{server.http_port}")[0]
    rebound_list = exchange(server, head(server, "GET", "/v1/jobs",
                                         host=f"evil.example:{server.http_port}"))[0]
    own = post_json(server, "/v1/jobs", body, [("Content-Type", "application/json"),
                                               ("Origin", f"http://127.0.0.1:{server.http_port}")])[0]
    return {"text_plain_form": form, "foreign_origin": foreign, "foreign_host_post": rebound,
            "foreign_host_list": rebound_list, "own_origin": own,
            "jobs_created": jobs_count(server) - before}


def content_types(server):
    body = notch_request()
    result = {}
    for content_type in ("text/plain", "application/xml", "image/png", None):
        headers = [("Content-Type", content_type)] if content_type else []
        headers.append(("Authorization", "Bearer x"))  # not the CSRF rule: the type's own
        result[content_type or "missing"] = post_json(server, "/v1/jobs", body, headers)[0]
    return result


def lenient_json(server):
    json_type = [("Content-Type", "application/json")]
    request = notch_request()
    cases = {"raw NUL": request[:-1] + b'\x00}', "BOM": b"\xef\xbb\xbf" + request,
             "duplicate keys": request[:-1] + b',"options":{}}',
             "invalid UTF-8": request[:-1] + b',"requestId":"\xff"}'}
    return {name: post_json(server, "/v1/jobs", body, json_type)[:3:2]
            for name, body in cases.items()}
