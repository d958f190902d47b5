"""Browser tests of the lab page: Debian's Chromium, headless, driven by Playwright against
the real `bearing-sim serve` on a loopback port with a temporary database.

Run by scripts/ci/test-all (after the Rust tests built the release binary):
    python tests/browser/test_web.py [--screenshots docs/guide/screenshots]
Exits non-zero on the first failed check. Chromium is /usr/bin/chromium (BEARING_SIM_CHROMIUM
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
        page = browser.new_page(viewport={"width": 1280, "height": 800})
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
    page.click("button[type=submit]")


def run(page, base, shots, console_errors):
    def compound_preset_to_success():
        submit_form(page, base, 0.02)
        page.wait_for_url(re.compile(r"#/simulations/[\w-]+$"))
        expect(page.locator("#job-state")).to_have_text("succeeded", timeout=120_000)
        # the spectrum plot with its BPFO marker, and the time signal
        expect(page.locator('#spectrum-chart line[data-marker="BPFO"]')).to_have_count(1)
        expect(page.locator("#signal-chart path.series")).to_have_count(1)
        expect(page.locator("#summary")).to_contain_text("Mean cage speed")
        expect(page.locator("#view")).not_to_contain_text("null")
        if shots:
            page.screenshot(path=str(shots / "result.png"), full_page=False)

    def switch_to_best_component():
        page.select_option("#spectrum-kind", "best_component")
        expect(page.locator("#spectrum-chart")).to_have_attribute("data-kind", "best_component")
        expect(page.locator('#spectrum-chart line[data-marker="BPFO"]')).to_have_count(1)
        if shots:
            page.locator("#signal-chart").scroll_into_view_if_needed()
            page.evaluate("window.scrollBy(0, 120)")
            page.screenshot(path=str(shots / "result-plots.png"), full_page=False)

    def zoom_the_time_signal():
        box = page.locator("#signal-chart svg").bounding_box()
        y = box["y"] + box["height"] / 2
        page.mouse.move(box["x"] + box["width"] * 0.3, y)
        page.mouse.down()
        page.mouse.move(box["x"] + box["width"] * 0.5, y, steps=5)
        page.mouse.up()
        expect(page.locator("#signal-chart").locator("xpath=..")).to_contain_text("points")

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

    def recording_files_list_their_channels_and_name_the_inner_race():
        # issue 36: the page lists a file's channels (through the API's reader) before it
        # uploads it, plots the chosen one, and the job keeps the file's name
        for name, channel, fs in [("cwru_ir007.mat", "0", "12000"), ("ir007_pcm16.wav", "0", None),
                                  ("ir007.csv", "0", None)]:
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

    def a_narrow_window_does_not_scroll_sideways():
        page.set_viewport_size({"width": 420, "height": 800})
        page.goto(f"{base}/#/new")
        page.locator("#submit-form").wait_for()
        width = page.evaluate("document.documentElement.scrollWidth")
        page.set_viewport_size({"width": 1280, "height": 800})
        assert width <= 420, f"page is {width} px wide in a 420 px window"

    def unreachable_service_says_so():
        page.route("**/v1/**", lambda route: route.abort())
        page.goto(f"{base}/#/")
        expect(page.locator("#banner")).to_contain_text("unreachable")
        page.unroute("**/v1/**")
        # the aborted requests log network errors by design; they are not page errors
        console_errors[:] = [e for e in console_errors if "ERR_FAILED" not in e]

    def a_study_table_and_its_trend_plots():
        study = {"name": "axial load", "base": {"preset": "h7005c", "fault_case": "outer",
                 "overrides": {"solver": {"duration": 0.03}}},
                 "design": {"type": "one_at_a_time", "factors": [
                     {"name": "axial_load", "pointer": "/operating/axial_load", "values": [300.0, 400.0]}]}}
        req = urllib.request.Request(f"{base}/v1/studies", data=json.dumps(study).encode(),
                                     headers={"Content-Type": "application/json"}, method="POST")
        sid = json.load(urllib.request.urlopen(req))["id"]
        page.goto(f"{base}/#/studies")
        page.click(f'a[href="#/studies/{sid}"]')
        expect(page.locator("#study-state")).to_have_text("succeeded", timeout=120_000)
        expect(page.locator("#study-table tbody tr")).to_have_count(2)
        img = page.locator("img.trend").first
        expect(img).to_be_visible()
        page.wait_for_function("[...document.querySelectorAll('img.trend')].every(i => i.complete && i.naturalWidth > 0)")
        if shots:
            page.screenshot(path=str(shots / "study.png"))

    check("compound preset, 20 ms, to succeeded with a BPFO marker", compound_preset_to_success)
    check("switch the spectrum to the best component", switch_to_best_component)
    check("zoom the time signal", zoom_the_time_signal)
    check("a bad scene's error next to its field", bad_scene_error_next_to_its_field)
    check("a CWRU inner-race excerpt: BPFI identified, verdict inner race", cwru_upload_identifies_bpfi)
    check("cancel a running job", cancel_a_running_job)
    check("the job list", the_jobs_list)
    check("a study's table and trend plots", a_study_table_and_its_trend_plots)
    check("recording files (.mat, WAV, CSV): channels listed, inner race named", recording_files_list_their_channels_and_name_the_inner_race)
    check("keyboard navigation", keyboard_reaches_the_navigation)
    check("narrow window", a_narrow_window_does_not_scroll_sideways)
    check("unreachable service", unreachable_service_says_so)
    assert not console_errors, f"console errors: {console_errors}"
    print("ok   no console errors")


if __name__ == "__main__":
    main()
