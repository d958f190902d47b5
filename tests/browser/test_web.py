"""Browser tests of the lab page: Debian's Chromium, headless, driven by Playwright against
the real `bearing-sim serve` on a loopback port with a temporary database.

Run by scripts/ci/test-all (after the Rust tests built the release binary):
    python tests/browser/test_web.py [--screenshots docs/guide/screenshots] [--assets-from-src]
Exits non-zero on the first failed check. `--assets-from-src` serves the page's files from
src/api/web instead of the binary's copies (for editing the page without a rebuild). Chromium is /usr/bin/chromium (BEARING_SIM_CHROMIUM
overrides it); Playwright never downloads a browser here.
"""

import json
import os
import re
import urllib.request
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from playwright.sync_api import expect, sync_playwright

ROOT = Path(__file__).resolve().parents[2]
BINARY = ROOT / "target" / "release" / "bearing-sim"
CHROMIUM = os.environ.get("BEARING_SIM_CHROMIUM", "/usr/bin/chromium")
CWRU_IR = ROOT / "crates" / "bearing-core" / "tests" / "fixtures" / "cwru" / "cwru_ir007_0hp_12k_de.f32le"
RECORDINGS = ROOT / "crates" / "bearing-core" / "tests" / "fixtures" / "recordings"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--disable-quic", "--no-first-run"]


def start_server(tmp):
    out = open(Path(tmp) / "stdout", "w+")
    err = open(Path(tmp) / "server.log", "w")
    proc = subprocess.Popen(
        [str(BINARY), "serve", "--bind", "127.0.0.1:0", "--workers", "2",
         "--database-url", f"sqlite://{tmp}/jobs.db"],
        stdout=out, stderr=err, env={k: v for k, v in os.environ.items() if not k.startswith("BEARING_SIM_")})
    for _ in range(200):
        out.seek(0)
        m = re.search(r"listening on (http://\S+)", out.read())
        if m:
            return proc, m.group(1)
        if proc.poll() is not None:
            sys.exit(f"server exited: {(Path(tmp) / 'server.log').read_text()}")
        time.sleep(0.05)
    sys.exit("server did not report its address")


def check(name, fn):
    t = time.time()
    fn()
    print(f"ok   {name} ({time.time() - t:.1f} s)")


def main():
    shots = None
    if "--screenshots" in sys.argv:
        shots = ROOT / sys.argv[sys.argv.index("--screenshots") + 1]
        shots.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as pw:
        proc, base = start_server(tmp)
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 800}, accept_downloads=True)
        if "--assets-from-src" in sys.argv:
            web = ROOT / "src" / "api" / "web"
            types = {".js": "text/javascript", ".css": "text/css"}
            page.route("**/assets/*", lambda route: route.fulfill(
                path=str(web / route.request.url.rsplit("/", 1)[1]),
                content_type=types[Path(route.request.url).suffix]))
        page.set_default_timeout(60_000)
        console_errors = []
        page.on("console", lambda m: console_errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: console_errors.append(str(e)))
        try:
            run(page, base, shots, console_errors)
        finally:
            browser.close()
            proc.terminate()
            proc.wait(timeout=20)
    print("browser tests passed")


def submit_form(page, base, duration, **fields):
    page.goto(f"{base}/#/new")
    page.locator("#submit-form").wait_for()
    page.fill('[name="solver.duration"]', str(duration))
    for name, value in fields.items():
        page.fill(f'[name="{name}"]', str(value))
    expect(page.locator("#patch")).to_contain_text(f'"duration": {duration}')
    # the form starts from the preset's integrator, not the first option it lists
    expect(page.locator("#patch")).to_contain_text('"integrator": "auto_etd"')
    page.click("button[type=submit]")


# Text boxes of every <text> in `selector` (client pixels), and the pairs that overlap by more
# than half a pixel each way (a shared edge of anti-aliased glyph boxes is not an overlap).
OVERLAPS = """(sel) => {
  const boxes = [...document.querySelectorAll(sel + ' text')].filter((t) => t.textContent.trim())
    .map((t) => { const r = t.getBoundingClientRect(); return { text: t.textContent, x: r.x, y: r.y, w: r.width, h: r.height }; })
    .filter((b) => b.w > 0 && b.h > 0);
  const bad = [];
  for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
    const a = boxes[i], b = boxes[j];
    const dx = Math.min(a.x + a.w, b.x + b.w) - Math.max(a.x, b.x), dy = Math.min(a.y + a.h, b.y + b.h) - Math.max(a.y, b.y);
    if (dx > 0.5 && dy > 0.5) bad.push(`${a.text} / ${b.text}`);
  }
  return { count: boxes.length, texts: boxes.map((b) => b.text), bad };
}"""


def api_json(base, path, body=None):
    req = urllib.request.Request(f"{base}{path}", data=json.dumps(body).encode() if body is not None else None,
                                 headers={"Content-Type": "application/json"}, method="POST" if body is not None else "GET")
    return json.load(urllib.request.urlopen(req))


def job_count(base):
    return sum(len(api_json(base, f"/v1/{k}?limit=200")["items"]) for k in ("simulations", "analyses"))


def download(page, selector):
    """Click a download button; the file's name and bytes."""
    with page.expect_download() as d:
        page.click(selector)
    dl = d.value
    return dl.suggested_filename, Path(dl.path()).read_bytes()


def with_summary(route):
    """Answer a result request with the service's answer plus a verdict summary."""
    response = route.fetch()
    result = response.json()
    result["analysis"]["verdict"]["summary"] = "Inner race fault (test sentence)."
    route.fulfill(response=response, json=result)


def no_sideways_scroll(page, width, what):
    got = page.evaluate("document.documentElement.scrollWidth")
    assert got <= width, f"{what} is {got} px wide in a {width} px window"


def run(page, base, shots, console_errors):
    state = {}

    def compound_preset_to_success():
        submit_form(page, base, 0.1)
        page.wait_for_url(re.compile(r"#/simulations/[\w-]+$"))
        state["compound"] = page.url.rsplit("/", 1)[1]
        expect(page.locator("#job-state")).to_have_text("succeeded", timeout=240_000)
        # the spectrum plot with its BPFO marker and BPFI sidebands, and the time signal
        expect(page.locator('#spectrum-chart line[data-marker="BPFO"]')).to_have_count(1)
        expect(page.locator("#signal-chart path.series")).to_have_count(1)
        expect(page.locator("#summary")).to_contain_text("Mean cage speed")
        expect(page.locator("#view")).not_to_contain_text("null")
        if shots:
            page.screenshot(path=str(shots / "result.png"), full_page=False)

    def spectrum_labels_never_overlap():
        # every text of the chart (ticks, axis titles, marker labels, peak errors), in each
        # spectrum and scale, at a desktop and a phone width
        for width in (1280, 360):
            page.set_viewport_size({"width": width, "height": 800})
            page.goto(f"{base}/#/simulations/{state['compound']}")
            page.locator("#spectrum-chart svg").wait_for()
            for kind in ("raw", "best_component"):
                page.select_option("#spectrum-kind", kind)
                expect(page.locator("#spectrum-chart")).to_have_attribute("data-kind", kind)
                for scale in ("linear", "db"):
                    page.select_option("#spectrum-scale", scale)
                    page.locator("#spectrum-chart svg").wait_for()
                    got = page.evaluate(OVERLAPS, "#spectrum-chart")
                    assert not got["bad"], f"{width} px, {kind}, {scale}: overlapping labels {got['bad']}"
                    assert "BPFO" in got["texts"] and "BPFI" in got["texts"], f"{width} px {kind}: {got['texts']}"
                    # legible: tick labels keep their size in a narrow window
                    tick_h = page.evaluate("document.querySelector('#spectrum-chart text.tick').getBoundingClientRect().height")
                    assert tick_h >= 10, f"tick labels are {tick_h:.1f} px tall at {width} px"
            print(f"     {width} px: {got['count']} texts, none overlapping; {page.locator('#spectrum-chart svg').get_attribute('data-hidden-labels')} marker labels left to the legend")
        page.set_viewport_size({"width": 1280, "height": 800})
        page.select_option("#spectrum-scale", "linear")
        page.select_option("#spectrum-kind", "raw")
        expect(page.locator("#spectrum-chart")).to_have_attribute("data-kind", "raw")
        # sidebands around BPFI, identified peaks with their error, the keyed legend
        expect(page.locator('#spectrum-chart line.sideband').first).to_be_attached()
        expect(page.locator("#spectrum-chart circle.peak").first).to_be_attached()
        expect(page.locator("#spectrum-chart").locator("xpath=..").locator("ul.legend")).to_contain_text("BPFI ± shaft sidebands")

    def spectrum_zoom_and_readout():
        svg = page.locator("#spectrum-chart svg")
        svg.scroll_into_view_if_needed()
        box = svg.bounding_box()
        y = box["y"] + box["height"] / 2
        page.mouse.move(box["x"] + box["width"] * 0.2, y)
        page.mouse.down()
        page.mouse.move(box["x"] + box["width"] * 0.4, y, steps=5)
        page.mouse.up()
        expect(page.locator("#fmin")).not_to_have_value("0")
        lo = float(page.input_value("#fmin"))
        assert lo > 0, f"zoom left fmin at {lo}"
        page.mouse.move(box["x"] + box["width"] * 0.5, y)
        expect(page.locator("#spectrum-readout")).to_contain_text(re.compile(r"Hz: .*nearest marker"))
        page.click("#spectrum-reset")
        expect(page.locator("#fmin")).to_have_value("0")
        # a range that does not parse is an error next to it, not a guess
        page.fill("#fmax", "1e3x")
        page.locator("#fmax").dispatch_event("change")
        expect(page.locator("#spectrum-error")).to_contain_text("not a number")
        page.fill("#fmax", "2000")
        page.locator("#fmax").dispatch_event("change")
        expect(page.locator("#spectrum-error")).to_have_text("")

    def a_download_button_keeps_a_press_across_a_redraw():
        # the spectrum reloads and redraws between the press and the release (a new
        # range); a button rebuilt by the redraw would lose the click, and with it the file
        button = page.locator('#spectrum-chart >> xpath=.. >> [data-download="svg"]')
        button.scroll_into_view_if_needed()
        box = button.bounding_box()
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        page.mouse.down()
        chart = page.locator("#spectrum-chart")
        before = chart.get_attribute("data-range")
        page.locator("#fmax").evaluate("e => { e.value = '2100'; e.dispatchEvent(new Event('change')); }")
        # the chart redrawn over the new range (the service's bins end it near 2100 Hz)
        # before the release
        expect(chart).not_to_have_attribute("data-range", before)
        with page.expect_download(timeout=10_000) as d:
            page.mouse.up()
        assert d.value.suggested_filename.endswith(".svg"), d.value.suggested_filename

    def a_result_offers_downloads():
        name, data = download(page, '#spectrum-chart >> xpath=.. >> [data-download="svg"]')
        assert name.endswith(".svg") and data.lstrip().startswith(b"<svg") and b"BPFO" in data, (name, data[:80])
        name, data = download(page, '#spectrum-chart >> xpath=.. >> [data-download="png"]')
        assert name.endswith(".png") and data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, (name, len(data))
        name, data = download(page, '[data-download="spectrum-csv"]')
        lines = data.decode().splitlines()
        assert name.endswith(".csv") and lines[0] == "frequency_hz,amplitude" and len(lines) > 100, (name, lines[:3])
        f1, a1 = map(float, lines[2].split(","))
        assert f1 > 0 and a1 >= 0, lines[2]
        name, data = download(page, '[data-download="summary-csv"]')
        assert data.decode().startswith("quantity,value,unit") and "Mean cage speed" in data.decode(), data[:200]
        name, data = download(page, '[data-download="identifications-csv"]')
        rows = data.decode().splitlines()
        assert rows[0].startswith("spectrum,line,harmonic,theory_hz") and any(",BPFO," in r for r in rows), rows[:3]
        name, data = download(page, '#signal-chart >> xpath=.. >> [data-download="svg"]')
        assert data.lstrip().startswith(b"<svg"), data[:80]

    def page_and_endpoint_draw_the_same_chart():
        # the SVG endpoint's chart, inlined into the page so the browser measures its text
        sid = state["compound"]
        got = page.evaluate("""async (id) => {
          const svg = await (await fetch(`/v1/simulations/${id}/plots/spectrum.svg`)).text();
          const box = document.createElement('div'); box.id = 'endpoint-svg'; box.style.width = '800px';
          box.innerHTML = svg; document.body.append(box);
          const texts = [...box.querySelectorAll('text')].map((t) => [t.textContent.trim(), (t.getAttribute('fill') || '').toLowerCase()]);
          const page = [...document.querySelectorAll('#spectrum-chart text.marker-label')].map((t) => [t.textContent, t.getAttribute('fill').toLowerCase()]);
          const strokes = (root, sel) => [...new Set([...root.querySelectorAll(sel)].map((e) => (e.getAttribute('stroke') || '').toLowerCase()))].sort();
          return { texts, page, endpointStrokes: strokes(box, 'line, polyline, path'), pageStrokes: strokes(document, '#spectrum-chart line.marker'),
                   title: document.querySelector('#spectrum-chart').closest('.plot').querySelector('h3').firstChild.textContent };
        }""", sid)
        endpoint = dict(got["texts"])
        assert got["title"] in endpoint, f"page title {got['title']!r} not among the endpoint's texts {list(endpoint)[:5]}"
        for t in ("frequency (Hz)", "envelope amplitude (m/s²)"):
            assert t in endpoint, f"endpoint lacks the axis title {t!r}"
        shared = [(t, c) for t, c in got["page"] if t in endpoint]
        assert len(shared) >= 3, f"too few marker labels in common: {got['page']} vs {list(endpoint)}"
        for t, c in shared:
            assert endpoint[t] == c, f"{t}: page {c}, endpoint {endpoint[t]}"
        missing = set(got["pageStrokes"]) - set(got["endpointStrokes"])
        assert not missing, f"marker colours of the page missing from the endpoint: {missing}"
        ov = page.evaluate(OVERLAPS, "#endpoint-svg")
        assert not ov["bad"], f"the endpoint's chart has overlapping text: {ov['bad']}"
        ticks = [t for t, _ in got["texts"] if re.fullmatch(r"[-0-9.e]+", t)]
        assert not any(re.fullmatch(r"\d\.\d\de-?\d+", t) for t in ticks), f"unreadable ticks: {ticks}"
        page.evaluate("document.getElementById('endpoint-svg').remove()")
        print(f"     {len(shared)} marker labels in the same colours; title {got['title']!r} in both")

    def switch_to_best_component():
        page.select_option("#spectrum-kind", "best_component")
        expect(page.locator("#spectrum-chart")).to_have_attribute("data-kind", "best_component")
        expect(page.locator('#spectrum-chart line[data-marker="BPFO"]')).to_have_count(1)
        if shots:
            page.locator("#spectrum-chart").scroll_into_view_if_needed()
            page.evaluate("window.scrollBy(0, 60)")
            page.screenshot(path=str(shots / "result-plots.png"), full_page=False)

    def zoom_the_time_signal():
        box = page.locator("#signal-chart svg").bounding_box()
        y = box["y"] + box["height"] / 2
        page.mouse.move(box["x"] + box["width"] * 0.3, y)
        page.mouse.down()
        page.mouse.move(box["x"] + box["width"] * 0.5, y, steps=5)
        page.mouse.up()
        expect(page.locator("#signal-chart").locator("xpath=..")).to_contain_text("points")

    def blank_duration_is_an_error_at_the_field():
        before = job_count(base)
        page.goto(f"{base}/#/new")
        page.locator("#submit-form").wait_for()
        page.fill('[name="solver.duration"]', "")
        page.fill('[name="solver.rtol"]', "1e-5x")
        page.click("button[type=submit]")
        expect(page.locator('.field[data-path="solver.duration"] .error')).to_contain_text("required")
        expect(page.locator('.field[data-path="solver.duration"] .error')).to_contain_text("the preset's is 0.5")
        expect(page.locator('.field[data-path="solver.rtol"] .error')).to_contain_text("not a number")
        expect(page.locator("#submit-status")).to_contain_text("Not submitted")
        assert page.url.endswith("#/new")
        assert job_count(base) == before, "a blank duration created a job"
        # a likely mistake is a warning, not a refusal
        page.fill('[name="solver.duration"]', "0.05")
        page.fill('[name="operating.speed.ramp_time"]', "0.1")
        expect(page.locator('.field[data-path="solver.duration"] .warning')).to_contain_text("speed ramp")
        page.goto(f"{base}/#/")  # leave the form, so the next visit starts from the preset

    def bad_scene_error_next_to_its_field():
        submit_form(page, base, 0.02, **{"operating.axial_load": -5})
        err = page.locator('.field[data-path="operating.axial_load"] .error')
        expect(err).to_contain_text("must be >= 0")
        # Chromium logs the expected 422 as a failed resource load; nothing else may appear
        console_errors[:] = [e for e in console_errors if "status of 422" not in e]
        if shots:
            page.screenshot(path=str(shots / "new-simulation.png"))

    def cwru_upload_identifies_bpfi():
        page.goto(f"{base}/#/upload")
        page.set_input_files("#file", str(CWRU_IR))
        page.fill("#fs", "12000")
        page.fill("#rpm", "1797")
        page.select_option("#bearing", "cwru6205")
        page.fill("#kurtogram", "6")
        page.click("button[type=submit]")
        page.wait_for_url(re.compile(r"#/analyses/[\w-]+$"))
        expect(page.locator("#job-state")).to_have_text("succeeded", timeout=120_000)
        expect(page.locator('#ids-raw tr[data-line="BPFI"][data-detected="true"]').first).to_be_visible()
        # the kurtogram's band is reported too (there BPFI reads 11.3 dB, under the threshold)
        expect(page.locator('#ids-kurtogram tr[data-line="BPFI"]').first).to_be_visible()
        # and its runner-up, the best band beside it (4-5 kHz here, the first 2-4 kHz)
        expect(page.locator('#ids-kurtogram-runner-up tr[data-line="BPFI"]').first).to_be_visible()
        # and the verdict names the inner race, with its evidence table
        expect(page.locator("#summary")).to_contain_text("inner race")
        expect(page.locator("#verdict")).to_contain_text("rolling element")
        # per-line flags carry it: the BPFI lines count for the named fault, BPFO lines not
        expect(page.locator('#ids-raw tr[data-line="BPFI"][data-in-verdict="true"]').first).to_be_visible()
        expect(page.locator('#ids-raw tr[data-line="BPFO"][data-in-verdict="true"]')).to_have_count(0)
        # a verdict's summary sentence (issue 35 adds it to the report) heads the result
        page.route("**/v1/analyses/*/result", with_summary)
        page.reload()
        expect(page.locator("#verdict-summary")).to_have_text("Inner race fault (test sentence).")
        page.unroute("**/v1/analyses/*/result")
        # the detected BPFI peak is marked on the spectrum with its error, and no label overlaps
        expect(page.locator("#spectrum-chart circle.peak.detected").first).to_be_attached()
        expect(page.locator("#spectrum-chart text.peak-label").first).to_contain_text(re.compile(r"^[+-][0-9.]+ %$"))
        got = page.evaluate(OVERLAPS, "#spectrum-chart")
        assert not got["bad"], f"overlapping labels in the CWRU spectrum: {got['bad']}"

    def recording_files_list_their_channels_and_name_the_inner_race():
        # issue 36: the page lists a file's channels (through the API's reader) before it
        # uploads it, plots the chosen one, and the job keeps the file's name
        for name, channel, fs in [("cwru_ir007.mat", "0", "12000"), ("ir007_pcm16.wav", "0", None),
                                  ("ir007_float.wav", "0", None), ("ir007.csv", "0", None)]:
            page.goto(f"{base}/#/upload")
            page.set_input_files("#file", str(RECORDINGS / name))
            expect(page.locator("#recording-about")).to_contain_text("channel")
            if name.endswith(".mat"):
                expect(page.locator("#channel option")).to_have_count(2)
                expect(page.locator("#recording-about")).to_contain_text("X105RPM")
                expect(page.locator("#recording-about")).to_contain_text("no sample rate in the file")
                expect(page.locator("#rpm")).to_have_value("1797")
            else:
                expect(page.locator("#channel option")).to_have_count(1)
                expect(page.locator("#fs")).to_have_value(re.compile(r"^1199\d|^12000"))
                page.fill("#rpm", "1797")
            page.select_option("#channel", channel)
            if fs:
                page.fill("#fs", fs)
            expect(page.locator("#recording-preview svg")).to_be_visible()
            if shots and name.endswith(".mat"):
                page.screenshot(path=str(shots / "upload-recording.png"))
            page.select_option("#bearing", "cwru6205")
            page.click("button[type=submit]")
            page.wait_for_url(re.compile(r"#/analyses/[\w-]+$"))
            expect(page.locator("#job-state")).to_have_text("succeeded", timeout=120_000)
            expect(page.locator("#summary")).to_contain_text("inner race")
            expect(page.locator("body")).to_contain_text(name)
        # a channel that does not exist is not offered; a file that cannot be read says why,
        # next to the file field
        page.goto(f"{base}/#/upload")
        bad = Path(tempfile.mkdtemp()) / "ragged.csv"
        bad.write_text("time,accel\n0,1\n0.001,2,3\n")
        page.set_input_files("#file", str(bad))
        expect(page.locator('.field[data-path="file"] .error')).to_contain_text("line 3: 3 fields, the header has 2")
        console_errors[:] = [e for e in console_errors if "status of 422" not in e]

    def cancel_a_running_job():
        submit_form(page, base, 0.5)
        page.wait_for_url(re.compile(r"#/simulations/[\w-]+$"))
        expect(page.locator("#job-state")).to_have_text(re.compile("queued|running"))
        page.click("#cancel")
        expect(page.locator("#job-state")).to_have_text("cancelled", timeout=60_000)

    def the_jobs_list():
        page.goto(f"{base}/#/")
        expect(page.locator("#jobs tbody tr")).to_have_count(3)
        expect(page.locator('#jobs tr[data-state="cancelled"]')).to_have_count(1)
        if shots:
            page.screenshot(path=str(shots / "jobs.png"))

    def a_named_short_run_to_compare():
        page.goto(f"{base}/#/new")
        page.locator("#submit-form").wait_for()
        page.fill('[name="name"]', "compound, 40 ms")
        page.fill('[name="solver.duration"]', "0.04")
        page.click("button[type=submit]")
        page.wait_for_url(re.compile(r"#/simulations/[\w-]+$"))
        state["short"] = page.url.rsplit("/", 1)[1]
        expect(page.locator("#job-name")).to_have_text("compound, 40 ms")
        expect(page.locator("#job-state")).to_have_text("succeeded", timeout=240_000)

    def two_jobs_overlaid():
        page.goto(f"{base}/#/")
        for sid in (state["compound"], state["short"]):
            page.check(f'#jobs tr[data-id="{sid}"] input.pick')
        page.click("#compare")
        page.wait_for_url(re.compile(r"#/compare/"))
        expect(page.locator("#compare-chart path.series")).to_have_count(2)
        expect(page.locator("#compare-table thead th")).to_have_count(3)
        expect(page.locator("#compare-table")).to_contain_text("compound, 40 ms")
        # the 40 ms run ends inside the speed ramp: its lines differ, so none are drawn
        expect(page.locator("#compare-lines")).to_contain_text("differ")
        got = page.evaluate(OVERLAPS, "#compare-chart")
        assert not got["bad"], f"overlapping labels in the comparison: {got['bad']}"
        if shots:
            page.screenshot(path=str(shots / "compare.png"))

    def a_study_started_from_the_page():
        page.goto(f"{base}/#/studies")
        page.locator("#study-form").wait_for()
        page.fill('[name="study.duration"]', "")
        page.click("#study-form button[type=submit]")
        expect(page.locator('.field[data-path="study.duration"] .error')).to_contain_text("required")
        page.fill('[name="study.duration"]', "0.03")
        page.select_option("#study-case", "outer")
        page.select_option("#study-design", "one_at_a_time")
        page.select_option("#study-factor", "axial_load")
        page.fill('[name="study.values"]', "300, 400")
        page.click("#study-form button[type=submit]")
        page.wait_for_url(re.compile(r"#/studies/[\w-]+$"))
        expect(page.locator("#study-state")).to_have_text("succeeded", timeout=240_000)
        expect(page.locator("#study-table tbody tr")).to_have_count(2)
        img = page.locator("img.trend").first
        expect(img).to_be_visible()
        page.wait_for_function("[...document.querySelectorAll('img.trend')].every(i => i.complete && i.naturalWidth > 0)")
        expect(page.locator(".plot h3").filter(has_text="against axial load, outer fault")).to_have_count(1)
        if shots:
            page.screenshot(path=str(shots / "study.png"))

    def keyboard_reaches_the_navigation():
        page.goto(f"{base}/#/")
        page.reload()  # a fresh document: Tab starts at the top
        page.locator("#jobs").wait_for()
        # Tab through the header to the "New simulation" link and follow it with Enter
        for _ in range(8):
            page.keyboard.press("Tab")
            if page.evaluate("document.activeElement.textContent") == "New simulation":
                break
        else:
            raise AssertionError("Tab never reached the New simulation link")
        page.keyboard.press("Enter")
        page.wait_for_url(re.compile(r"#/new$"))
        page.locator("#submit-form").wait_for()

    def narrow_windows_do_not_scroll_sideways():
        pages = [("jobs", "#/", "#jobs"), ("new simulation", "#/new", "#submit-form"),
                 ("result", f"#/simulations/{state['compound']}", "#spectrum-chart svg"),
                 ("comparison", f"#/compare/simulations:{state['compound']},simulations:{state['short']}", "#compare-chart svg"),
                 ("studies", "#/studies", "#study-form")]
        for width in (420, 360):
            page.set_viewport_size({"width": width, "height": 800})
            for what, hash_, ready in pages:
                page.goto(f"{base}/{hash_}")
                page.locator(ready).wait_for()
                if what == "result":
                    page.locator("#kurtosis-chart svg").wait_for()
                    if shots and width == 360:
                        page.locator("#spectrum-chart").scroll_into_view_if_needed()
                        page.screenshot(path=str(shots / "result-narrow.png"))
                no_sideways_scroll(page, width, f"the {what} page")
        page.set_viewport_size({"width": 1280, "height": 800})

    def unreachable_service_says_so():
        page.route("**/v1/**", lambda route: route.abort())
        page.goto(f"{base}/#/")
        expect(page.locator("#banner")).to_contain_text("unreachable")
        page.unroute("**/v1/**")
        # the aborted requests log network errors by design; they are not page errors
        console_errors[:] = [e for e in console_errors if "ERR_FAILED" not in e]

    check("compound preset, 0.1 s, to succeeded with a BPFO marker", compound_preset_to_success)
    check("no two labels of the spectrum overlap (1280 and 360 px, raw and best, linear and dB)", spectrum_labels_never_overlap)
    check("zoom, pan back and read the spectrum; a bad range is an error", spectrum_zoom_and_readout)
    check("a download button keeps a press across the chart's redraw", a_download_button_keeps_a_press_across_a_redraw)
    check("a result offers SVG, PNG and CSV downloads", a_result_offers_downloads)
    check("the SVG endpoint draws the page's chart", page_and_endpoint_draw_the_same_chart)
    check("switch the spectrum to the best component", switch_to_best_component)
    check("zoom the time signal", zoom_the_time_signal)
    check("a blank duration creates no job and is an error at the field", blank_duration_is_an_error_at_the_field)
    check("a bad scene's error next to its field", bad_scene_error_next_to_its_field)
    check("a CWRU inner-race excerpt: BPFI identified, verdict inner race", cwru_upload_identifies_bpfi)
    check("cancel a running job", cancel_a_running_job)
    check("the job list", the_jobs_list)
    check("a named run", a_named_short_run_to_compare)
    check("two jobs overlaid and side by side", two_jobs_overlaid)
    check("a study started from the page, its table and trend plots", a_study_started_from_the_page)
    check("recording files (.mat, PCM and float WAV, CSV): channels listed, inner race named", recording_files_list_their_channels_and_name_the_inner_race)
    check("keyboard navigation", keyboard_reaches_the_navigation)
    check("no page scrolls sideways at 420 or 360 px", narrow_windows_do_not_scroll_sideways)
    check("unreachable service", unreachable_service_says_so)
    assert not console_errors, f"console errors: {console_errors}"
    print("ok   no console errors")


if __name__ == "__main__":
    main()
