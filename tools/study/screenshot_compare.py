#!/usr/bin/python3
"""Screenshots a study's comparison page (STUDY_DIR/compare.html) as a reader
sees it: Debian's headless Chromium through chromedriver and Selenium
(tools/setup.sh installs them), a 1200 x 800 window, after pressing KEYS on
the page (its keys: 0-9 rows, e/f/i maps, + zoom, ] exposure, ...).

Usage: screenshot_compare.py STUDY_DIR OUT.png [KEYS]
Example: screenshot_compare.py out 'docs/images/compare_page.png' '2++'
"""
import os
import sys
import tempfile

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    study, out = sys.argv[1], sys.argv[2]
    keys = sys.argv[3] if len(sys.argv) == 4 else ""
    page = os.path.join(study, "compare.html")
    if not os.path.exists(page):
        sys.exit(f"screenshot_compare: {page}: no such page (run nuld study report first)")
    with tempfile.TemporaryDirectory() as profile:
        opts = webdriver.ChromeOptions()
        for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1200,800",
                     "--disable-background-networking", "--no-first-run",
                     f"--user-data-dir={profile}"):
            opts.add_argument(flag)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
        try:
            driver.get("file://" + os.path.abspath(page))
            ready = "return nuldCompare.state().ready;"
            WebDriverWait(driver, 60).until(lambda d: d.execute_script(ready))
            canvas = driver.find_element(By.ID, "canvas")
            for k in keys:
                canvas.send_keys(k)
                WebDriverWait(driver, 60).until(lambda d: d.execute_script(ready))
            if not driver.save_screenshot(out):
                sys.exit(f"screenshot_compare: chromium wrote no {out}")
        finally:
            driver.quit()
    print(f"screenshot_compare: {out}")


if __name__ == "__main__":
    main()
