"""Opens a pcbench page (index.html) in headless Chromium and checks it as a reader sees it.

    page_check.py INDEX.html REPORT.json [--screenshot PNG]

Chromium (Debian's /usr/bin/chromium) is driven over the DevTools protocol on a pipe
(--remote-debugging-pipe: JSON messages ending in NUL on file descriptors 3 and 4), so nothing
beyond Debian's packages is needed. Fails (exit 1) when the page logs a console error or throws,
when an image does not decode, or when its table of runs differs from the report: the same run
ids in the same order, each with the report's status and verdict; or when the answer at the top
differs from the report: the verdict matrix must hold a row per estimator (with its own
parameters) and one cell per run, with its verdict and its
efficiency relative to the first honest run on its integrand (recomputed here from the report),
and the maps of tiles that differ must mark exactly the tiles the report's tile comparisons list.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

CHROMIUM_FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--remote-debugging-pipe", "about:blank",
]


class DevTools:
    """A minimal DevTools client: numbered commands, events collected while waiting."""

    def __init__(self, chromium="/usr/bin/chromium"):
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        self._profile = tempfile.TemporaryDirectory()

        def child_fds():  # the protocol's fixed descriptors: 3 reads commands, 4 writes replies
            # Copies first: dup2 onto 3 could otherwise close the other pipe end if it is 3.
            commands, replies = os.dup(to_browser_r), os.dup(from_browser_w)
            os.dup2(commands, 3)
            os.dup2(replies, 4)

        # close_fds=False: subprocess would close 3 and 4 after child_fds() made them.
        self._process = subprocess.Popen(
            [chromium, f"--user-data-dir={self._profile.name}"] + CHROMIUM_FLAGS,
            preexec_fn=child_fds, close_fds=False, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._buffer = b""
        self._next_id = 0
        self.events = []

    def _read_message(self):
        while b"\0" not in self._buffer:
            chunk = os.read(self._from_browser, 1 << 16)
            if not chunk:
                raise RuntimeError("chromium closed the DevTools pipe")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def send(self, method, session=None, **params):
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        while True:
            reply = self._read_message()
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_for(self, method):
        for event in self.events:
            if event.get("method") == method:
                return event
        while True:
            event = self._read_message()
            self.events.append(event)
            if event.get("method") == method:
                return event

    def close(self):
        try:
            self.send("Browser.close")
        except (RuntimeError, OSError):
            pass
        try:
            self._process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._process.kill()
        self._profile.cleanup()


# Run in the page: what a reader sees of the table and the images.
READ_PAGE = """JSON.stringify({
  rows: [...document.querySelectorAll('#runs tbody tr[data-run-id]')].map(tr => ({
    id: tr.dataset.runId,
    status: tr.querySelector('td.status').dataset.status,
    verdict: tr.querySelector('td.verdict').dataset.verdict})),
  matrix: [...document.querySelectorAll('#matrix td[data-run-id]')].map(td => ({
    id: td.dataset.runId, verdict: td.dataset.verdict, relative: td.dataset.relative,
    top: td.getBoundingClientRect().top + window.scrollY})),
  matrixRows: document.querySelectorAll('#matrix tbody tr').length,
  runsTop: document.getElementById('runs-heading').getBoundingClientRect().top + window.scrollY,
  tiles: [...document.querySelectorAll('.tilemap')].map(m => ({
    integrand: m.dataset.integrand,
    marked: [...m.querySelectorAll('[data-tile]')].map(t => [t.dataset.tile, t.className])})),
  images: [...document.images].map(img => ({ok: img.complete && img.naturalWidth > 0,
                                             alt: img.alt})),
  title: document.title})"""


def problems_in(events):
    found = []
    for e in events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.exceptionThrown":
            found.append("exception: " + params["exceptionDetails"].get("text", ""))
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            found.append("console error: " + json.dumps(params.get("args"))[:300])
        elif method == "Log.entryAdded" and params["entry"].get("level") == "error":
            found.append("log error: " + params["entry"].get("text", ""))
    return found


def check_page(index, report_path, screenshot=None, section=None):
    with open(report_path, encoding="utf-8") as f:
        report = json.load(f)
    browser = DevTools()
    try:
        target = browser.send("Target.createTarget", url="about:blank")["targetId"]
        session = browser.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            browser.send(f"{domain}.enable", session=session)
        browser.send("Page.navigate", session=session, url="file://" + os.path.abspath(index))
        browser.wait_for("Page.loadEventFired")
        seen = json.loads(browser.send("Runtime.evaluate", session=session, expression=READ_PAGE,
                                       returnByValue=True)["result"]["value"])
        if screenshot:
            import base64
            metrics = browser.send("Page.getLayoutMetrics", session=session)["cssContentSize"]
            top = 0
            if section:  # start at a heading of the page (its id) rather than at the top
                top = browser.send(
                    "Runtime.evaluate", session=session, returnByValue=True,
                    expression=f"document.getElementById({json.dumps(section)})"
                               ".getBoundingClientRect().top + window.scrollY")["result"]["value"]
            shot = browser.send("Page.captureScreenshot", session=session, format="png",
                                captureBeyondViewport=True,
                                clip={"x": 0, "y": top, "width": metrics["width"],
                                      "height": min(metrics["height"] - top, 4000), "scale": 1})
            with open(screenshot, "wb") as f:
                f.write(base64.b64decode(shot["data"]))
        failures = problems_in(browser.events)
    finally:
        browser.close()

    expected = [{"id": r["id"], "status": r["status"],
                 "verdict": (r.get("verdict") or {}).get("result") or ""}
                for r in report.get("runs") or []]
    if seen["rows"] != expected:
        failures.append(f"table differs from the report: page {seen['rows'][:3]}... "
                        f"({len(seen['rows'])} rows), report {expected[:3]}... "
                        f"({len(expected)} runs)")
    failures += matrix_problems(report, seen)
    broken = [img["alt"] for img in seen["images"] if not img["ok"]]
    if broken:
        failures.append(f"{len(broken)} images did not decode: {broken[:3]}")
    return failures, seen


def expected_relative(report):
    """{run id: efficiency / the efficiency of the first run on the same integrand (and integrand
    parameters) that is not expected biased and has one}; None where there is none."""
    def eff(run):
        source = run.get("image") if isinstance(run.get("image"), dict) else run.get("aggregates")
        value = (source or {}).get("efficiency")
        return value if isinstance(value, (int, float)) and value > 0 else None

    out, baselines = {}, {}
    runs = report.get("runs") or []
    for run in runs:
        key = (run["integrand"], json.dumps(run.get("integrand_params") or {}, sort_keys=True))
        if key not in baselines:
            baselines[key] = None
        if (baselines[key] is None and eff(run) is not None and
                (run.get("verdict") or {}).get("expect") != "biased"):
            baselines[key] = eff(run)
    for run in runs:
        key = (run["integrand"], json.dumps(run.get("integrand_params") or {}, sort_keys=True))
        base = baselines[key]
        out[run["id"]] = eff(run) / base if base and eff(run) is not None else None
    return out


def matrix_problems(report, seen):
    found = []
    runs = report.get("runs") or []
    cells = {c["id"]: c for c in seen["matrix"]}
    if sorted(cells) != sorted(r["id"] for r in runs) or len(seen["matrix"]) != len(runs):
        found.append(f"the matrix has {len(seen['matrix'])} cells for {len(runs)} runs")
    # A row per estimator and its own parameters (not its integrand's: the columns hold those).
    estimators = {(r["estimator"], json.dumps({k: v for k, v in (r.get("params") or {}).items()
                                                if k not in (r.get("integrand_params") or {})},
                                               sort_keys=True)) for r in runs}
    if runs and seen["matrixRows"] != len(estimators):
        found.append(f"the matrix has {seen['matrixRows']} rows for {len(estimators)} estimators")
    relative = expected_relative(report)
    for run in runs:
        cell = cells.get(run["id"])
        if cell is None:
            continue
        verdict = (run.get("verdict") or {}).get("result") or ""
        if cell["verdict"] != verdict:
            found.append(f"matrix cell {run['id']}: verdict {cell['verdict']!r}, report {verdict!r}")
        want, got = relative[run["id"]], cell["relative"]
        if (want is None) != (got == "") or (want is not None and
                                              abs(float(got) - want) > 1e-9 * abs(want)):
            found.append(f"matrix cell {run['id']}: relative efficiency {got!r}, report {want}")
        if cell["top"] > seen["runsTop"]:
            found.append("the matrix is not above the table of runs")
    # The tile maps: per integrand, the tiles the report's tile comparisons list as differing.
    want_tiles = {}
    for c in report.get("comparisons") or []:
        if c.get("tile_columns") is None or c["a"].endswith("+injected"):
            continue
        marks = want_tiles.setdefault(c["integrand"], {})
        for x in range(c["tile_columns"]):
            for y in range(c["tile_rows"]):
                marks.setdefault(f"{x},{y}", "")
        # The finest scale's tiles, and the tiles of the blocks that differ at the coarsest scale.
        tiles = {(x, y) for x, y, _ in c["tiles_differing"]}
        for scale in c.get("scales") or []:
            if scale["block"] == c.get("coarsest_differing_block"):
                per = scale["block"] // c["scales"][0]["block"]
                tiles |= {(x, y) for bx, by, _ in scale["blocks_differing"]
                          for x in range(bx * per, min((bx + 1) * per, c["tile_columns"]))
                          for y in range(by * per, min((by + 1) * per, c["tile_rows"]))}
        for x, y in tiles:
            kind = "expected" if c["expect"] == "biased" else "unexpected"
            if marks[f"{x},{y}"] != "unexpected":
                marks[f"{x},{y}"] = kind
    got_tiles = {m["integrand"]: dict(m["marked"]) for m in seen["tiles"]}
    if got_tiles != want_tiles:
        found.append(f"the tile maps differ from the report's tiles_differing: page "
                     f"{str(got_tiles)[:200]}, report {str(want_tiles)[:200]}")
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("index")
    parser.add_argument("report")
    parser.add_argument("--screenshot", help="write a PNG of the page (at most 4000 px tall)")
    parser.add_argument("--section", help="with --screenshot: start at the heading with this id")
    args = parser.parse_args()
    failures, seen = check_page(args.index, args.report, args.screenshot, args.section)
    for failure in failures:
        print("FAILED  " + failure)
    print(f"{args.index}: {len(seen['rows'])} rows, {len(seen['images'])} images, "
          f"{len(failures)} problems")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
