# SPDX-License-Identifier: Apache-2.0
"""Measures the HTTP side under each attack of issue 24's table and prints the figures beside the
issue's (taken before the HTTP side moved to libmicrohttpd), as a Markdown table; also written to
$ISPQ_TEST_ARTIFACTS/http_attack_report.md. Each attack runs against a fresh ispq-server with a
256 MiB memory budget (the 512 MiB chunked body against a 4 MiB --max_message_bytes, as in the
issue). Not a test: it asserts nothing (tests/http/bounds_test.py does), it measures.

    ISPQ_SERVER_BINARY=build/release/server/ispq-server ISPQ_CLI=build/release/client/ispq \\
    ISPQ_TEST_DATA=tests/data/tmesh python3 tests/http/http_attack_report.py [--seconds 30]
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import http_attacks as attacks  # noqa: E402
import ispq_http_server as ispq  # noqa: E402

SMALL_LIMIT = "--max_message_bytes=4194304"


def mib(value):
    return f"{value:.0f} MiB"


def peak(figures):
    return f"RSS {mib(figures['rss_before_mib'])} -> peak {mib(figures['peak_mib'])}"


def measure(seconds):
    rows = []

    def row(case, before, after):
        rows.append((case, before, after))
        print(f"- {case}: {after}", flush=True)

    with ispq.Server(attacks.BUDGET_FLAG, SMALL_LIMIT) as server:
        for coding in ("gzip", "deflate"):
            f = attacks.compressed_body(server, coding)
            row(f"{coding} body, 1 MiB inflating to 1 GiB",
                "inflated whole: RSS +2 GiB, then 429 after 21 s",
                f"{f['status']} before the body is read; {peak(f)}")
        f = attacks.chunked_body(server)
        row("chunked body of 512 MiB (limit 4 MiB)", "read whole: RSS 29 -> 1050 MiB",
            f"{f['status']} after {f['sent_mib']:.1f} MiB taken by the socket; {peak(f)}")
        f = attacks.unframed_body(server)
        row("POST with no Content-Length, not chunked",
            "read whole; connection closed with no answer", f"{f['status']}")
        f = attacks.nested_bodies(server)
        row("JSON nested 10^3..10^6 deep, then eight 1 MB bodies of `[`",
            "400, but RSS 27 -> 696 MiB; eight bodies left 1.8 GiB resident",
            f"{sorted(set(f['statuses'].values()))} and {f['eight']}; {peak(f)}")
        for name, f in attacks.header_floods(server).items():
            row(f"256 MiB {name}", "read whole (header lines: 200); RSS +514..573 MiB",
                f"{f['status']} after {f['sent_mib']:.2f} MiB taken by the socket; {peak(f)}")
        ct = attacks.content_types(server)
        row("text/plain, application/xml, image/png, no content type",
            "all parsed as JSON", ", ".join(f"{k}: {v}" for k, v in ct.items()))
        lenient = attacks.lenient_json(server)
        row("raw NUL, BOM, duplicate keys (and invalid UTF-8)", "accepted",
            ", ".join(f"{k}: {v[0]}" for k, v in lenient.items()))

    token_file = os.path.join(ispq.ARTIFACTS, "http_report_token")
    with open(token_file, "w") as out:
        out.write("report-token\n")
    with ispq.Server(attacks.BUDGET_FLAG, f"--auth_token_file={token_file}") as server:
        f = attacks.compressed_body(server, "gzip")
        row("gzip body with tokens configured, none sent",
            "inflated before the 401 (254 KiB body: +256 MiB)",
            f"{f['status']} before authentication; {peak(f)}")

    with ispq.Server(attacks.BUDGET_FLAG, "--workers=1") as server:
        f = attacks.concurrent_bodies(server)
        row("40 bodies of 30 MiB at once", "RSS 1433 MiB: bodies accounted only once received",
            f"answers {f['statuses']}; {peak(f)} (budget 256 MiB)")

    with ispq.Server(attacks.BUDGET_FLAG, "--workers=1") as server:
        f = attacks.cross_site(server)
        row("anonymous server: cross-origin text/plain form POST, foreign Host",
            "creates a job (CSRF); any Host served (DNS rebinding)",
            f"form {f['text_plain_form']}, foreign Origin {f['foreign_origin']}, foreign Host "
            f"{f['foreign_host_post']}/{f['foreign_host_list']}; jobs created: "
            f"{f['jobs_created']} (the same-origin control)")

    with ispq.Server(attacks.BUDGET_FLAG, "--workers=1") as server:
        f = attacks.slow_and_idle(server, seconds=seconds)
        probes = "; ".join(
            f"{path} {f[path]['n']} probes, all {sorted(f[path]['statuses'])}, p50 "
            f"{f[path]['p50_ms']:.1f} ms, p99 {f[path]['p99_ms']:.1f} ms, max {f[path]['max_ms']:.1f} ms"
            for path in ("/healthz", "/readyz", "/metrics"))
        row(f"300 slow (250 slowloris heads, 50 trickled chunked bodies) + 300 idle connections, "
            f"{seconds} s", "/healthz failed 6 of 15 probes, /metrics 6 of 11 (others up to "
            "3.5 s); 50 unfinished uploads: /healthz timed out 3 of 3",
            f"{probes}; jobs during it: {f['jobs']}; connections: {f['connections']}; {peak(f)}")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=int, default=30, help="of slow and idle connections")
    args = parser.parse_args()
    os.makedirs(ispq.ARTIFACTS, exist_ok=True)
    started = time.monotonic()
    rows = measure(args.seconds)
    table = ["| case | before (issue 24) | after |", "| --- | --- | --- |"]
    table += [f"| {case} | {before} | {after} |" for case, before, after in rows]
    text = "\n".join(table) + "\n"
    print("\n" + text)
    path = os.path.join(ispq.ARTIFACTS, "http_attack_report.md")
    with open(path, "w") as out:
        out.write(text)
    print(f"written to {path} in {time.monotonic() - started:.0f} s")


if __name__ == "__main__":
    main()
