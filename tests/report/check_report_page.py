#!/usr/bin/env python3
"""Renders both pages, `gyroflip report`'s and `gyroflip reproduce --quick`'s, in headless
Chromium (issues 10, 22) and checks what a reader would see: a screenshot that is not blank,
every image loaded, no console error, nothing wider than the window (tables stay on the page),
no preformatted text; and the rest of the report folder (summary.json's numbers equal
`calibrate --json`'s, report.pdf is a PDF, each figure has its gnuplot script, data and three
images). Exit 77 (skipped) without chromium.
Usage: check_report_page.py GYROFLIP_EXE"""
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib


def browser():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return name
    return None


def chromium(exe, tmp, *args):
    profile = tempfile.mkdtemp(dir=tmp)
    return subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                           "--no-first-run", "--disable-background-networking",
                           f"--user-data-dir={profile}", *args],
                          capture_output=True, text=True, timeout=120)


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
    return busy


def main():
    gf = os.path.abspath(sys.argv[1])
    exe = browser()
    if exe is None:
        print("chromium not installed: skipped")
        return 77
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
