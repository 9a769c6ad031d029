# SPDX-License-Identifier: Apache-2.0
"""By hand, next to the load test (tests/load): measures what the HTTP side costs. While
`ispq_load_test` runs, this samples the CPU time of the ispq-server it started (a child of the
given load-test process) and, with --http_port, also follows the server's jobs over server-sent
events (the newest job, one after the other, as a web view would) and scrapes /metrics every
second. Prints the server's CPU seconds, the events received and their delays from publication.

  ispq_load_test --clients 4 --jobs_per_client 100 --workers 2 --levels 10,25 \\
      --server_flags=--http_listen=127.0.0.1:18089 & python3 overhead_watcher.py $! --http_port 18089
"""
import argparse
import datetime
import http.client
import json
import os
import statistics
import threading
import time

TICKS = os.sysconf("SC_CLK_TCK")


def server_pid(parent):
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                command = f.read().split(b"\0")[0]
        except OSError:
            continue
        if int(fields[1]) == parent and command.endswith(b"ispq-server"):
            return int(entry)
    return None


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime + stime


def follow_jobs(port, stop, delays):
    while not stop.is_set():
        try:
            connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
            connection.request("GET", "/v1/jobs?pageSize=1")
            jobs = json.loads(connection.getresponse().read()).get("jobs", [])
            if not jobs:
                time.sleep(0.05)
                continue
            connection.request("GET", f"/v1/{jobs[0]['name']}:watch")
            response = connection.getresponse()
            for line in response:
                if line.startswith(b"data: {\"job\""):
                    event = json.loads(line[6:])
                    published = datetime.datetime.fromisoformat(event["time"][:26].rstrip("Z"))
                    now = datetime.datetime.utcnow()
                    delays.append((now - published).total_seconds() * 1000)
            connection.close()
        except (OSError, ValueError, http.client.HTTPException):
            time.sleep(0.1)


def scrape(port, stop, count):
    while not stop.wait(1.0):
        try:
            connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
            connection.request("GET", "/metrics")
            connection.getresponse().read()
            connection.close()
            count[0] += 1
        except OSError:
            pass


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("load_test_pid", type=int)
    parser.add_argument("--http_port", type=int, default=0)
    args = parser.parse_args()
    pid = None
    deadline = time.monotonic() + 600
    while pid is None and time.monotonic() < deadline:
        pid = server_pid(args.load_test_pid)
        time.sleep(0.05)
    if pid is None:
        raise SystemExit("no ispq-server under that process")
    stop, delays, scrapes = threading.Event(), [], [0]
    threads = []
    if args.http_port:
        threads = [threading.Thread(target=follow_jobs, args=(args.http_port, stop, delays)),
                   threading.Thread(target=scrape, args=(args.http_port, stop, scrapes))]
        for thread in threads:
            thread.start()
    last = 0.0
    while True:
        try:
            last = cpu_seconds(pid)
        except OSError:
            break
        time.sleep(0.02)
    stop.set()
    for thread in threads:
        thread.join(timeout=35)
    print(f"server CPU seconds: {last:.2f}")
    if args.http_port:
        print(f"metrics scrapes: {scrapes[0]}; events over SSE: {len(delays)}; delay from "
              f"publication: median {statistics.median(delays):.2f} ms, "
              f"p90 {sorted(delays)[int(0.9 * (len(delays) - 1))]:.2f} ms" if delays else
              "no events")


if __name__ == "__main__":
    main()
