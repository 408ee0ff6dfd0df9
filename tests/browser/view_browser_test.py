#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Browser test of graphslam's viewer pages (ctest label `browser`): headless Chromium opens
a page, which must report itself ready with no console error; a screenshot must not be blank
and must show the edges' expected colours where the page says they are; scripted
interaction (zoom, a layer switched off, the iteration slider, a vertex clicked) must change
the picture. Exits 77 (skipped) without Chromium.

  view_browser_test.py PAGE.html [--screenshot OUT.png] [--expect-3d] [--orbit]
"""
import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402

SKIP = 77


def pixels(png):
    try:
        from PIL import Image
        import io
        img = Image.open(io.BytesIO(png)).convert("RGB")
        w, h = img.size
        data = img.tobytes()
        return w, h, [data[y * 3 * w:(y + 1) * 3 * w] for y in range(h)]
    except ImportError:
        return cdp.decode_png(png)


def check_colours(png, samples, left):
    """Fraction of `samples` ({x, y, rgb}) with a pixel near the expected colour within 2 px,
    and the fraction of non-white pixels right of `left` (the drawing)."""
    w, h, rows = pixels(png)
    drawn = total = 0
    for y in range(0, h, 2):
        row = rows[y]
        for x in range(left, w, 2):
            total += 1
            if row[3 * x] < 235 or row[3 * x + 1] < 235 or row[3 * x + 2] < 235:
                drawn += 1
    hits = 0
    for s in samples:
        cx, cy, want = int(round(s["x"])), int(round(s["y"])), s["rgb"]
        found = False
        for y in range(max(0, cy - 2), min(h, cy + 3)):
            for x in range(max(0, cx - 2), min(w, cx + 3)):
                p = rows[y][3 * x:3 * x + 3]
                if sum(abs(p[k] - want[k]) for k in range(3)) <= 60:
                    found = True
        hits += found
    return hits / max(1, len(samples)), drawn / max(1, total)


# In the page: up to 200 visible, non-rejected edges whose midpoints are on screen, with the
# colour the page draws them in (chi2 colouring).
SAMPLE_JS = """(() => {
  const v = window.graphslamView, d = v.data, st = v.state, f = st.frame;
  const out = [], canvas = document.getElementById('view'), r = canvas.getBoundingClientRect();
  if (d.ne === 0 && d.ape) {  // a trajectory: its path in the APE colours
    for (let i = 0; i + 1 < d.nv && out.length < 200; i += Math.max(1, Math.floor(d.nv / 400))) {
      const a = v.screenOf(i), b = v.screenOf(i + 1);
      const x = r.left + 0.5 * (a[0] + b[0]), y = r.top + 0.5 * (a[1] + b[1]);
      if (!(Math.hypot(b[0] - a[0], b[1] - a[1]) > 6) || x < r.left + 5 || y < 5 || x > r.right - 5 || y > r.bottom - 5) continue;
      out.push({x: x, y: y, rgb: GV.apeColor(0.5 * (d.ape[i] + d.ape[i + 1]), d.apeRange).map(Math.round)});
    }
    return out;
  }
  const step = Math.max(1, Math.floor(d.ne / 400));
  for (let k = 0; k < d.ne && out.length < 200; k += step) {
    if (!GV.edgeVisible(d, st, k) || (d.eflag[k] & 11)) continue;
    const a = v.screenOf(d.ea[k]), b = v.screenOf(d.eb[k]);
    const len = Math.hypot(b[0] - a[0], b[1] - a[1]);
    if (!(len > 12)) continue;
    const x = r.left + 0.5 * (a[0] + b[0]), y = r.top + 0.5 * (a[1] + b[1]);
    if (x < r.left + 5 || y < 5 || x > r.right - 5 || y > r.bottom - 5) continue;
    const c = GV.chi2Color(d.frames[f].chi2[k], d.chi2Range).map(Math.round);
    out.push({x: x, y: y, rgb: c});
  }
  return out;
})()"""


class Failure(Exception):
    pass


def expect(cond, what):
    if not cond:
        raise Failure(what)
    print("ok: " + what)


def wait_ready(b, timeout):
    t0 = time.time()
    while time.time() - t0 < timeout:
        if b.evaluate("!!(window.graphslamView && window.graphslamView.ready)"):
            return time.time() - t0
        errs = b.errors()
        if errs:
            raise Failure("errors before the page was ready: " + "; ".join(errs))
        time.sleep(0.05)
    raise Failure("the page did not report ready within %d s" % timeout)


def interact(b, args):
    """The scripted interaction: each step must change the screenshot."""
    shot = b.screenshot()
    canvas = b.evaluate("(() => { const r = document.getElementById('view').getBoundingClientRect();"
                        " return [r.left + r.width / 2, r.top + r.height / 2]; })()")
    b.call("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": canvas[0], "y": canvas[1],
                                        "deltaX": 0, "deltaY": -400})
    time.sleep(0.4)
    b.evaluate("window.graphslamView.redraw()")
    after = b.screenshot()
    expect(after != shot, "zooming with the wheel changes the picture")
    shot = after
    drawn = b.evaluate("window.graphslamView.drawn")
    layer = b.evaluate("""(() => { let boxes = [...document.querySelectorAll('input[id^=layer-kind]')];
      if (!boxes.length) boxes = [...document.querySelectorAll('input[id=layer-truth]')];
      const box = boxes.length > 1 ? boxes[1] : boxes[0]; box.click(); return box.id; })()""")
    b.evaluate("window.graphslamView.redraw()")
    after = b.screenshot()
    expect(after != shot and b.evaluate("window.graphslamView.drawn") < drawn,
           "switching off the layer %s draws less" % layer)
    shot = after
    if args.slider:
        label0 = b.evaluate("document.getElementById('frame-label').textContent")
        b.evaluate("""(() => { const s = document.getElementById('frame'); s.value = '0';
          s.dispatchEvent(new Event('input')); })()""")
        b.evaluate("window.graphslamView.redraw()")
        after = b.screenshot()
        label1 = b.evaluate("document.getElementById('frame-label').textContent")
        expect(after != shot and label0 != label1,
               "the iteration slider shows another frame (%s -> %s)" % (label0, label1))
        shot = after
        b.evaluate("""(() => { const s = document.getElementById('frame'); s.value = s.max;
          s.dispatchEvent(new Event('input')); })()""")
    b.evaluate("window.graphslamView.redraw()")
    shot = b.screenshot()
    target = b.evaluate("""(() => { const v = window.graphslamView, d = v.data;
      const c = document.getElementById('view').getBoundingClientRect();
      for (let i = Math.floor(d.nv / 3); i < d.nv; i++) { const p = v.screenOf(i);
        if (p[0] > 20 && p[1] > 20 && p[0] < c.width - 20 && p[1] < c.height - 20)
          return [c.left + p[0], c.top + p[1], d.vid[i]]; } return null; })()""")
    expect(target is not None, "a vertex is on screen")
    for kind in ("mousePressed", "mouseReleased"):
        b.call("Input.dispatchMouseEvent", {"type": kind, "x": target[0], "y": target[1],
                                            "button": "left", "clickCount": 1})
    b.evaluate("window.graphslamView.redraw()")
    after = b.screenshot()
    info = b.evaluate("window.graphslamView.info()")
    expect(after != shot and info.startswith("vertex ") and "line:" in info,
           "clicking a vertex selects it (%s)" % info.split("\n")[0])
    if args.ape:
        return
    b.evaluate("document.getElementById('layer-vertices').click()")
    edge = b.evaluate("""(() => { const v = window.graphslamView, d = v.data, st = v.state;
      const c = document.getElementById('view').getBoundingClientRect();
      for (let k = 0; k < d.ne; k++) { if (!GV.edgeVisible(d, st, k)) continue;
        const a = v.screenOf(d.ea[k]), b = v.screenOf(d.eb[k]);
        const x = 0.5 * (a[0] + b[0]), y = 0.5 * (a[1] + b[1]);
        if (Math.hypot(b[0] - a[0], b[1] - a[1]) > 4 && x > 20 && y > 20 && x < c.width - 20 &&
            y < c.height - 20) return [c.left + x, c.top + y]; } return null; })()""")
    expect(edge is not None, "an edge is on screen")
    for kind in ("mousePressed", "mouseReleased"):
        b.call("Input.dispatchMouseEvent", {"type": kind, "x": edge[0], "y": edge[1],
                                            "button": "left", "clickCount": 1})
    info = b.evaluate("window.graphslamView.info()")
    expect(info.startswith("edge ") and "chi2: " in info and "line: " in info,
           "clicking an edge shows its tag, chi2 and line (%s)" % " / ".join(info.split("\n")[:3]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("page")
    ap.add_argument("--screenshot", help="save the first screenshot here")
    ap.add_argument("--slider", action="store_true", help="the page has iterations")
    ap.add_argument("--expect-3d", action="store_true")
    ap.add_argument("--expect-rejected", action="store_true")
    ap.add_argument("--canvas", action="store_true", help="the canvas 2D fallback (#canvas)")
    ap.add_argument("--ape", action="store_true", help="a trajectory coloured by APE")
    ap.add_argument("--orbit", action="store_true", help="report the frame time while orbiting")
    ap.add_argument("--timeout", type=float, default=60)
    args = ap.parse_args()
    chromium = cdp.find_chromium()
    if not chromium:
        print("SKIP: no Chromium found (apt-get install chromium, or set GRAPHSLAM_CHROMIUM)")
        return SKIP
    b = cdp.Browser(chromium)
    try:
        t0 = time.time()
        url = "file://" + os.path.abspath(args.page) + ("#canvas" if args.canvas else "")
        b.call("Page.navigate", {"url": url})
        wait = wait_ready(b, args.timeout)
        info = b.evaluate("""(() => { const v = window.graphslamView; return {readyMs: v.readyMs,
          decodeMs: v.decodeMs, renderer: v.renderer, dim: v.data.dim, nv: v.data.nv, ne: v.data.ne,
          rejected: v.data.flagCount.rejected, frames: v.data.frames.length}; })()""")
        print("page ready after %.2f s (script %.0f ms, decode %.0f ms): %s" %
              (time.time() - t0, info["readyMs"], info["decodeMs"], json.dumps(info)))
        want = "canvas" if args.canvas else "webgl"
        expect(info["renderer"] == want, "drawn with " + want)
        expect(info["dim"] == (3 if args.expect_3d else 2), "a %dD graph" % info["dim"])
        if args.expect_rejected:
            expect(info["rejected"] > 0, "%d rejected edges marked" % info["rejected"])
        time.sleep(0.2)
        png = b.screenshot()
        if args.screenshot:
            with open(args.screenshot, "wb") as f:
                f.write(png)
        samples = b.evaluate(SAMPLE_JS)
        left = int(b.evaluate("document.getElementById('view').getBoundingClientRect().left"))
        match, ink = check_colours(png, samples, left)
        expect(ink > 0.01, "the drawing is not blank (%.1f%% of its pixels drawn)" % (100 * ink))
        expect(len(samples) >= 10 and match >= 0.5,
               "%s show their colours where they are (%d of %d sampled)" %
               ("poses (APE)" if args.ape else "edges (chi2)", round(match * len(samples)), len(samples)))
        if args.orbit:
            ms = b.evaluate("""(() => { const v = window.graphslamView; const t = [];
              for (let i = 0; i < 60; i++) { const t0 = performance.now(); v.orbit(6, 1);
                t.push(performance.now() - t0); } t.sort((a, b) => a - b);
              return [t[30], v.frameTimeMs]; })()""")
            print("frame time while orbiting: median %.2f ms (page reports %.2f ms)" % (ms[0], ms[1]))
        interact(b, args)
        errs = b.errors()
        expect(not errs, "no console errors" + ("" if not errs else ": " + "; ".join(errs)))
    except Failure as e:
        print("FAILED: " + str(e))
        return 1
    finally:
        b.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
