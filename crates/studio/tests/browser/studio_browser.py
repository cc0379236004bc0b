#!/usr/bin/env python3
"""The studio in a real browser: Debian's Chromium, driven headless by
Selenium through chromium-driver (apt: chromium chromium-driver
python3-selenium; nothing is downloaded).

    /usr/bin/python3 crates/studio/tests/browser/studio_browser.py \
        target/debug/synthavision [ARTIFACTS_DIR]

Opens the page on a copy of the helicopter, waits for the first frame,
drags to turn the model and sees the picture change, clicks a region and
sees its name, makes it transparent and sees pixels change, adds a cut
plane, edits the file and sees the reload, breaks it and sees the error at
its line. Screenshots go to ARTIFACTS_DIR (default target/studio-browser).
Fails, never skips, when Chromium or its driver is missing.
"""

import os
import shutil
import subprocess
import sys
import tempfile
import time

CHROMIUM = "/usr/bin/chromium"
DRIVER = "/usr/bin/chromedriver"
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", "..", ".."))


def fail(message):
    print(f"studio browser test FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def wait_for(what, condition, seconds=60):
    deadline = time.time() + seconds
    while time.time() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.1)
    fail(f"timed out waiting for {what}")


def main():
    if len(sys.argv) < 2:
        fail("usage: studio_browser.py SYNTHAVISION [ARTIFACTS_DIR]")
    binary = os.path.abspath(sys.argv[1])
    artifacts = os.path.abspath(
        sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "target", "studio-browser")
    )
    for path in (CHROMIUM, DRIVER, binary):
        if not os.path.exists(path):
            fail(f"{path} is missing (apt-get install chromium chromium-driver python3-selenium)")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.options import Options
        from selenium.webdriver.chrome.service import Service
    except ImportError as error:
        fail(f"selenium is missing ({error}); apt-get install python3-selenium")
    os.makedirs(artifacts, exist_ok=True)
    work = tempfile.mkdtemp(prefix="studio-browser-")
    scene = os.path.join(work, "helicopter.sv")
    shutil.copy(os.path.join(ROOT, "examples", "helicopter", "helicopter.sv"), scene)
    server = subprocess.Popen(
        [binary, "studio", scene, "--port", "0", "--output", os.path.join(work, "out")],
        stdout=subprocess.PIPE,
        text=True,
    )
    driver = None
    try:
        line = server.stdout.readline()
        if "http://" not in line:
            fail(f"the studio did not print its address: {line!r}")
        url = line[line.index("http://"):].strip()
        options = Options()
        options.binary_location = CHROMIUM
        for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1500,860"):
            options.add_argument(argument)
        driver = webdriver.Chrome(service=Service(DRIVER), options=options)
        run(driver, url, scene, artifacts)
        print("studio browser test passed; screenshots in", artifacts)
    finally:
        if driver is not None:
            driver.quit()
        server.terminate()
        server.wait(timeout=10)
        shutil.rmtree(work, ignore_errors=True)


def run(driver, url, scene, artifacts):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    js = driver.execute_script
    frames = lambda: int(js("return +(document.getElementById('view').dataset.frames || 0)"))
    # A digest of the pixels on the canvas.
    digest = lambda: js(
        "const c = document.getElementById('view');"
        "const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
        "let h = 0; for (let i = 0; i < d.length; i += 7) h = (h * 31 + d[i]) | 0; return h;"
    )

    # The full frame of the newest view the page asked for.
    def settled_after(count):
        wait_for("a full frame", lambda: frames() > count and js(
            "const s = window.studio;"
            "return s.lastFrame.kind === 'full' && s.lastFrame.seq === s.seq;"))

    driver.get(url)
    wait_for("the first frame", lambda: frames() >= 1)
    settled_after(0)
    driver.save_screenshot(os.path.join(artifacts, "1-first-frame.png"))
    before = digest()

    canvas = driver.find_element(By.ID, "view")
    count = frames()
    drag = ActionChains(driver).move_to_element(canvas).click_and_hold()
    for _ in range(8):
        drag = drag.move_by_offset(15, 4)
    drag.release().perform()
    settled_after(count)
    if digest() == before:
        fail("dragging did not change the picture")
    driver.save_screenshot(os.path.join(artifacts, "2-turned.png"))

    # A pixel well inside a region (its neighbours 8 pixels away are of
    # the same region), in canvas coordinates from the canvas's centre.
    target = js(
        "const s = window.studio; const w = s.idsWidth, h = s.idsHeight, r = 8;"
        "const at = (x, y) => s.ids[y * w + x];"
        "for (let y = r; y < h - r; y += 3) for (let x = r; x < w - r; x += 3)"
        "  { const id = at(x, y); if (id > 0 && at(x - r, y) === id && at(x + r, y) === id"
        "      && at(x, y - r) === id && at(x, y + r) === id) {"
        "    const box = document.getElementById('view').getBoundingClientRect();"
        "    return [x / w * box.width - box.width / 2, y / h * box.height - box.height / 2,"
        "            s.model.regions[id - 1].name]; } }"
        "return null;"
    )
    if not target:
        fail("no region on the picture")
    offset_x, offset_y, name = target
    ActionChains(driver).move_to_element_with_offset(canvas, int(offset_x), int(offset_y)).click().perform()
    wait_for(f"the name of `{name}`", lambda: name in driver.find_element(By.ID, "pick-name").text)

    count, before = frames(), digest()
    driver.find_element(By.ID, "pick-ghost").click()
    settled_after(count)
    wait_for("the transparent region's pixels", lambda: digest() != before, 10)

    # A cut along y, the far half kept: the camera looks into the cut.
    count = frames()
    Select(driver.find_element(By.ID, "cut-axis")).select_by_value("y")
    driver.find_element(By.ID, "cut-add").click()
    driver.find_element(By.CSS_SELECTOR, "#cuts button[title='keep the other side']").click()
    settled_after(count)
    wait_for("the section view", lambda: js("return document.getElementById('section').naturalWidth > 0"))
    driver.save_screenshot(os.path.join(artifacts, "3-picked-transparent-cut.png"))

    regions = js("return window.studio.model.regions.length")
    with open(scene, "a") as file:
        file.write("\nBODY extra SPH (0, 0, 9) 0.6\nREGION extra = +extra\n")
    wait_for("the reload", lambda: js("return window.studio.model.regions.length") == regions + 1)
    with open(scene, "a") as file:
        file.write("REGION broken = +nowhere\n")
    lines = sum(1 for _ in open(scene))
    problems = driver.find_element(By.ID, "problems")
    wait_for("the error shown", lambda: problems.is_displayed() and f":{lines}:" in problems.text)
    driver.save_screenshot(os.path.join(artifacts, "4-error.png"))


if __name__ == "__main__":
    main()
