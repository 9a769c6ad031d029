# SPDX-License-Identifier: Apache-2.0
"""A minimal Chrome DevTools Protocol client over --remote-debugging-pipe: headless Chromium reads
NUL-terminated JSON commands on its fd 3 and writes responses and events on its fd 4, so driving
it needs neither a websocket library nor a debugging port. Every wait is bounded. The browser dies
with the test process, however that ends (its own helper processes follow their browser)."""
import base64
import fcntl
import hashlib
import json
import os
import select
import shutil
import subprocess
import tempfile
import time

from child_processes import die_with_parent


def trust_certificate_flag(cert_file):
    """The Chromium flag that trusts this one certificate's key and nothing else:
    --ignore-certificate-errors-spki-list with base64(SHA-256 of its SubjectPublicKeyInfo)
    (headless Chromium has no CA store a test may add to without NSS tools)."""
    public = subprocess.run(["openssl", "x509", "-in", cert_file, "-pubkey", "-noout"],
                            check=True, capture_output=True, timeout=60).stdout
    der = subprocess.run(["openssl", "pkey", "-pubin", "-outform", "der"], input=public,
                         check=True, capture_output=True, timeout=60).stdout
    return "--ignore-certificate-errors-spki-list=" + base64.b64encode(
        hashlib.sha256(der).digest()).decode()


def _high_fd(fd):
    """`fd` moved to a descriptor numbered 10 or more (close-on-exec, as os.pipe's are)."""
    high = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
    os.close(fd)
    return high


class Browser:
    def __init__(self, chromium="chromium", width=1280, height=1500, timeout=60, extra_args=()):
        if shutil.which(chromium) is None:
            raise RuntimeError(f"{chromium} is not installed (deploy/install-deps.sh installs it)")
        self.profile = tempfile.mkdtemp(prefix="ispq-chromium-")
        # Above fd 4: a pipe end that already is fd 3 or 4 would be dup2'ed onto itself, which
        # leaves it close-on-exec, and Chromium would find no pipe (when the test's parent left
        # fd 3 free, as an interactive shell does).
        to_browser_read, self._to_browser = (_high_fd(fd) for fd in os.pipe())
        self._from_browser, from_browser_write = (_high_fd(fd) for fd in os.pipe())

        tie_to_test = die_with_parent()

        def pipes_as_fd_3_and_4():
            tie_to_test()
            os.dup2(to_browser_read, 3)
            os.dup2(from_browser_write, 4)

        self.log = open(os.path.join(self.profile, "chromium.log"), "w")
        self.process = subprocess.Popen(
            [chromium, "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
             "--remote-debugging-pipe", f"--user-data-dir={self.profile}", "--no-first-run",
             "--no-default-browser-check", "--disable-extensions", "--hide-scrollbars",
             f"--window-size={width},{height}", *extra_args, "about:blank"],
            stdout=self.log, stderr=self.log, close_fds=False, preexec_fn=pipes_as_fd_3_and_4)
        os.close(to_browser_read)
        os.close(from_browser_write)
        self._buffer = b""
        self._next_id = 0
        self.events = []
        self.timeout = timeout
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        self.call("Page.enable", session=True)
        self.call("Runtime.enable", session=True)

    def _read_message(self, deadline):
        while b"\0" not in self._buffer:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError("no answer from Chromium")
            ready, _, _ = select.select([self._from_browser], [], [], remaining)
            if ready:
                chunk = os.read(self._from_browser, 1 << 20)
                if not chunk:
                    raise RuntimeError("Chromium closed its DevTools pipe")
                self._buffer += chunk
        message, _, self._buffer = self._buffer.partition(b"\0")
        return json.loads(message)

    def call(self, method, params=None, session=False, timeout=None):
        self._next_id += 1
        command = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            command["sessionId"] = self.session
        os.write(self._to_browser, json.dumps(command).encode() + b"\0")
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            message = self._read_message(deadline)
            if message.get("id") == self._next_id:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result", {})
            self.events.append(message)

    def evaluate(self, expression, await_promise=False):
        """The JSON-serializable value of a JavaScript expression in the page."""
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                "awaitPromise": await_promise}, session=True)
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def wait_for(self, expression, timeout=60, interval=0.05):
        """Polls `expression` until it is truthy; its value."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(interval)
        raise TimeoutError(f"{expression} still false after {timeout} s")

    def set_file_input(self, selector, path):
        root = self.call("DOM.getDocument", session=True)["root"]["nodeId"]
        node = self.call("DOM.querySelector", {"nodeId": root, "selector": selector}, session=True)
        self.call("DOM.setFileInputFiles", {"files": [path], "nodeId": node["nodeId"]}, session=True)

    def screenshot(self, path):
        data = self.call("Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True},
                         session=True)["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))

    def close(self):
        try:
            self.call("Browser.close", timeout=10)
        except Exception:  # noqa: BLE001 - closing anyway
            pass
        try:
            self.process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self._to_browser)
        os.close(self._from_browser)
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
