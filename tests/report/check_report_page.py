#!/usr/bin/env python3
"""Renders both pages, `gyroflip report`'s and `gyroflip reproduce --quick`'s, in headless
Chromium (issues 10, 22, 31) and checks what a reader would see: a screenshot that is not blank,
every image loaded, no console error, no preformatted text; at 1280 and at 900 px no table that
scrolls sideways and nothing wider than the window; at 700 and 500 px a table may scroll inside
its own box (overflow-x: auto) but nothing else leaves the window, and no caption is cut by its
box nor a column out of view in it; at each width no word broken inside (a line break in
"compensat ed", "18 00 s" or "inconclusiv e": every run of non-blank characters must lie on one
line; only the words marked "brk", paths and hashes longer than any column, may break anywhere,
in the provenance too: "see d 1" and "10013 9" were found there); and the rest of the report folder (summary.json's numbers equal
`calibrate --json`'s, report.pdf is a PDF, each figure has its gnuplot script, data and three
images). Exit 77 (skipped) without chromium.
Usage: check_report_page.py GYROFLIP_EXE
       check_report_page.py --layout PAGE.html...   (the width checks alone, on pages made already)
With GYROFLIP_SCREENSHOTS=DIR set, a screenshot of each page at each width is kept in DIR."""
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib
from html import unescape


def browser():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return name
    return None


def chromium(exe, tmp, *args):
    """Headless Chromium with a fresh profile and nothing that reaches the network."""
    profile = tempfile.mkdtemp(dir=tmp)
    try:
        return subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                               "--disable-dev-shm-usage", "--no-first-run",
                               "--disable-background-networking", "--disable-component-update",
                               "--disable-sync", f"--user-data-dir={profile}", *args],
                              capture_output=True, text=True, timeout=120)
    finally:
        shutil.rmtree(profile, ignore_errors=True)


# Run after the page's layout: each table box that scrolls sideways (its caption and widths), the
# page's own overflow, and each word (a run of non-blank characters in one text node) whose
# pieces lie on more than one line: a line break inside it. Only spans of class "brk" (paths,
# hashes, longer than any column) may break anywhere.
LAYOUT_PROBE = r"""<script>
window.addEventListener('load', () => {
  const d = document.documentElement,
        out = {page: d.scrollWidth - d.clientWidth, height: d.scrollHeight, tables: [], words: [],
               scrolling: [], outside: [], cut: []};
  for (const box of document.querySelectorAll('.tablebox'))
    if (box.scrollWidth > box.clientWidth + 1) {
      const what = (box.querySelector('caption') || box).textContent.slice(0, 90) +
                   ' (' + box.scrollWidth + ' px in ' + box.clientWidth + ')';
      out.tables.push(what);
      // Narrow windows: a table may scroll, but only inside its own box, which scrolls.
      if (getComputedStyle(box).overflowX !== 'auto' ||
          box.getBoundingClientRect().right > d.clientWidth + 1)
        out.outside.push('a table box that does not scroll within the window: ' + what);
      else out.scrolling.push(what);
    }
  // In a box, scrolling or not, the caption is read whole and every column is in view without
  // scrolling (third review of issue 31, M7: at 700 and 500 px a verdict caption was cut by its
  // box and the outcome column lay off-screen in it).
  for (const box of document.querySelectorAll('.tablebox')) {
    const right = box.getBoundingClientRect().left + box.clientWidth + 1;
    const cap = box.querySelector('caption');
    if (cap) {
      const r = document.createRange();
      r.selectNodeContents(cap);
      if ([...r.getClientRects()].some(q => q.width > 0 && q.right > right))
        out.cut.push('a caption cut by its box: ' + cap.textContent.slice(0, 90));
    }
    const row = box.querySelector('tr');
    const last = row && row.lastElementChild;
    if (last && last.getBoundingClientRect().right > right)
      out.cut.push('a column out of view in its box (' + (last.textContent || '').slice(0, 30) +
                   '): ' + (cap ? cap.textContent.slice(0, 90) : ''));
  }
  for (const t of document.querySelectorAll('table'))
    if (t.getBoundingClientRect().right > d.clientWidth + 1) {
      out.tables.push('wider than the window: ' + t.querySelector('caption').textContent.slice(0, 90));
      if (!t.closest('.tablebox'))
        out.outside.push('a table outside a scroll box: ' + t.querySelector('caption').textContent.slice(0, 90));
    }
  // Everything else lies inside the window (review of issue 31, M4: checked at 700 px too).
  for (const el of document.body.querySelectorAll('*')) {
    if (el.closest('.tablebox, script, style') && !el.classList.contains('tablebox')) continue;
    const r = el.getBoundingClientRect();
    if (r.width > 0 && (r.right > d.clientWidth + 1 || r.left < -1))
      out.outside.push(el.tagName.toLowerCase() + (el.className ? '.' + el.className : '') +
                       ' reaches ' + Math.round(r.right) + ' px of ' + d.clientWidth + ': ' +
                       (el.textContent || '').slice(0, 60));
  }
  const walk = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let n = walk.nextNode(); n; n = walk.nextNode()) {
    const el = n.parentElement;
    if (el.closest('.brk, script, style')) continue;
    for (const m of n.textContent.matchAll(/\S+/g)) {
      const r = document.createRange();
      r.setStart(n, m.index);
      r.setEnd(n, m.index + m[0].length);
      const rects = [...r.getClientRects()].filter(q => q.width > 0);
      const lines = rects.filter((q, i) => rects.slice(0, i).every(p => q.top >= p.bottom - 1 || q.bottom <= p.top + 1));
      if (lines.length > 1) out.words.push(m[0]);
    }
  }
  const p = document.createElement('div');
  p.id = 'layout-probe';
  p.textContent = JSON.stringify(out);
  document.body.appendChild(p);
});
</script></body>"""


# Window widths checked, and whether a table may scroll inside its own box there: at 900 px and
# wider no table scrolls; narrower (700 px, a small laptop window or a tablet; 500 px, a phone held
# upright; reviews of issue 31, M4, M7) a table box may scroll, but its caption is never cut and
# every column is in view (the probe's "cut"), and nothing else leaves the window.
WIDTHS = ((1280, False), (900, False), (700, True), (500, True))


def check_layout(exe, tmp, index, width, shots=None, scroll_boxes=False):
    """At a window `width` px wide: no table that scrolls sideways (with `scroll_boxes`, only
    inside its own scrolling box), nothing wider than the window, no word broken inside. Raises
    AssertionError naming each. With `shots`, a screenshot of the whole page at that width is kept
    there. Returns the captions of the tables that scroll in their box."""
    html = open(index, encoding="utf-8").read()
    probe = os.path.join(os.path.dirname(index), f"probe{width}.html")
    open(probe, "w", encoding="utf-8").write(html.replace("</body>", LAYOUT_PROBE))
    try:
        dom = chromium(exe, tmp, f"--window-size={width},1000", "--virtual-time-budget=10000",
                       "--run-all-compositor-stages-before-draw", "--dump-dom", "file://" + probe).stdout
    finally:
        os.remove(probe)
    start = dom.find('<div id="layout-probe">')
    assert start >= 0, f"the layout probe did not run at {width} px: {dom[-300:]}"
    found = json.loads(unescape(dom[start + len('<div id="layout-probe">'):dom.index("</div>", start)]))
    problems = [] if scroll_boxes else [f"a table scrolls sideways: {t}" for t in found["tables"]]
    problems += found["outside"] + found["cut"]
    if found["page"] > 0:
        problems.append(f"the page is {found['page']} px wider than the window")
    problems += [f"a word is broken across lines: {w!r}" for w in found["words"]]
    if shots:
        name = os.path.basename(os.path.dirname(index)) or "page"
        height = max(1000, min(30000, found["height"]))
        chromium(exe, tmp, f"--window-size={width},{height}", "--virtual-time-budget=10000",
                 f"--screenshot={os.path.join(shots, f'{name}_{width}.png')}", "file://" + index)
    assert not problems, f"{index} at {width} px:\n  " + "\n  ".join(problems)
    return found["scrolling"]


def png_busy_fraction(path):
    """The fraction of the screenshot's raw (filtered) bytes that differ from the most common
    byte: ~0 for a blank page."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if kind == b"IDAT":
            idat += data[pos + 8:pos + 8 + n]
        pos += 12 + n
    raw = zlib.decompress(idat)
    counts = [0] * 256
    for b in raw[::7]:
        counts[b] += 1
    return 1.0 - max(counts) / sum(counts)


def check_page(exe, tmp, index, images):
    """The page in Chromium: every image loaded, no console message, nothing wider than the
    window, a screenshot that is not blank. Returns the screenshot's busy fraction."""
    html = open(index, encoding="utf-8").read()
    assert "http://" not in html and "https://" not in html, "the page must need no network"
    assert "<pre" not in html, "tables, not preformatted text"
    assert html.count("<img") == images, html.count("<img")

    # Every image loaded and no overflow: a copy of the page with a script that counts the
    # broken images and compares the page's width with the window's (900 px: a narrow one).
    probe = os.path.join(os.path.dirname(index), "probe.html")
    open(probe, "w", encoding="utf-8").write(html.replace(
        "</body>", "<script>window.addEventListener('load', () => { const d = document.documentElement; "
        "document.title = 'broken=' + [...document.images].filter(i => !i.complete || i.naturalWidth === 0)"
        ".length + ' of ' + document.images.length + ' overflow=' + (d.scrollWidth > d.clientWidth); "
        "});</script></body>"))
    dom = chromium(exe, tmp, "--window-size=900,1200", "--virtual-time-budget=5000", "--dump-dom",
                   "file://" + probe).stdout
    want = f"<title>broken=0 of {images} overflow=false</title>"
    assert want in dom, dom[:300]
    os.remove(probe)

    # The page itself: no console message of any kind, and a screenshot that is not blank.
    shot = os.path.join(tmp, "shot.png")
    r = chromium(exe, tmp, "--enable-logging=stderr", "--v=0", "--window-size=1200,2400",
                 f"--screenshot={shot}", "file://" + index)
    console = [line for line in r.stderr.splitlines() if ":CONSOLE" in line]
    assert r.returncode == 0 and not console, console or r.stderr[-500:]
    busy = png_busy_fraction(shot)
    assert busy > 0.01, f"the screenshot is blank ({busy:.4f}; a blank page gives 0.0003)"

    # At a laptop's width and at a narrow window's (review of issue 31: tables scrolled at both).
    for width, scroll_boxes in WIDTHS:
        check_layout(exe, tmp, index, width, os.environ.get("GYROFLIP_SCREENSHOTS"), scroll_boxes)
    return busy


def main():
    exe = browser()
    if exe is None:
        print("chromium not installed: skipped")
        return 77
    if sys.argv[1] == "--layout":
        failed = 0
        with tempfile.TemporaryDirectory() as tmp:
            for page in sys.argv[2:]:
                for width, scroll_boxes in WIDTHS:
                    try:
                        scrolled = check_layout(exe, tmp, os.path.abspath(page), width,
                                                os.environ.get("GYROFLIP_SCREENSHOTS"),
                                                scroll_boxes)
                        print(f"{page} at {width} px: ok" +
                              "".join(f"\n  scrolls in its box: {t}" for t in scrolled))
                    except AssertionError as e:
                        failed += 1
                        print(e)
        return 1 if failed else 0
    gf = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory() as tmp:
        def run(*args):
            subprocess.run([gf, *args], check=True, cwd=tmp, capture_output=True, text=True)
        run("simulate", "--sensor", "hz1-90-100a", "--duration", "900", "--temp", "20", "--seed", "1", "-o", "c20.csv")
        run("simulate", "--sensor", "hz1-90-100a", "--duration", "900", "--temp", "4", "--seed", "2", "-o", "c4.csv")
        run("report", "c20.csv", "c4.csv", "--latitude", "42.6", "--axis", "north", "-o", "rep", "--title", "Test report")
        rep = os.path.join(tmp, "rep")
        busy = check_page(exe, tmp, os.path.join(rep, "index.html"), 10)  # 2 summary + 4 per run

        # The rest of the folder.
        assert open(os.path.join(rep, "report.pdf"), "rb").read(5) == b"%PDF-"
        summary = json.load(open(os.path.join(rep, "summary.json")))
        cal = json.loads(subprocess.run([gf, "calibrate", "c20.csv", "--json"], cwd=tmp, check=True,
                                        capture_output=True, text=True).stdout)
        assert summary["runs"][0]["delta_n_dps"] == cal["delta_n_dps"]
        assert summary["runs"][0]["stderr_correlated_dps"] == cal["stderr_correlated_dps"]
        assert len(summary["runs"][0]["sha256"]) == 64
        figs = os.listdir(os.path.join(rep, "figures"))
        for stem in ("delta_n_runs", "delta_n_temperature", "run1_dwells", "run1_compensated",
                     "run1_bias", "run1_allan", "run2_allan"):
            for ext in (".gp", ".png", ".svg", ".pdf", "_1.dat"):
                assert stem + ext in figs, stem + ext
        assert not [f for f in os.listdir(tmp) if f.startswith(".rep")], "a staging folder was left"
        print(f"report page ok: 10 images loaded, no console message, screenshot {busy:.2f} busy")

        # The reproduction's page: 3 tables + 8 figures + 4 Allan plots.
        run("reproduce", "--quick", "-o", "repro")
        busy = check_page(exe, tmp, os.path.join(tmp, "repro", "index.html"), 15)
        assert open(os.path.join(tmp, "repro", "report.pdf"), "rb").read(5) == b"%PDF-"
        print(f"reproduce page ok: 15 images loaded, no console message, screenshot {busy:.2f} busy")
    return 0


if __name__ == "__main__":
    sys.exit(main())
