"""The HTML report in headless Chromium: it loads without console errors, its formulas are
MathML that the browser lays out, and the trajectory player draws and moves the ball exactly
as funnel.motion does.

Run by ctest as `report_browser` (python/CMakeLists.txt):

    report_in_browser.py --funnel build/funnel [--keep DIR]

It makes `funnel paper --quick --only fig08,fig10` in a temporary directory (or DIR), opens
index.html in Chromium through the DevTools protocol over a pipe (--remote-debugging-pipe: only
the standard library is needed) and checks the page. Exit status 0 when every check passes,
1 when one fails, 77 (skipped, with a message) when Chromium is not installed.
"""

import argparse
import base64
import io
import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SKIP = 77
TIMEOUT = 60.0  # seconds for any one step of the browser
CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--disable-extensions", "--mute-audio", "--hide-scrollbars", "--window-size=1200,900")


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


class Browser:
    """Chromium with the DevTools protocol on file descriptors 3 (commands) and 4 (replies);
    messages are JSON texts ended by a NUL byte."""

    def __init__(self, binary, profile):
        to_chrome_r, self._to_chrome = os.pipe()
        self._from_chrome, from_chrome_w = os.pipe()

        def child_fds():  # the pipe ends become fds 3 and 4 in the browser (inheritable)
            a, b = os.dup(to_chrome_r), os.dup(from_chrome_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self._log = tempfile.TemporaryFile()  # a file, not a pipe: a chatty browser cannot block on it
        self.proc = subprocess.Popen([binary, *CHROMIUM_FLAGS, f"--user-data-dir={profile}",
                                      "--remote-debugging-pipe", "about:blank"],
                                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=self._log,
                                     preexec_fn=child_fds, close_fds=False)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._buffer = b""
        self._next_id = 0
        self.events = []

    def _receive(self, deadline):
        while b"\0" not in self._buffer:
            ready, _, _ = select.select([self._from_chrome], [], [], max(0.0, deadline - time.monotonic()))
            if not ready:
                raise TimeoutError("no answer from Chromium")
            chunk = os.read(self._from_chrome, 1 << 20)
            if not chunk:
                self._log.seek(0)
                raise EOFError("Chromium closed the DevTools pipe: " + self._log.read(4000).decode(errors="replace"))
            self._buffer += chunk
        raw, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(raw)

    def call(self, method, params=None, session=None):
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._to_chrome, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + TIMEOUT
        while True:
            reply = self._receive(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_for(self, method):
        deadline = time.monotonic() + TIMEOUT
        for i, event in enumerate(self.events):
            if event.get("method") == method:
                return self.events.pop(i)
        while True:
            event = self._receive(deadline)
            if event.get("method") == method:
                return event
            self.events.append(event)

    def close(self):
        try:
            self.call("Browser.close")
            self.proc.wait(timeout=10)
        except Exception:
            self.proc.kill()
            self.proc.wait()
        os.close(self._to_chrome)
        os.close(self._from_chrome)
        self._log.close()


def page_errors(events):
    """Console errors and uncaught exceptions among the DevTools events."""
    errors = []
    for event in events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Runtime.exceptionThrown":
            details = params.get("exceptionDetails", {})
            errors.append("exception: " + details.get("exception", {}).get("description", details.get("text", "")))
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            errors.append("console.error: " + " ".join(str(a.get("value", a.get("description"))) for a in params["args"]))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            errors.append("log: " + params["entry"].get("text", ""))
    return errors


def distinct_colours(png_bytes):
    """The number of distinct RGB colours of a PNG image, and its pixel array."""
    from matplotlib.image import imread
    pixels = imread(io.BytesIO(png_bytes), format="png")[..., :3]
    return len({tuple(p) for p in (pixels.reshape(-1, 3) * 255).astype(int).tolist()}), pixels


def contact_cases():
    """(geometry, events) with a sustained face contact (simulated) and with an edge contact
    (synthetic: a quarter turn about the right edge point at constant speed)."""
    import math
    import numpy as np
    import funnel
    r = funnel.simulate(release=0.5, theta=30.0, e=0.3, events=True)
    assert "contact_start" in set(r["events"]["kind"])
    cases = [(dict(funnel.geometry(theta=30.0), release=0.5), r["events"])]
    g = dict(funnel.geometry(theta=50.0), release=0.0)
    ex, ey, a, w = g["half_gap"], g["y_bottom"], g["radius"], 2.0
    angles = (math.pi / 2, 0.0)
    at = [(ex + a * math.cos(t), ey + a * math.sin(t)) for t in angles]
    vel = [(a * w * math.sin(t), -a * w * math.cos(t)) for t in angles]
    y0 = g["y_release"]
    t_fall = math.sqrt(2 * (y0 - at[0][1]))
    ev = {"time": [t_fall, t_fall, t_fall + math.pi / 4, t_fall + math.pi / 4 + 0.05],
          "kind": ["face", "edge_contact_start", "edge_contact_end", "exit"], "wall": ["right"] * 3 + ["none"],
          "x": [at[0][0], at[0][0], at[1][0], at[1][0]], "y": [at[0][1], at[0][1], at[1][1], at[1][1] - 0.01],
          "u_before": [0.0, 0.0, vel[1][0], 0.0], "v_before": [-t_fall, vel[0][1], vel[1][1], 0.0],
          "omega_before": [0.0, 5.0, 9.0, 9.0], "u_after": [0.0, vel[0][0], vel[1][0], 0.0],
          "v_after": [vel[0][1], vel[0][1], vel[1][1], 0.0], "omega_after": [5.0, 5.0, 9.0, 9.0]}
    g["release"] = at[0][0] / g["half_width"]
    cases.append((g, {k: np.array(v) for k, v in ev.items()}))
    return cases


def check(outdir, binary, failures):
    import numpy as np
    from funnel import motion
    from funnel.plot import _panel_rows, load_figure
    profile = tempfile.mkdtemp(prefix="funnel-chromium-")
    browser = Browser(binary, profile)
    try:
        target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Page"):
            browser.call(f"{domain}.enable", session=session)
        browser.call("Page.navigate", {"url": (outdir / "index.html").resolve().as_uri()}, session=session)
        browser.wait_for("Page.loadEventFired")

        def js(expression):
            result = browser.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                       "awaitPromise": True}, session=session)
            if "exceptionDetails" in result:
                raise RuntimeError(f"{expression}: {result['exceptionDetails']}")
            return result["result"].get("value")

        # Formulas: MathML elements that the browser knows and lays out.
        maths = js("""(() => { const m = [...document.querySelectorAll('math')];
            return {count: m.length, mathml: m.every(e => e instanceof MathMLElement),
                    laid_out: m.filter(e => e.getBoundingClientRect().width > 0).length,
                    raw: document.body.innerText.includes('x_c/L') || document.body.innerText.includes('$')}; })()""")
        print(f"report_in_browser: {maths['count']} formulas, {maths['laid_out']} laid out")
        if maths["count"] < 10 or not maths["mathml"] or maths["laid_out"] < maths["count"] // 2 or maths["raw"]:
            failures.append(f"formulas are not rendered as MathML: {maths}")

        # The player: it draws at once, and the ball moves when the slider moves.
        players = js("Object.keys(window.funnelPlayers || {})")
        if players != ["fig08"]:
            failures.append(f"expected one player, for fig08; found {players}")
            return
        rect = js("""(() => { const c = document.querySelector('#player-fig08 canvas');
            c.scrollIntoView(); const r = c.getBoundingClientRect();
            return {x: r.x + window.scrollX, y: r.y + window.scrollY, width: r.width, height: r.height}; })()""")

        def shot():
            clip = dict(rect, scale=1)
            data = browser.call("Page.captureScreenshot", {"format": "png", "clip": clip,
                                                           "captureBeyondViewport": True}, session=session)["data"]
            return distinct_colours(base64.b64decode(data))

        colours0, pixels0 = shot()
        js("""(() => { const r = document.querySelector('#player-fig08 input[type=range]');
            r.value = '5000'; r.dispatchEvent(new Event('input')); })()""")
        colours1, pixels1 = shot()
        changed = float(np.mean(np.any(np.abs(pixels1 - pixels0) > 0.02, axis=-1)))
        print(f"report_in_browser: canvas {rect['width']:.0f}x{rect['height']:.0f} px, {colours0} colours at t = 0, "
              f"{100 * changed:.2f}% of the pixels changed at mid-time")
        if rect["width"] < 300 or colours0 < 20 or colours1 < 20:
            failures.append(f"the player's canvas is blank or tiny: {rect}, {colours0} and {colours1} colours")
        if changed < 0.001:
            failures.append("moving the time slider did not change the picture")
        t_before = js("window.funnelPlayers.fig08.t")
        js("document.querySelector('#player-fig08 button').click()")  # play for a moment, then pause
        time.sleep(0.5)
        js("document.querySelector('#player-fig08 button').click()")
        t_played = js("window.funnelPlayers.fig08.t")
        if not t_played > t_before + 0.2:
            failures.append(f"playing did not advance the time: t = {t_before} before, {t_played} after")

        # The JavaScript motion is that of funnel.motion, from the figure's own data.
        meta, columns = load_figure(outdir / "fig08")
        worst = 0.0
        for i, panel in enumerate(meta["panels"]):
            rows = _panel_rows(columns, panel["id"])
            times = np.linspace(0.0, float(rows["time"][-1]), 41)
            ref = np.stack(motion.state_at(meta["geometry"][panel["id"]], rows, times), axis=1)
            got = np.array(js(f"[{','.join(repr(float(t)) for t in times)}].map(t => "
                              f"window.funnelPlayers.fig08.stateAt({i}, t))"))
            worst = max(worst, float(np.max(np.abs(got - ref) / (1.0 + np.abs(ref)))))
        # ... also for sustained contacts along a face and arcs about an edge point.
        for g, ev in contact_cases():
            times = np.linspace(0.0, float(ev["time"][-1]), 61)
            ref = np.stack(motion.state_at(g, ev, times), axis=1)
            data = json.dumps({"g": g, "ev": {k: np.asarray(v).tolist() for k, v in ev.items()}})
            got = np.array(js(f"(() => {{ const d = {data}; const s = FunnelPlayer.segments(d.g, d.ev); "
                              f"return {json.dumps(times.tolist())}.map(t => FunnelPlayer.stateAt(s, t)); }})()"))
            worst = max(worst, float(np.max(np.abs(got - ref) / (1.0 + np.abs(ref)))))
        print(f"report_in_browser: player vs funnel.motion.state_at: largest relative difference {worst:.2e}")
        if worst > 1e-9:
            failures.append(f"the player's motion differs from funnel.motion.state_at by {worst:.3g}")
        js("new Promise(r => setTimeout(r, 200))")
        failures.extend(page_errors(browser.events))
    finally:
        browser.close()
        shutil.rmtree(profile, ignore_errors=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--funnel", required=True, help="the funnel binary")
    parser.add_argument("--keep", help="make the report in this directory and keep it")
    args = parser.parse_args(argv)
    binary = find_chromium()
    if binary is None:
        print("report_in_browser: SKIPPED: Chromium is not installed (Debian: apt-get install chromium; "
              "scripts/setup.sh installs it)")
        return SKIP
    outdir = Path(args.keep or tempfile.mkdtemp(prefix="funnel-report-"))
    try:
        proc = subprocess.run([args.funnel, "paper", "--quick", "--only", "fig08,fig10", "--out", str(outdir)],
                              capture_output=True, text=True, timeout=600)
        if proc.returncode != 0 or not (outdir / "index.html").is_file():
            print(f"report_in_browser: funnel paper failed:\n{proc.stderr}")
            return 1
        failures = []
        check(outdir, binary, failures)
    finally:
        if not args.keep:
            shutil.rmtree(outdir, ignore_errors=True)
    for failure in failures:
        print(f"report_in_browser: FAILED: {failure}")
    if not failures:
        print("report_in_browser: the page loads without errors, formulas are MathML, the player draws and plays")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
