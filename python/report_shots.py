#!/usr/bin/python3
"""Renders a study report as its readers see it: one headless-Chromium screenshot per section at a
given width, and the page printed to PDF.

    /usr/bin/python3 python/report_shots.py <report.html> <dir> [--width 1400 | --phone] [--no-pdf] [--no-shots]

Writes <dir>/<section>.png (the section alone, full height up to 16000 px) for every
<section id> of the page, <dir>/report.pdf (Chromium's --print-to-pdf, the page's print CSS) and
<dir>/layout.json: the page's height, each section's height, every table, figure or block
that runs past the page's column at this width with its overflow in px (a table cut off at this
width, or scrolled inside its box, is listed), and page_overflow_px / offscreen: how far the page
itself runs past the screen and what runs past it outside a scroll box (a phone's reader loses
those values; it should be 0 and empty at every width, 390 px included), and in_box: captions and row
labels of a table scrolled in its box that leave the box at the scroll's start or end (empty). The report is never modified; the views are
temporary copies with one extra style rule each. --no-shots writes layout.json (and the PDF) only.
--phone renders on an emulated phone instead of a narrowed desktop window: Chromium's own mobile
emulation (a 390 × 844 CSS px screen at 3 device pixels per px, touch, a mobile user agent; the
page's viewport meta tag applies as on a phone) driven through ChromeDriver by Selenium (Debian's
chromium-driver and python3-selenium); layout.json then adds "device" and "viewport" (the layout
viewport's width and the device pixel ratio the page saw: 390 and 3 when the page lays itself out
for the phone, 980 when a page without a viewport tag is zoomed out).
Exit codes: 0 written, 1 Chromium (or ChromeDriver) failed, 2 bad input.
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

MAX_HEIGHT_PX = 16000

# Measures, after load, the page's height and every element wider than the main column: the body
# attribute data-layout holds {"height": h, "overflow": [[tag#id.class, px beyond], ...]}.
MEASURE = """<script>window.addEventListener('load', function () {
  var main = document.querySelector('main') || document.body, right = main.getBoundingClientRect().right, out = [];
  document.querySelectorAll('main table, main figure, main pre, main img').forEach(function (e) {
    var r = e.getBoundingClientRect(), wrap = e.closest('.table-wrap'), clip = 0;
    if (wrap && wrap.scrollWidth > wrap.clientWidth + 1) clip = wrap.scrollWidth - wrap.clientWidth;
    var beyond = Math.max(0, Math.round(r.right - right), clip);
    if (beyond > 0) out.push([e.tagName.toLowerCase() + (e.id ? '#' + e.id : ''), beyond]);
  });
  var sections = {};
  document.querySelectorAll('main > section[id]').forEach(function (s) {
    sections[s.id] = Math.ceil(s.getBoundingClientRect().height);
  });
  // Past the screen itself (the page scrolls sideways: values fall off a phone's screen), apart from
  // what scrolls inside its own box (.table-wrap, pre).
  var vw = Math.min(document.documentElement.clientWidth, document.documentElement.getBoundingClientRect().width),
      offscreen = [];
  document.querySelectorAll('main *, header *').forEach(function (e) {
    if (e.closest('.table-wrap, pre')) return;
    var r = e.getBoundingClientRect();
    if (r.width > 0 && r.right > vw + 1) offscreen.push([e.tagName.toLowerCase() + (e.id ? '#' + e.id : ''),
                                                         Math.round(r.right - vw)]);
    // Text squeezed to nothing (a grid column pushed off by its neighbour) is lost as well.
    else if (/^(DD|P|LI|FIGCAPTION|H[1-3])$/.test(e.tagName) && e.textContent.trim() && r.width < 24)
      offscreen.push([e.tagName.toLowerCase() + ' squeezed', Math.round(r.width)]);
  });
  // A table scrolled in its box keeps its caption and row labels in view (else a phone's reader
  // reads numbers without their row): checked at the box's start and scrolled to its end.
  var inBox = [];
  document.querySelectorAll('main .table-wrap').forEach(function (w) {
    if (w.scrollWidth <= w.clientWidth + 1) return;
    [0, w.scrollWidth].forEach(function (x) {
      w.scrollLeft = x;
      var b = w.getBoundingClientRect();
      w.querySelectorAll('caption, tbody th:first-child, tfoot th:first-child').forEach(function (e) {
        var r = e.getBoundingClientRect(), t = e.closest('table');
        if (r.left < b.left - 1 || r.right > b.right + 1)
          inBox.push([(t.id ? '#' + t.id + ' ' : '') + e.tagName.toLowerCase() + ' "' + e.textContent.trim().slice(0, 30) +
                      '" at scroll ' + (x ? 'end' : 'start'), Math.round(Math.max(b.left - r.left, r.right - b.right))]);
      });
    });
    w.scrollLeft = 0;
  });
  document.body.setAttribute('data-layout', JSON.stringify({height: document.documentElement.scrollHeight, in_box: inBox.slice(0, 50),
                                                           overflow: out, sections: sections,
                                                           page_overflow_px: offscreen.reduce(function (m, x) {
                                                             return /squeezed/.test(x[0]) ? m : Math.max(m, x[1]); }, 0),
                                                           offscreen: offscreen.slice(0, 50)}));
});</script>"""


def chromium(args: list[str], profile: Path) -> subprocess.CompletedProcess:
    base = ["timeout", "180", "chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--disable-quic", f"--user-data-dir={profile}", "--virtual-time-budget=5000"]
    return subprocess.run(base + args, capture_output=True, text=True, check=False)


# Headless Chromium lays a window out at least 500 px wide; a narrower view (a 390 px phone) is the
# page's root box held at that width (the page's narrow-screen rules apply from 640 px down).
MIN_WINDOW_PX = 500


def view(html: str, section: str | None, width: int = MIN_WINDOW_PX) -> str:
    """The page with one section shown alone (None: the whole page), plus the measuring script."""
    style = f"<style>html{{width:{width}px}}</style>" if width < MIN_WINDOW_PX else ""
    if section:
        style += (f"<style>header,nav.toc,footer{{display:none}}main>section:not(#{section}){{display:none}}"
                 "</style>")
    # The report's CSP allows inline scripts and styles only; the measuring script is inline.
    return html.replace("</head>", style + "</head>", 1).replace("</body>", MEASURE + "</body>", 1)


# The phone of --phone: a 390 × 844 CSS px screen (a 6.1-inch phone of 2022–2024) at 3 device pixels per
# CSS px, touch, a mobile Chrome user agent.
PHONE = {"deviceMetrics": {"width": 390, "height": 844, "pixelRatio": 3.0, "touch": True},
         "userAgent": "Mozilla/5.0 (Linux; Android 13; Pixel 7) AppleWebKit/537.36 (KHTML, like Gecko) "
                      "Chrome/120.0 Mobile Safari/537.36"}
VIEWPORT = "return JSON.stringify({width: window.innerWidth, device_pixel_ratio: window.devicePixelRatio})"


class Phone:
    """Chromium under ChromeDriver with its mobile emulation (Selenium's Chrome options)."""

    def __init__(self, profile: Path):
        try:
            from selenium import webdriver
            from selenium.webdriver.chrome.service import Service
        except ImportError as e:
            raise RuntimeError("--phone needs Selenium (Debian's python3-selenium)") from e
        options = webdriver.ChromeOptions()
        for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
                  "--disable-background-networking", f"--user-data-dir={profile}"):
            options.add_argument(a)
        options.add_experimental_option("mobileEmulation", PHONE)
        try:
            self.driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        except Exception as e:  # ChromeDriver missing or failing to start Chromium
            raise RuntimeError(f"ChromeDriver did not start (Debian's chromium-driver): {str(e)[:300]}") from e
        self.driver.set_page_load_timeout(120)

    def layout(self, path: Path) -> dict:
        """The measuring script's result on `path` (it runs on the load event), plus the viewport."""
        self.driver.get(f"file://{path}")
        value = self.driver.find_element("tag name", "body").get_attribute("data-layout")
        if not value:
            raise RuntimeError(f"the phone did not lay out {path}")
        out = json.loads(value)
        out["viewport"] = json.loads(self.driver.execute_script(VIEWPORT))
        return out

    def screenshot(self, path: Path, png: Path) -> None:
        """The whole page `path`, beyond the screen's height (Chrome DevTools' Page.captureScreenshot)."""
        import base64
        self.driver.get(f"file://{path}")
        shot = self.driver.execute_cdp_cmd("Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True})
        png.write_bytes(base64.b64decode(shot["data"]))

    def close(self) -> None:
        self.driver.quit()


def layout(path: Path, width: int, profile: Path) -> dict:
    r = chromium([f"--window-size={max(width, MIN_WINDOW_PX)},1000", "--dump-dom", f"file://{path}"], profile)
    m = re.search(r"data-layout=\"([^\"]*)\"", r.stdout)
    if not m:
        raise RuntimeError(f"chromium did not lay out {path}: {r.stderr[-300:]}")
    return json.loads(m.group(1).replace("&quot;", '"'))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    width, pdf, shots, phone = 1400, True, True, False
    args = []
    i = 0
    while i < len(argv):
        if argv[i] == "--width" and i + 1 < len(argv):
            width = int(argv[i + 1])
            i += 2
            continue
        if argv[i] == "--no-pdf":
            pdf = False
        elif argv[i] == "--no-shots":
            shots = False
        elif argv[i] == "--phone":
            phone, width = True, PHONE["deviceMetrics"]["width"]
        else:
            args.append(argv[i])
        i += 1
    if len(args) != 2 or not Path(args[0]).is_file() or not 320 <= width <= 4000:
        print("usage: report_shots.py <report.html> <dir> [--width 320…4000 | --phone] [--no-pdf] [--no-shots]",
              file=sys.stderr)
        return 2
    report, out = Path(args[0]).resolve(), Path(args[1])
    out.mkdir(parents=True, exist_ok=True)
    html = report.read_text(encoding="utf-8")
    sections = re.findall(r'<section id="([a-z0-9-]+)"', html)
    result = {"width_px": width, "sections": {}}
    with tempfile.TemporaryDirectory(prefix="clearshape_shots_") as tmp:
        tmp = Path(tmp)
        device = None
        try:
            if phone:
                device = Phone(tmp / "phone-profile")
                result["device"] = {"kind": "phone (Chromium mobile emulation)", **PHONE["deviceMetrics"]}
            # The phone lays the page out at its own width: no root-box rule.
            page_width = MIN_WINDOW_PX if phone else width
            whole = tmp / "page.html"
            whole.write_text(view(html, None, page_width), encoding="utf-8")
            lay = device.layout(whole) if device else layout(whole, width, tmp / "profile")
            result["height_px"], result["overflow"] = lay["height"], lay["overflow"]
            result["page_overflow_px"], result["offscreen"] = lay.get("page_overflow_px", 0), lay.get("offscreen", [])
            result["in_box"] = lay.get("in_box", [])
            if device:
                result["viewport"] = lay["viewport"]
            for sid in sections if shots else []:
                page = tmp / f"{sid}.html"
                page.write_text(view(html, sid, page_width), encoding="utf-8")
                h = int(lay.get("sections", {}).get(sid, 2000))
                height = min(MAX_HEIGHT_PX, max(200, h + 60))
                if device:
                    device.screenshot(page, out / (sid + ".png"))
                else:
                    chromium([f"--window-size={max(width, MIN_WINDOW_PX)},{height}",
                              f"--screenshot={out / (sid + '.png')}", f"file://{page}"], tmp / "profile")
                result["sections"][sid] = {"height_px": h}
            if pdf:
                r = chromium(["--no-pdf-header-footer", f"--print-to-pdf={out / 'report.pdf'}", f"file://{report}"],
                             tmp / "profile")
                if not (out / "report.pdf").exists():
                    raise RuntimeError(f"chromium did not print {report}: {r.stderr[-300:]}")
        except RuntimeError as e:
            print(f"report_shots: {e}", file=sys.stderr)
            return 1
        finally:
            if device:
                device.close()
    (out / "layout.json").write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(out / "layout.json")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
