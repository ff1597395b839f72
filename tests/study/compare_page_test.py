#!/usr/bin/python3
"""The comparison page (tools/study/compare_page.h) in a real browser.

Runs a tiny study, opens OUT/compare.html from disk in Debian's headless
Chromium (through chromedriver and Selenium, which tools/setup.sh installs),
and checks the pixels the canvas shows against the study's own files: the
reference and each row's EXR (read with nuld.read_image) through the page's
exposure and the sRGB curve, the error and FLIP PNGs as they are; after
switching rows by keys and clicks, zooming, panning, changing exposure and
spp. Also that the page asked for nothing but files beside it.

Usage: compare_page_test.py NULD [SCREENSHOT.png]
(PYTHONPATH must reach the nuld module; a screenshot is saved when named.)
"""
import os
import shutil
import subprocess
import sys
import tempfile

import matplotlib.image as mpimg
import numpy as np

import nuld

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import WebDriverWait


def srgb8(v):
    v = np.clip(v, 0, 1)
    c = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)
    return np.round(255 * c)


class Page:
    def __init__(self, driver):
        self.d = driver
        self.canvas = driver.find_element(By.ID, "canvas")

    def state(self):
        return self.d.execute_script("return nuldCompare.state();")

    def wait(self):
        WebDriverWait(self.d, 30).until(
            lambda d: d.execute_script("return nuldCompare.state().ready;"))
        return self.state()

    def key(self, k):
        self.canvas.send_keys(k)
        return self.wait()

    def pixels(self):
        """The canvas as an (H, W, 4) array of bytes."""
        data = self.d.execute_script("""
            const c = document.getElementById('canvas');
            return [c.width, c.height,
                    Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data)];""")
        w, h, flat = data
        return np.array(flat, dtype=np.float64).reshape(h, w, 4)


def shown_image(page, width, height):
    """The image pixels the canvas shows at the page's zoom and pan: the
    canvas pixel at each image pixel's block centre, keyed by the image's
    own (x, y)."""
    s = page.state()
    canvas = page.pixels()
    zoom, px, py = s["zoom"], s["panX"], s["panY"]
    h, w = canvas.shape[:2]
    out = {}
    for y in range(height):
        cy = int(py + zoom * (y + 0.5))
        for x in range(width):
            cx = int(px + zoom * (x + 0.5))
            if 0 <= cx < w and 0 <= cy < h:
                out[(x, y)] = canvas[cy, cx, :3]
    return out


def check(page, expected, what, tolerance=2.0):
    shown = shown_image(page, expected.shape[1], expected.shape[0])
    assert len(shown) > 100, f"{what}: only {len(shown)} image pixels on the canvas"
    worst = 0.0
    for (x, y), rgb in shown.items():
        worst = max(worst, float(np.max(np.abs(rgb - expected[y, x]))))
    assert worst <= tolerance, f"{what}: a shown pixel is {worst} levels from the file's"
    print(f"compare_page: {what}: {len(shown)} pixels within {worst:g} levels")


def main():
    nuld_bin = sys.argv[1]
    screenshot = sys.argv[2] if len(sys.argv) > 2 else ""
    for tool in ("chromium", "chromedriver"):
        if not shutil.which(tool):
            sys.exit(f"compare_page_test: {tool} is not installed (tools/setup.sh installs it)")
    tmp = tempfile.mkdtemp(prefix="nuld_compare_")
    try:
        env = dict(os.environ, NULD_CACHE=os.path.join(tmp, "cache"))
        env.pop("NULD_REFERENCE_CACHE", None)
        out = os.path.join(tmp, "study")
        subprocess.run([nuld_bin, "study", "render", "default", "--res", "48x32",
                        "--spp", "4,16", "--repeats", "2", "--backends", "independent,sobol",
                        "--integrator", "direct", "--reference-spp", "256", "--output", out,
                        "--no-report", "-q"], check=True, env=env, stdout=subprocess.DEVNULL)
        subprocess.run([nuld_bin, "study", "report", out], check=True, env=env,
                       stdout=subprocess.DEVNULL)
        page_path = os.path.join(out, "compare.html")
        assert os.path.exists(page_path), "nuld study report wrote no compare.html"

        opts = webdriver.ChromeOptions()
        for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=900,700",
                     "--disable-background-networking", "--disable-component-update",
                     "--no-first-run", "--disable-sync", f"--user-data-dir={tmp}/profile"):
            opts.add_argument(flag)
        opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
        try:
            run(driver, out, page_path, screenshot)
        finally:
            driver.quit()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("compare_page: passed")


def run(driver, out, page_path, screenshot):
    driver.get("file://" + os.path.abspath(page_path))
    page = Page(driver)
    s = page.wait()
    assert s["rows"] == ["reference", "independent", "sobol"], s["rows"]
    assert s["zoom"] == 1 and s["row"] == 0, s

    ref = nuld.read_image(os.path.join(out, "default", "reference.exr"))[..., :3]
    check(page, srgb8(ref), "reference at 1:1")

    # Row 2 by its key: sobol at 4 spp, then zoomed twice about the centre.
    s = page.key("2")
    sobol = nuld.read_image(os.path.join(out, "default", "sobol_spp4.exr"))[..., :3]
    check(page, srgb8(sobol), "sobol, 4 spp")
    assert np.max(np.abs(srgb8(sobol) - srgb8(ref))) > 10, "the 4-spp render looks like the reference"
    page.key("+")
    s = page.key("+")
    assert s["zoom"] == 4, s
    check(page, srgb8(sobol), "sobol zoomed 4x")
    # Inside one image pixel's 4x4 block the canvas is one colour (no smoothing).
    canvas = page.pixels()
    bx, by = int(s["panX"] + 4 * 3), int(s["panY"] + 4 * 3)
    block = canvas[by:by + 4, bx:bx + 4, :3]
    assert np.all(block == block[0, 0]), "a zoomed pixel's block is not one colour"

    # Clicking the independent row keeps the zoom and pan (one view for all).
    driver.find_elements(By.CSS_SELECTOR, "#rows button")[1].click()
    t = page.wait()
    assert (t["row"], t["zoom"], t["panX"], t["panY"]) == (1, 4, s["panX"], s["panY"]), t
    independent = nuld.read_image(os.path.join(out, "default", "independent_spp4.exr"))[..., :3]
    check(page, srgb8(independent), "independent, same view")

    # The error and FLIP maps one key away, as their PNGs are.
    page.key("e")
    error = mpimg.imread(os.path.join(out, "default", "independent_spp4_error.png"))[..., :3]
    check(page, np.round(255 * error), "independent's error map", tolerance=1)
    page.key("f")
    flip = mpimg.imread(os.path.join(out, "default", "independent_spp4_flip.png"))[..., :3]
    check(page, np.round(255 * flip), "independent's FLIP map", tolerance=1)

    # Exposure +1 stop: twice the linear values.
    page.key("i")
    page.key("]")
    s = page.key("]")
    assert s["exposure"] == 1, s
    check(page, srgb8(2 * independent), "independent at +1 stop")

    # A drag pans every image by the drag.
    before = page.state()
    ActionChains(driver).move_to_element(page.canvas).click_and_hold().move_by_offset(
        30, 20).release().perform()
    s = page.wait()
    assert (s["panX"] - before["panX"], s["panY"] - before["panY"]) == (30, 20), s
    check(page, srgb8(2 * independent), "independent after a pan")

    # Next spp keeps the row.
    s = page.key(Keys.PAGE_DOWN)
    assert s["spp"] == 1 and s["rows"][s["row"]] == "independent", s
    independent16 = nuld.read_image(os.path.join(out, "default", "independent_spp16.exr"))
    check(page, srgb8(2 * independent16[..., :3]), "independent, 16 spp")

    # "z": the largest power-of-two zoom that fits, centred.
    s = page.key("z")
    h, w = page.pixels().shape[:2]
    z = s["zoom"]
    fits, largest = 48 * z <= w and 32 * z <= h, 96 * z > w or 64 * z > h
    assert z >= 2 and fits and largest, s
    check(page, srgb8(2 * independent16[..., :3]), "independent, 16 spp, fitted")

    # Nothing but files beside the page; no errors in the console.
    # (Chromium keeps no resource timings for file://: the elements that
    # load something say where from.)
    urls = driver.execute_script("""
        return Array.from(document.querySelectorAll('script[src], link[href], img[src]'))
                    .map(e => e.src || e.href);""")
    assert len(urls) >= 4 and all(u.startswith("file://") for u in urls), urls
    errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
    assert not errors, errors
    if screenshot:
        page.key("h")
        page.key("2")
        driver.save_screenshot(screenshot)


if __name__ == "__main__":
    main()
