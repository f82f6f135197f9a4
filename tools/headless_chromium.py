#!/usr/bin/python3
"""Drive Debian's headless Chromium over the DevTools protocol, with the standard library.

Used by the tests of the pages deploysim writes (the mission report, the 3D viewer): open a
local file with no network, collect every console error, uncaught exception and failed
resource load, evaluate JavaScript in the page and take screenshots.

Why this file: the usual drivers (Playwright, Puppeteer, Selenium) are not Debian packages
or download their own browser; the DevTools protocol over a pipe (--remote-debugging-pipe:
JSON messages ending in a NUL byte, browser reads fd 3 and writes fd 4) needs nothing but
subprocess and json.

As a library:
    with Browser() as b:
        page = b.open("file:///abs/path/report.html")   # waits for the load event
        page.evaluate("document.title")
        page.screenshot("shot.png")
        page.errors()      # list of one-line strings; empty when the page is clean

As a command:
    headless_chromium.py PAGE.html [--screenshot OUT.png] [--width W --height H]
prints the console errors and exits 1 when there are any.
"""

import argparse
import base64
import json
import os
import pathlib
import select
import shutil
import subprocess
import sys
import tempfile
import time

CHROMIUM = "/usr/bin/chromium"

# Flags for a closed network and a root user (see the machine notes): no sandbox, no GPU,
# no background connections, a fresh profile per run.
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--disable-dev-shm-usage",
    "--mute-audio",
    "--remote-debugging-pipe",
]


class ChromiumError(RuntimeError):
    pass


class Browser:
    """One headless Chromium process; closed by close() or the with-block."""

    def __init__(self, width=1280, height=800, timeout=60.0):
        if not os.access(CHROMIUM, os.X_OK):
            raise ChromiumError(f"{CHROMIUM} not found (Debian package chromium)")
        self.timeout = timeout
        self.width, self.height = width, height
        self._profile = tempfile.mkdtemp(prefix="deploysim-chromium-")
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        # The child must see the pipes as fds 3 (reads) and 4 (writes).
        def place_fds():
            # Through fds above 4 first, so that a pipe already on 3 or 4 is not clobbered.
            r, w = os.dup(to_browser_r), os.dup(from_browser_w)
            r, w = os.dup2(r, 100), os.dup2(w, 101)
            os.dup2(r, 3)
            os.dup2(w, 4)

        self._proc = subprocess.Popen(
            [CHROMIUM, *FLAGS, f"--user-data-dir={self._profile}",
             f"--window-size={width},{height}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            # Not pass_fds=(3, 4): the child checks those fds before place_fds makes them,
            # and fails with EBADF when the parent happens to have 3 or 4 closed.
            preexec_fn=place_fds, close_fds=False)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._buf = b""
        self._next_id = 0
        self._events = []

    # --- protocol -------------------------------------------------------------------
    def _send(self, method, params=None, session=None):
        self._next_id += 1
        msg = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._to_browser, json.dumps(msg).encode() + b"\0")
        return self._next_id

    def _read_message(self, deadline):
        while b"\0" not in self._buf:
            if time.monotonic() > deadline:
                raise ChromiumError("no answer from chromium before the timeout")
            ready, _, _ = select.select([self._from_browser], [], [], 0.2)
            if ready:
                chunk = os.read(self._from_browser, 1 << 20)
                if not chunk:
                    raise ChromiumError("chromium closed the DevTools pipe")
                self._buf += chunk
        raw, self._buf = self._buf.split(b"\0", 1)
        return json.loads(raw)

    def call(self, method, params=None, session=None, timeout=None):
        """Sends a command and returns its result (events seen meanwhile are kept)."""
        cid = self._send(method, params, session)
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            msg = self._read_message(deadline)
            if msg.get("id") == cid:
                if "error" in msg:
                    raise ChromiumError(f"{method}: {msg['error'].get('message')}")
                return msg.get("result", {})
            if "method" in msg:
                self._events.append(msg)

    def wait_event(self, method, session, timeout=None):
        deadline = time.monotonic() + (timeout or self.timeout)
        for i, ev in enumerate(self._events):
            if ev["method"] == method and ev.get("sessionId") == session:
                return self._events.pop(i)
        while True:
            msg = self._read_message(deadline)
            if "method" in msg:
                if msg["method"] == method and msg.get("sessionId") == session:
                    return msg
                self._events.append(msg)

    def drain(self, seconds=0.0):
        """Reads the events that arrive within `seconds` (console output after load)."""
        deadline = time.monotonic() + seconds
        while True:
            try:
                msg = self._read_message(deadline)
            except ChromiumError:
                return
            if "method" in msg:
                self._events.append(msg)

    # --- pages ----------------------------------------------------------------------
    def open(self, url, settle=0.3):
        """Opens url in a new tab, waits for its load event; returns a Page."""
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.call("Target.attachToTarget",
                            {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime.enable", "Log.enable", "Page.enable"):
            self.call(domain, session=session)
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": self.width, "height": self.height, "deviceScaleFactor": 1,
                   "mobile": False}, session=session)
        t0 = time.monotonic()
        self.call("Page.navigate", {"url": url}, session=session)
        self.wait_event("Page.loadEventFired", session)
        load_seconds = time.monotonic() - t0
        self.drain(settle)
        return Page(self, session, load_seconds, target)

    def close(self):
        if self._proc.poll() is None:
            try:
                self._send("Browser.close")
                self._proc.wait(timeout=10)
            except Exception:
                self._proc.kill()
                self._proc.wait()
        for fd in (self._to_browser, self._from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self._profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _remote_object_text(obj):
    if "value" in obj:
        return str(obj["value"])
    return obj.get("description", obj.get("type", "?"))


class Page:
    def __init__(self, browser, session, load_seconds, target):
        self.browser = browser
        self.session = session
        self.target = target
        self.load_seconds = load_seconds  # navigation start to the load event [s]

    def evaluate(self, expression, await_promise=True):
        """Evaluates a JavaScript expression; returns its value (JSON-serialisable)."""
        r = self.browser.call("Runtime.evaluate",
                              {"expression": expression, "awaitPromise": await_promise,
                               "returnByValue": True}, session=self.session)
        if "exceptionDetails" in r:
            d = r["exceptionDetails"]
            text = d.get("exception", {}).get("description", d.get("text", "exception"))
            raise ChromiumError(f"evaluate({expression!r}): {text.splitlines()[0]}")
        return r["result"].get("value")

    def screenshot(self, path):
        data = self.browser.call("Page.captureScreenshot", {"format": "png"},
                                 session=self.session)["data"]
        pathlib.Path(path).write_bytes(base64.b64decode(data))
        return path

    def close(self):
        """Closes the tab (its events stay readable through errors())."""
        self.browser.call("Target.closeTarget", {"targetId": self.target})

    def errors(self):
        """Console errors, uncaught exceptions and failed loads of this page, one line each."""
        self.browser.drain(0.1)
        out = []
        for ev in self.browser._events:
            if ev.get("sessionId") != self.session:
                continue
            p = ev.get("params", {})
            if ev["method"] == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append("console." + p["type"] + ": " +
                           " ".join(_remote_object_text(a) for a in p.get("args", [])))
            elif ev["method"] == "Runtime.exceptionThrown":
                d = p.get("exceptionDetails", {})
                text = d.get("exception", {}).get("description", d.get("text", "exception"))
                out.append("uncaught: " + text.splitlines()[0])
            elif ev["method"] == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                e = p["entry"]
                out.append(f"{e.get('source', 'log')}: {e.get('text', '')} {e.get('url', '')}".strip())
        return out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("page", help="HTML file to open (a local path)")
    ap.add_argument("--screenshot", help="write a PNG of the page after it loaded")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=800)
    a = ap.parse_args(argv)
    url = pathlib.Path(a.page).resolve().as_uri()
    with Browser(a.width, a.height) as b:
        page = b.open(url)
        if a.screenshot:
            page.screenshot(a.screenshot)
        errs = page.errors()
        print(f"loaded in {page.load_seconds:.3f} s; {len(errs)} console error(s)")
        for e in errs:
            print("  " + e)
        return 1 if errs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
