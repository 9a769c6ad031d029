# SPDX-License-Identifier: Apache-2.0
"""The web view in a real browser: headless Chromium (driven over the DevTools protocol,
devtools_pipe.py) opens the page of a live ispq-server, uploads a T-mesh made of copies of the
bundled notch sample through the page's form, watches the objective curve appear and grow while
the job runs, and checks the result the page shows (and offers for download) against what the CLI
gets for the same job and against the product's validator. Saves a screenshot of the page and the
event-to-browser delays as test artifacts."""
import json
import os
import statistics
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ispq_http_server as ispq  # noqa: E402
from devtools_pipe import Browser  # noqa: E402
from tmesh_copies import disjoint_copies  # noqa: E402

# About a second of solving on the development machine, long enough to watch the curve grow (160
# copies solve in 0.6 s now, and a run once saw the curve grow fewer than three times).
COPIES = 320
LEVEL = 100

STATE = """JSON.stringify({
  points: Number(document.getElementById('curve').dataset.points),
  resultShown: !document.getElementById('result').hidden,
  phase: document.getElementById('job-phase').textContent,
  error: document.getElementById('job-error').hidden ? '' : document.getElementById('job-error').textContent,
  form: document.getElementById('form-message').textContent})"""

SHOWN_RESULT = """JSON.stringify({
  valid: document.getElementById('result-valid').textContent,
  objective: document.getElementById('result-objective').textContent,
  hexes: document.getElementById('result-hexes').textContent,
  termination: document.getElementById('result-termination').textContent,
  lpSolves: document.getElementById('result-lp-solves').textContent,
  title: document.getElementById('job-title').textContent,
  download: document.getElementById('download').getAttribute('href'),
  events: window.ispq.events, latenciesMs: window.ispq.latenciesMs})"""


class WebViewBrowserTest(unittest.TestCase):
    def test_upload_watch_and_compare_with_the_cli(self):
        os.makedirs(ispq.ARTIFACTS, exist_ok=True)
        notch = json.loads(ispq.bundled("hex-me/s07c_notch.tmesh.json"))
        mesh_path = os.path.join(ispq.ARTIFACTS, f"notch_x{COPIES}.tmesh.json")
        with open(mesh_path, "w") as f:
            json.dump(disjoint_copies(notch, COPIES), f)

        with ispq.Server("--workers=1") as server, Browser() as browser:
            browser.call("Page.navigate", {"url": f"http://127.0.0.1:{server.http_port}/"},
                         session=True)
            browser.wait_for("document.readyState === 'complete' && "
                             "document.getElementById('upload-form') !== null")
            self.assertEqual(browser.evaluate("document.title"), "ispq — live quantization")
            browser.set_file_input("#mesh-file", mesh_path)
            browser.evaluate(f"document.getElementById('level').value = '{LEVEL}'")
            browser.evaluate("document.getElementById('upload-form').requestSubmit()")

            # The curve appears and grows while the job runs.
            observed, deadline = [], time.monotonic() + 300
            while time.monotonic() < deadline:
                state = json.loads(browser.evaluate(STATE))
                self.assertFalse(state["error"], state)
                observed.append(state)
                if state["resultShown"]:
                    break
                time.sleep(0.05)
            self.assertTrue(observed[-1]["resultShown"], observed[-1])
            running = [s["points"] for s in observed if not s["resultShown"] and s["points"] > 0]
            self.assertGreaterEqual(len(set(running)), 3,
                                    f"the curve should grow while the job runs: {running}")
            self.assertEqual(running, sorted(running), "points are only added")
            self.assertGreater(observed[-1]["points"], running[-1])

            shown = json.loads(browser.evaluate(SHOWN_RESULT))
            job_name = json.loads(server.request("GET", "/v1/jobs")[2])["jobs"][0]["name"]
            # The job list catches up at its next refresh (bounded only against a hang).
            browser.wait_for("[...document.querySelectorAll('#jobs tbody tr')].some("
                             "row => row.children[2].textContent === 'SUCCEEDED')",
                             timeout=ispq.SAFETY_NET)
            browser.screenshot(os.path.join(ispq.ARTIFACTS, "web_view.png"))

            # The downloadable result is the job's result.
            downloaded = json.loads(browser.evaluate(
                "fetch(document.getElementById('download').href).then(r => r.text())",
                await_promise=True))

            # What the CLI gets for the same job (over gRPC), and the validator's verdict.
            cli_result_path = os.path.join(ispq.ARTIFACTS, "web_view_cli_result.json")
            run = subprocess.run([ispq.CLI, "watch", job_name, "--server", server.address,
                                  "--out", cli_result_path], capture_output=True, text=True,
                                 timeout=120)
            self.assertEqual(run.returncode, 0, run.stderr)
            with open(cli_result_path) as f:
                cli = json.load(f)

        self.assertEqual(shown["valid"], "yes")
        self.assertEqual(float(shown["objective"]), cli["objective"])
        self.assertEqual(shown["hexes"], cli["hexes"])
        self.assertEqual(shown["termination"], cli["termination"])
        self.assertEqual(shown["lpSolves"], cli["stats"]["lpSolves"])
        self.assertIn(f"{notch['name']}x{COPIES}", shown["title"])
        self.assertTrue(shown["download"].startswith("blob:"))
        self.assertEqual(downloaded["q"], cli["q"])
        self.assertEqual(downloaded["objective"], cli["objective"])
        verdict = ispq.validate(mesh_path, downloaded, LEVEL)
        self.assertEqual(verdict["exit_code"], 0, verdict)
        self.assertTrue(verdict["valid"], verdict)
        # The in-process solve of the same instance gives the same numbers (the solver is
        # deterministic).
        local = subprocess.run([ispq.CLI, "quantize", mesh_path, "--local", "--level", str(LEVEL),
                                "--json"], capture_output=True, text=True, timeout=300)
        self.assertEqual(local.returncode, 0, local.stderr)
        local_result = json.loads(local.stdout)
        self.assertEqual(local_result["objective"], cli["objective"])
        self.assertEqual(local_result["hexes"], cli["hexes"])

        latencies = shown["latenciesMs"]
        self.assertEqual(len(latencies), len(shown["events"]))
        report = {"events": len(latencies), "median_ms": statistics.median(latencies),
                  "p90_ms": sorted(latencies)[int(0.9 * (len(latencies) - 1))],
                  "max_ms": max(latencies), "curve_points_while_running": running}
        with open(os.path.join(ispq.ARTIFACTS, "web_view_latency.json"), "w") as f:
            json.dump(report, f, indent=2)
        print(f"event-to-browser delay over {report['events']} events: median "
              f"{report['median_ms']} ms, p90 {report['p90_ms']} ms, max {report['max_ms']} ms")


if __name__ == "__main__":
    unittest.main()
