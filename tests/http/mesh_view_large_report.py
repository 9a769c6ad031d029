# SPDX-License-Identifier: Apache-2.0
"""How fast the web view's 3-D view opens a million-arc part (issue 30): not a test (the mesh is
236 MB and takes a minute to generate), a measurement to run by hand on a built tree:

    ISPQ_SERVER_BINARY=build/release/server/ispq-server ISPQ_CLI=build/release/client/ispq \\
    ISPQ_TEST_DATA=tests/data/tmesh /usr/bin/python3 tests/http/mesh_view_large_report.py \\
        [--arcs 1000000] [--mesh F.tmesh.pb]

It makes a synthetic part with tests/bench's ispq_make_large_tmesh (unless --mesh is given),
submits it over gRPC (`ispq submit`: UploadMesh, since no HTTP body holds it), follows the running
job in the page in headless Chromium, and prints how long the view took to draw (the geometry
built from the running job's mesh, decimated, then drawn; and again from the cache), with a
screenshot in the artifacts directory."""
import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ispq_http_server as ispq  # noqa: E402
from devtools_pipe import Browser  # noqa: E402

VIEW = """JSON.stringify({segments: ispqView.segments, arcs: ispqView.arcs, stride: ispqView.stride,
  firstDrawMs: ispqView.firstDrawMs, status: document.getElementById('mesh-status').textContent,
  caption: document.getElementById('mesh-caption').textContent})"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arcs", type=int, default=1000000)
    parser.add_argument("--mesh", help="a .tmesh.pb to use instead of generating one")
    args = parser.parse_args()
    os.makedirs(ispq.ARTIFACTS, exist_ok=True)
    mesh = args.mesh
    if mesh is None:
        generator = os.path.join(os.path.dirname(ispq.CLI), "..", "tests", "bench",
                                 "ispq_make_large_tmesh")
        mesh = os.path.join(ispq.ARTIFACTS, f"large_{args.arcs}.tmesh.pb")
        subprocess.run([generator, "--family", "single", "--arcs", str(args.arcs), "--compact",
                        "--out", mesh], check=True, timeout=1200)
    with ispq.Server("--workers=1", "--max_job_seconds=300") as server, Browser() as browser:
        started = time.monotonic()
        submitted = subprocess.run([ispq.CLI, "submit", mesh, "--level", "100", "--server",
                                    f"127.0.0.1:{server.port}", "--json"],
                                   capture_output=True, text=True, timeout=1200, check=True)
        name = json.loads(submitted.stdout)["name"]
        print(f"submitted {name} in {time.monotonic() - started:.1f} s")
        browser.call("Page.navigate", {"url": f"http://127.0.0.1:{server.http_port}/"},
                     session=True)
        browser.wait_for("document.readyState === 'complete' && typeof MeshView !== 'undefined'")
        for attempt in ("built from the running job's mesh", "from the cache"):
            started = time.monotonic()
            browser.evaluate(f"follow({json.dumps(name)})")
            browser.wait_for("ispqView.segments > 0 || "
                             "document.getElementById('mesh-status').textContent !== "
                             "'loading the mesh…'", timeout=300)
            wall = time.monotonic() - started
            view = json.loads(browser.evaluate(VIEW))
            print(f"{attempt}: {view['segments']} segments of {view['arcs']} arcs (stride "
                  f"{view['stride']}) drawn {view['firstDrawMs']:.0f} ms after the geometry was "
                  f"asked for, {wall:.2f} s after following the job; {view['caption']}"
                  f"{' ' + view['status'] if view['status'] else ''}")
        browser.evaluate("document.getElementById('mesh-figure').scrollIntoView()")
        time.sleep(0.5)
        path = os.path.join(ispq.ARTIFACTS, "mesh_view_large.png")
        browser.screenshot(path)
        print(f"screenshot: {path}")
        subprocess.run([ispq.CLI, "cancel", name, "--server", f"127.0.0.1:{server.port}"],
                       capture_output=True, timeout=60)


if __name__ == "__main__":
    main()
