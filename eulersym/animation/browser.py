"""A headless Chromium driven over the DevTools protocol on a pipe, to see a page as a person would: open a file,
run a script in it, take a screenshot. Used by the tests and by ``eulersym bench animate``; not by the package.

Chromium starts with no network use of its own (``--disable-background-networking`` and friends), a fresh profile
folder, and ``--remote-debugging-pipe``: the protocol's JSON messages, each ended by a NUL byte, go to the browser on
its file descriptor 3 and come back on 4, so no port is opened.
"""

from __future__ import annotations

import base64
import fcntl
import json
import os
import shutil
import subprocess
import tempfile
import time

from eulersym.errors import EulersymError

__all__ = ["Chromium", "find_chromium", "FLAGS"]

#: How Chromium is started (besides the profile folder and the pipe).
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-default-apps", "--mute-audio", "--hide-scrollbars")


def find_chromium() -> str | None:
    """The Chromium (or Chrome) executable on PATH, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def _high(fd: int) -> int:
    """``fd`` moved to a descriptor number of 10 or more (close-on-exec), so that placing the child's 3 and 4 cannot
    overwrite it."""
    high = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
    os.close(fd)
    return high


class Chromium:
    """One headless browser and one page in it.

    Examples
    --------
    >>> import os, tempfile
    >>> page = os.path.join(tempfile.mkdtemp(), "p.html")
    >>> _ = open(page, "w").write("<title>hi</title><p>hello</p>")
    >>> with Chromium() as browser:  # doctest: +SKIP
    ...     browser.open(page)
    ...     browser.evaluate("document.title")
    'hi'
    """

    def __init__(self, executable: str | None = None, width: int = 800, height: int = 800, timeout: float = 60.0):
        executable = executable or find_chromium()
        if executable is None:
            raise EulersymError("Chromium was not found on PATH (Debian: apt-get install chromium)")
        self.timeout = timeout
        self._profile = tempfile.mkdtemp(prefix="eulersym-chromium-")
        to_browser_r, self._to_browser = (_high(fd) for fd in os.pipe())
        self._from_browser, from_browser_w = (_high(fd) for fd in os.pipe())

        def fds():  # in the child: the protocol's descriptors 3 (in) and 4 (out), kept across exec
            os.dup2(to_browser_r, 3)
            os.dup2(from_browser_w, 4)

        # close_fds=False: every other descriptor of ours is close-on-exec (Python's default), and 3 and 4 must stay
        self._process = subprocess.Popen(
            [executable, *FLAGS, f"--user-data-dir={self._profile}", "--remote-debugging-pipe",
             f"--window-size={width},{height}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            close_fds=False, preexec_fn=fds)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._buffer = b""
        self._next = 0
        self._session = None
        target = self._call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self._session = self._call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        self._call("Emulation.setDeviceMetricsOverride", {"width": width, "height": height, "deviceScaleFactor": 1,
                                                          "mobile": False})
        self._call("Page.enable")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        """End the browser (the process this object started) and remove its profile folder."""
        if self._process.poll() is None:
            try:
                self._call("Browser.close", session=False)
            except (EulersymError, OSError):
                pass
            try:
                self._process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()
        for fd in (self._to_browser, self._from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self._profile, ignore_errors=True)

    def _call(self, method: str, params: dict | None = None, *, session: bool = True) -> dict:
        self._next += 1
        message = {"id": self._next, "method": method, "params": params or {}}
        if session and self._session is not None:
            message["sessionId"] = self._session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            while b"\0" not in self._buffer:
                if time.monotonic() > deadline:
                    raise EulersymError(f"Chromium did not answer {method} within {self.timeout:g} s")
                chunk = os.read(self._from_browser, 1 << 16)
                if not chunk:
                    raise EulersymError(f"Chromium closed the pipe during {method}")
                self._buffer += chunk
            raw, self._buffer = self._buffer.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self._next:
                if "error" in reply:
                    raise EulersymError(f"Chromium: {method}: {reply['error'].get('message')}")
                return reply.get("result", {})

    def open(self, path: str, fragment: str = "") -> None:
        """Load a local file (``fragment``: the part after ``#``) and wait until it has loaded."""
        url = "file://" + os.path.abspath(path) + (f"#{fragment}" if fragment else "")
        self._call("Page.navigate", {"url": "about:blank"})
        self._call("Page.navigate", {"url": url})
        self.evaluate("new Promise(r => { if (document.readyState === 'complete') r(1); "
                      "else window.addEventListener('load', () => r(1)); })")

    def evaluate(self, expression: str):
        """The value of a JavaScript expression in the page (a promise is awaited); an exception is an error."""
        result = self._call("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                                 "returnByValue": True})
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            raise EulersymError(f"JavaScript error: {details.get('exception', {}).get('description') or details}")
        return result.get("result", {}).get("value")

    def screenshot(self, clip: dict | None = None) -> bytes:
        """A PNG of the page (``clip``: ``{"x", "y", "width", "height"}`` in CSS pixels)."""
        params = {"format": "png"}
        if clip is not None:
            params["clip"] = {**clip, "scale": 1}
        return base64.b64decode(self._call("Page.captureScreenshot", params)["data"])
