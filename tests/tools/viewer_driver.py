#!/usr/bin/env python3
"""Drive headless Chromium over the DevTools protocol on a pipe (no extra
Python modules, no network port): open pages, act on them as a person would
(clicks, keys, typing), evaluate read-only expressions, take screenshots.

Reads a plan as JSON on stdin:
  {"pages": [{"url": "file:///...", "viewport": [w, h], "mobile": false,
              "actions": [{"eval": "expr"}, {"click": "expr -> [x, y]"},
                          {"tap": "expr -> [x, y]"}, {"key": "ArrowLeft"},
                          {"type": "text"}, {"wait": "expr"},
                          {"drag": [x0, y0, x1, y1]}, {"pinch": [cx, cy, r0, r1]},
                          {"wheel": [x, y, dy]}, {"shot": "file.png"}]}]}
Prints JSON: the browser version and, per page, each action's result, the
console errors, uncaught exceptions, failed requests and every URL requested.
"""
import base64
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-default-apps",
    "--disable-extensions",
    "--mute-audio",
    # No name resolves: nothing can leave the machine.
    "--host-resolver-rules=MAP * ~NOTFOUND",
    # WebGL on the CPU (no GPU in headless runs).
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--remote-debugging-pipe",
]


class Browser:
    def __init__(self, exe):
        self.profile = tempfile.mkdtemp(prefix="karigami-chromium-")
        to_browser_r, self.to_browser = os.pipe()
        self.from_browser, from_browser_w = os.pipe()

        def fds():
            # The browser reads commands on fd 3 and answers on fd 4.
            a, b = os.dup(to_browser_r), os.dup(from_browser_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [exe] + CHROMIUM_FLAGS + ["--user-data-dir=" + self.profile, "about:blank"],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            preexec_fn=fds,
            close_fds=False,
        )
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.next_id = 0
        self.buffer = b""
        self.events = []

    def send(self, method, params=None, session=None, timeout=30):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self.to_browser, json.dumps(msg).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            reply = self.read(deadline)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def read(self, deadline):
        while b"\0" not in self.buffer:
            if time.time() > deadline:
                raise TimeoutError("no answer from the browser")
            chunk = os.read(self.from_browser, 1 << 20)
            if not chunk:
                raise RuntimeError("the browser closed the pipe")
            self.buffer += chunk
        raw, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(raw)

    def close(self):
        try:
            self.send("Browser.close", timeout=5)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        shutil.rmtree(self.profile, ignore_errors=True)


class Page:
    def __init__(self, browser, width, height, mobile):
        self.b = browser
        target = browser.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.target = target
        self.s = browser.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ["Page", "Runtime", "Log", "Network"]:
            self.send(domain + ".enable")
        self.send("Network.emulateNetworkConditions",
                  {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1})
        self.send("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": mobile})
        if mobile:
            self.send("Emulation.setTouchEmulationEnabled", {"enabled": True, "maxTouchPoints": 5})

    def send(self, method, params=None, timeout=30):
        return self.b.send(method, params, self.s, timeout)

    def eval(self, expr):
        r = self.send("Runtime.evaluate",
                      {"expression": expr, "returnByValue": True, "awaitPromise": True})
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expr}: {r['exceptionDetails'].get('exception', {}).get('description', r['exceptionDetails'])}")
        return r["result"].get("value")

    def frames(self, n=2):
        self.eval("new Promise(r => { let k = %d; const f = () => --k ? requestAnimationFrame(f) : r(1); requestAnimationFrame(f); })" % n)

    def wait(self, expr, timeout=20):
        deadline = time.time() + timeout
        while time.time() < deadline:
            try:
                if self.eval(expr):
                    return True
            except RuntimeError:
                pass
            time.sleep(0.05)
        raise TimeoutError("waited in vain for " + expr)

    def mouse(self, kind, x, y, button="left", buttons=0):
        self.send("Input.dispatchMouseEvent",
                  {"type": kind, "x": x, "y": y, "button": button, "buttons": buttons, "clickCount": 1})

    def click(self, x, y):
        self.mouse("mouseMoved", x, y, "none")
        self.mouse("mousePressed", x, y, "left", 1)
        self.mouse("mouseReleased", x, y, "left", 0)

    def tap(self, x, y):
        pt = [{"x": x, "y": y, "id": 1}]
        self.send("Input.dispatchTouchEvent", {"type": "touchStart", "touchPoints": pt})
        self.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})

    def pinch(self, cx, cy, r0, r1):
        """Two fingers from r0 to r1 px either side of (cx, cy)."""
        def points(r):
            return [{"x": cx - r, "y": cy, "id": 1}, {"x": cx + r, "y": cy, "id": 2}]
        self.send("Input.dispatchTouchEvent", {"type": "touchStart", "touchPoints": points(r0)})
        for k in range(1, 9):
            self.send("Input.dispatchTouchEvent", {"type": "touchMove", "touchPoints": points(r0 + (r1 - r0) * k / 8)})
        self.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})

    def wheel(self, x, y, dy):
        self.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": x, "y": y, "deltaX": 0, "deltaY": dy})

    def drag(self, x0, y0, x1, y1):
        self.mouse("mouseMoved", x0, y0, "none")
        self.mouse("mousePressed", x0, y0, "left", 1)
        for k in range(1, 9):
            t = k / 8
            self.mouse("mouseMoved", x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, "left", 1)
        self.mouse("mouseReleased", x1, y1, "left", 0)

    def key(self, name):
        codes = {"ArrowLeft": 37, "ArrowRight": 39, "Enter": 13, "Escape": 27}
        for kind in ["rawKeyDown", "keyUp"]:
            self.send("Input.dispatchKeyEvent",
                      {"type": kind, "key": name, "code": name,
                       "windowsVirtualKeyCode": codes.get(name, 0)})

    def shot(self, path):
        self.frames(2)
        data = self.send("Page.captureScreenshot", {"format": "png"})["data"]
        os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))
        return path


def run_page(browser, spec):
    w, h = spec.get("viewport", [1280, 800])
    page = Page(browser, w, h, spec.get("mobile", False))
    page.send("Page.navigate", {"url": spec["url"]})
    page.wait("window.karigami && window.karigami.ready")
    results = []
    for action in spec.get("actions", []):
        (kind, arg), = action.items()
        if kind == "eval":
            results.append(page.eval(arg))
        elif kind in ("click", "tap"):
            x, y = page.eval(arg)
            (page.click if kind == "click" else page.tap)(x, y)
            page.frames(2)
            results.append([x, y])
        elif kind in ("pinch", "wheel"):
            getattr(page, kind)(*arg)
            page.frames(2)
            results.append(None)
        elif kind == "drag":
            page.drag(*arg)
            page.frames(2)
            results.append(None)
        elif kind == "key":
            page.key(arg)
            page.frames(1)
            results.append(None)
        elif kind == "type":
            page.send("Input.insertText", {"text": arg})
            page.frames(1)
            results.append(None)
        elif kind == "wait":
            results.append(page.wait(arg))
        elif kind == "shot":
            results.append(page.shot(arg))
        else:
            raise ValueError("unknown action " + kind)
    page.frames(2)
    out = {"url": spec["url"], "results": results, "console_errors": [], "warnings": [], "exceptions": [],
           "failed_requests": [], "requests": []}
    for e in browser.events:
        if e.get("sessionId") != page.s:
            continue
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            out["console_errors"].append(" ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", [])))
        elif m == "Log.entryAdded" and p["entry"].get("level") == "error":
            out["console_errors"].append(p["entry"].get("text", ""))
        elif m == "Log.entryAdded" and p["entry"].get("level") == "warning":
            out["warnings"].append(p["entry"].get("text", ""))
        elif m == "Runtime.consoleAPICalled" and p.get("type") == "warning":
            out["warnings"].append(" ".join(str(a.get("value", "")) for a in p.get("args", [])))
        elif m == "Runtime.exceptionThrown":
            d = p["exceptionDetails"]
            out["exceptions"].append(d.get("exception", {}).get("description", d.get("text", "")))
        elif m == "Network.loadingFailed":
            out["failed_requests"].append(p.get("errorText", "") + " " + p.get("requestId", ""))
        elif m == "Network.requestWillBeSent":
            out["requests"].append(p["request"]["url"][:200])
    browser.events = [e for e in browser.events if e.get("sessionId") != page.s]
    browser.send("Target.closeTarget", {"targetId": page.target})
    return out


def main():
    plan = json.load(sys.stdin)
    exe = plan.get("chromium") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not exe:
        print("chromium not found", file=sys.stderr)
        sys.exit(3)
    browser = Browser(exe)
    try:
        version = browser.send("Browser.getVersion")
        report = {"browser": version.get("product"), "pages": [run_page(browser, p) for p in plan["pages"]]}
    finally:
        browser.close()
    json.dump(report, sys.stdout)


if __name__ == "__main__":
    main()
