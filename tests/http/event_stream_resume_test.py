# SPDX-License-Identifier: Apache-2.0
"""Server-sent events read by a raw HTTP client (http.client, no SSE library): the stream is
text/event-stream with `id:` lines equal to the events' numbers; a client that hangs up and comes
back with `Last-Event-ID: n` gets the events after n, exactly those a stream from n + 1 gets, and
the stream ends with an `end` frame carrying the final status. The result is checked by the
product's validator."""
import http.client
import json
import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ispq_http_server as ispq  # noqa: E402
from tmesh_copies import disjoint_copies  # noqa: E402


class RawEventStream:
    """One text/event-stream response read line by line from a socket."""

    def __init__(self, port, path, last_event_id=None, timeout=120):
        self.connection = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
        headers = {"Accept": "text/event-stream"}
        if last_event_id is not None:
            headers["Last-Event-ID"] = str(last_event_id)
        self.connection.request("GET", path, headers=headers)
        self.response = self.connection.getresponse()

    def frames(self):
        """Yields (id, event, data) per frame until the server ends the stream."""
        fields = {}
        while True:
            line = self.response.readline()
            if not line:
                return
            line = line.decode().rstrip("\n")
            if not line:
                if "data" in fields:
                    yield fields.get("id"), fields.get("event"), fields["data"]
                fields = {}
                continue
            if line.startswith(":"):
                continue
            name, _, value = line.partition(":")
            fields[name] = value[1:] if value.startswith(" ") else value

    def close(self):
        self.connection.close()  # hangs up mid-stream


class EventStreamResumeTest(unittest.TestCase):
    def test_last_event_id_resumes_after_a_hang_up(self):
        notch = json.loads(ispq.bundled("hex-me/s07c_notch.tmesh.json"))
        mesh = disjoint_copies(notch, 60)
        mesh_path = os.path.join(ispq.ARTIFACTS, "notch_x60.tmesh.json")
        os.makedirs(ispq.ARTIFACTS, exist_ok=True)
        with open(mesh_path, "w") as f:
            json.dump(mesh, f)
        with ispq.Server("--workers=1") as server:
            job = server.submit(json.dumps(mesh), 100, progressInterval="0.02s")
            path = f"/v1/{job['name']}:watch"

            first = RawEventStream(server.http_port, path)
            self.assertEqual(first.response.status, 200)
            self.assertTrue(first.response.getheader("Content-Type").startswith("text/event-stream"))
            seen = []
            for event_id, kind, data in first.frames():
                self.assertIsNone(kind)
                event = json.loads(data)
                self.assertEqual(event_id, event["sequence"])  # 64-bit: a JSON string
                seen.append(event)
                if len(seen) == 3:
                    break
            first.close()
            self.assertIn("accepted", seen[0])
            last_id = int(seen[-1]["sequence"])

            resumed = RawEventStream(server.http_port, path, last_event_id=last_id)
            self.assertEqual(resumed.response.status, 200)
            after, end = [], None
            for event_id, kind, data in resumed.frames():
                if kind == "end":
                    end = json.loads(data)
                    continue
                self.assertIsNone(end, "nothing after the end frame")
                event = json.loads(data)
                self.assertEqual(event_id, event["sequence"])
                after.append(event)
            resumed.close()
            self.assertEqual(end, {"code": 0, "status": "OK", "message": ""})
            self.assertGreater(len(after), 0)
            sequences = [int(e["sequence"]) for e in after]
            self.assertGreater(sequences[0], last_id)
            self.assertEqual(sequences, sorted(set(sequences)), "numbers only increase")
            self.assertIn("result", after[-1])

            # A stream started at last_id + 1 after the end replays exactly the kept events.
            replay = RawEventStream(server.http_port, f"{path}?fromEvent={last_id + 1}")
            replayed = [json.loads(d) for _, kind, d in replay.frames() if kind is None]
            replay.close()
            self.assertEqual(replayed[-1], after[-1])
            self.assertTrue(set(e["sequence"] for e in replayed) <= set(e["sequence"] for e in after))

            result = after[-1]["result"]
            verdict = ispq.validate(mesh_path, result, 100)
            self.assertEqual(verdict["exit_code"], 0, verdict)
            self.assertTrue(verdict["valid"], verdict)
            self.assertAlmostEqual(verdict["objective"], result["objective"], places=6)
            self.assertEqual(server.wait_done(job["name"])["result"]["q"], result["q"])


if __name__ == "__main__":
    unittest.main()
