# SPDX-License-Identifier: Apache-2.0
"""Cross-site requests from a real browser (headless Chromium over the DevTools protocol,
devtools_pipe.py) against an anonymous ispq-server, as issue 24 found them: a page on another
origin (a file:// page) posts a job with a text/plain form and with fetch in no-cors mode, and
tries a JSON fetch (which needs a CORS preflight the server does not grant). None may create a
job. The server's own page, whose origin matches, still submits and cancels."""
import json
import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ispq_http_server as ispq  # noqa: E402
from devtools_pipe import Browser  # noqa: E402

ATTACK_PAGE = """<!doctype html>
<html><body>
<iframe name="sink"></iframe>
<form id="form" method="POST" enctype="text/plain" target="sink" action="{url}">
  <input type="hidden" name='{{"mesh":{mesh},"x":"' value='"}}'>
</form>
<script>
window.done = {{form: false, noCors: null, json: null}};
document.querySelector('iframe').onload = () => {{ window.done.form = true; }};
document.getElementById('form').submit();
fetch('{url}', {{method: 'POST', mode: 'no-cors', headers: {{'Content-Type': 'text/plain'}},
                body: JSON.stringify({{mesh: {mesh}}})}})
  .then(r => {{ window.done.noCors = 'sent: ' + r.type; }})
  .catch(e => {{ window.done.noCors = 'failed: ' + e; }});
fetch('{url}', {{method: 'POST', headers: {{'Content-Type': 'application/json'}},
                body: JSON.stringify({{mesh: {mesh}}})}})
  .then(r => {{ window.done.json = 'answered ' + r.status; }})
  .catch(e => {{ window.done.json = 'blocked: ' + e; }});
</script>
</body></html>
"""

OWN_PAGE_SUBMIT_AND_CANCEL = """(async () => {{
  const submitted = await fetch('/v1/jobs', {{method: 'POST',
      headers: {{'Content-Type': 'application/json'}},
      body: JSON.stringify({{mesh: {mesh}, options: {{scaling: {{levelPercent: 10}}}}}})}});
  const job = await submitted.json();
  const cancelled = await fetch('/v1/' + job.name + ':cancel', {{method: 'POST',
      headers: {{'Content-Type': 'application/json'}}}});
  return JSON.stringify({{submitted: submitted.status, cancelled: cancelled.status}});
}})()"""


def jobs(server):
    return json.loads(server.request("GET", "/v1/jobs")[2])["jobs"]


class CrossSiteBrowserTest(unittest.TestCase):
    def test_other_origins_cannot_create_jobs_the_own_page_can(self):
        os.makedirs(ispq.ARTIFACTS, exist_ok=True)
        mesh = ispq.bundled("hex-me/s07c_notch.tmesh.json").strip()
        with ispq.Server("--workers=1") as server, Browser() as browser:
            refused = 'ispq_http_refused_total{status="415"}'
            refused_before = server.metric(refused)
            url = f"http://127.0.0.1:{server.http_port}/v1/jobs"
            page = os.path.join(ispq.ARTIFACTS, "cross_site_attack.html")
            with open(page, "w") as f:
                f.write(ATTACK_PAGE.format(url=url, mesh=mesh))
            browser.call("Page.navigate", {"url": f"file://{page}"}, session=True)
            done = json.loads(browser.wait_for(
                "window.done && window.done.form && window.done.noCors !== null && "
                "window.done.json !== null && JSON.stringify(window.done)", timeout=60))
            print(f"\nattack page: {done}", flush=True)
            self.assertTrue(done["json"].startswith("blocked"), done)  # no CORS preflight granted
            time.sleep(0.5)  # anything the server took has been answered by now
            self.assertEqual(jobs(server), [], "a cross-site request created a job")
            # The form and the no-cors fetch reached the server, which refused their text/plain.
            self.assertEqual(server.metric(refused) - refused_before, 2)

            browser.call("Page.navigate", {"url": f"http://127.0.0.1:{server.http_port}/"},
                         session=True)
            browser.wait_for("document.readyState === 'complete'")
            own = json.loads(browser.evaluate(OWN_PAGE_SUBMIT_AND_CANCEL.format(mesh=mesh),
                                              await_promise=True))
            self.assertEqual(own, {"submitted": 200, "cancelled": 200})
            self.assertEqual(len(jobs(server)), 1)


if __name__ == "__main__":
    unittest.main()
