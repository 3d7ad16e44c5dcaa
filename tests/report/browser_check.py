#!/usr/bin/env python3
"""Opens plumb HTML reports in Debian's Chromium (driven by Playwright) and checks them.

For each report: no console errors, no network request of any kind (only file: and data:
URLs are allowed; anything else is blocked and counted), every chart drawn with marks on
its canvas, every picture decoded, and every chart showing all its data: each point the
page carries is one Chart.js drew (none skipped), and lies inside the axes' range as the
live chart laid them out. A full-page screenshot is saved beside it as a test
artifact.

Usage: browser_check.py REPORT.html [REPORT.html ...]   (exit 0 all good, 1 a check failed)
"""
import json
import os
import sys
import tempfile

from playwright.sync_api import sync_playwright

CHROMIUM = os.environ.get("PLUMB_CHROMIUM", "/usr/bin/chromium")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--no-first-run"]
LOCAL = ("file:", "data:", "about:", "blob:")

# Per chart: the marks Chart.js laid out, and whether its canvas holds any painted pixel.
CHARTS = """() => window.plumbReport.charts.map((c) => {
  let marks = 0;
  c.data.datasets.forEach((d, i) => { marks += c.getDatasetMeta(i).data.length; });
  const ctx = c.canvas.getContext('2d');
  const px = ctx.getImageData(0, 0, c.canvas.width, c.canvas.height).data;
  let painted = 0;
  for (let i = 3; i < px.length; i += 4) if (px[i] !== 0) painted++;
  return { id: c.canvas.id, title: c.canvas.previousElementSibling ?
             c.canvas.previousElementSibling.textContent : '', marks, painted };
})"""
# Per x-y chart (live Chart.js instances): the points the page's data carries against those
# drawn, and every point outside the axes' range (up to a few, with the range).
OUTSIDE = """() => {
  const specs = JSON.parse(document.getElementById('plumb-charts').textContent);
  return window.plumbReport.charts.map((c, k) => {
    const spec = specs[k];
    const out = { id: c.canvas.id, kind: spec.kind, carried: 0, drawn: 0, outside: [] };
    if (spec.kind !== 'xy') return out;
    const x = c.scales.x, y = c.scales.y;
    out.range = [x.min, x.max, y.min, y.max];
    spec.series.forEach((s) => { out.carried += s.points.length; });
    c.data.datasets.forEach((d, i) => {
      const meta = c.getDatasetMeta(i), ctl = meta.controller;
      const start = ctl._drawStart || 0;
      const count = ctl._drawCount === undefined ? meta.data.length - start : ctl._drawCount;
      out.drawn += Math.min(count, meta.data.length - start);
      d.data.forEach((p) => {
        if (p.x < x.min || p.x > x.max || p.y < y.min || p.y > y.max) {
          if (out.outside.length < 5) out.outside.push([d.label, p.x, p.y]);
          else out.outside.push(null);
        }
      });
    });
    return out;
  });
}"""
PAGE = """() => ({
  canvases: document.querySelectorAll('canvas.plumb-chart').length,
  images: Array.from(document.images).map((i) => ({ alt: i.alt, ok: i.complete && i.naturalWidth > 0 })),
  tables: document.querySelectorAll('table').length,
  thumbnails: document.querySelectorAll('img.thumb').length,
})"""


def check(context, path):
    problems = []
    page = context.new_page()
    errors, requests = [], []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))

    def route(r):
        if r.request.url.startswith(LOCAL):
            r.continue_()
        else:
            requests.append(r.request.url)
            r.abort()

    page.route("**/*", route)
    page.on("request", lambda r: None if r.url.startswith(LOCAL) else requests.append(r.url))
    page.goto("file://" + os.path.abspath(path))
    try:
        page.wait_for_function("window.plumbReport && window.plumbReport.ready", timeout=60000)
    except Exception as e:  # noqa: BLE001 - said in the problem list
        problems.append(f"the page never said it was ready: {e}")
    page.wait_for_timeout(300)
    charts = page.evaluate(CHARTS) if not problems else []
    coverage = page.evaluate(OUTSIDE) if not problems else []
    info = page.evaluate(PAGE)
    shot = os.path.splitext(path)[0] + ".png"
    page.screenshot(path=shot, full_page=True)
    page.close()

    problems += [f"console error: {e}" for e in errors]
    problems += [f"network request: {u}" for u in sorted(set(requests))]
    if info["canvases"] != len(charts):
        problems.append(f"{info['canvases']} chart canvases but {len(charts)} charts drawn")
    for c in charts:
        if c["marks"] == 0 or c["painted"] == 0:
            problems.append(f"chart {c['id']} ({c['title']!r}) has {c['marks']} marks and "
                            f"{c['painted']} painted pixels")
    for c in coverage:
        if c["kind"] != "xy":
            continue
        if c["drawn"] != c["carried"]:
            problems.append(f"chart {c['id']} draws {c['drawn']} of its {c['carried']} points")
        if c["outside"]:
            shown = [p for p in c["outside"] if p is not None]
            problems.append(f"chart {c['id']}: {len(c['outside'])} points outside its axes "
                            f"x [{c['range'][0]}, {c['range'][1]}], y [{c['range'][2]}, "
                            f"{c['range'][3]}], e.g. {shown}")
    problems += [f"picture not decoded: {i['alt']}" for i in info["images"] if not i["ok"]]
    if info["tables"] == 0:
        problems.append("no table")
    want_thumbnails = os.environ.get("PLUMB_EXPECT_THUMBNAILS", "")
    if os.path.basename(path) in want_thumbnails.split(",") and info["thumbnails"] == 0:
        problems.append("no thumbnail of a highlighted element")
    points = sum(c["carried"] for c in coverage)
    summary = {"report": path, "charts": len(charts), "points": points,
               "pictures": len(info["images"]),
               "thumbnails": info["thumbnails"],
               "screenshot": shot, "problems": problems}
    print(json.dumps(summary))
    return problems


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    if not os.access(CHROMIUM, os.X_OK):
        print(f"browser_check: {CHROMIUM} is missing: apt-get install chromium", file=sys.stderr)
        return 1
    failed = False
    with tempfile.TemporaryDirectory(prefix="plumb-chromium-") as scratch, sync_playwright() as p:
        # Chromium keeps its crash reporter's settings in $XDG_CONFIG_HOME/chromium and more
        # below $HOME: both point into the scratch folder, so the test writes nothing in the
        # user's home (CI lists what a test run writes: scripts/list-created-files.sh)
        home = os.path.join(scratch, "home")
        env = dict(os.environ, HOME=home, XDG_CONFIG_HOME=os.path.join(home, ".config"),
                   XDG_CACHE_HOME=os.path.join(home, ".cache"))
        context = p.chromium.launch_persistent_context(
            os.path.join(scratch, "profile"), executable_path=CHROMIUM, args=FLAGS,
            headless=True, viewport={"width": 1280, "height": 900}, env=env)
        for path in sys.argv[1:]:
            problems = check(context, path) if os.path.isfile(path) else ["no such file"]
            for problem in problems:
                print(f"browser_check: {path}: {problem}", file=sys.stderr)
            failed = failed or bool(problems)
        context.close()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
