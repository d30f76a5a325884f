#!/usr/bin/python3
"""Take the README's picture of the lab: web/screenshot.py OUT.png [--build DIR]

Headless chromium (selenium) on the page served by serve.py: the arm let go from the horizontal
with gravity compensation off, so that it falls onto its shoulder stop, 2 s later, every overlay on.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import serve  # noqa: E402

from selenium import webdriver  # noqa: E402
from selenium.webdriver.chrome.options import Options  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('out')
    parser.add_argument('--build', default=None)
    args = parser.parse_args()
    server, url = serve.start(0, args.build)
    options = Options()
    options.binary_location = '/usr/bin/chromium'
    for flag in ('--headless=new', '--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage',
                 '--window-size=1000,760', '--force-device-scale-factor=1'):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service('/usr/bin/chromedriver'), options=options)
    try:
        driver.get(url + '?paused=1&spec=specs/5.1-lab.json')
        ready = driver.execute_async_script(
            'const done = arguments[arguments.length - 1]; window.lab.ready.then(done);')
        if not ready:
            sys.exit('the page did not get ready: %s' % driver.execute_script('return lab.errors()'))
        driver.execute_script(
            'for (const box of document.querySelectorAll("input[data-toggle]")) {'
            '  if (!box.checked) box.click();'
            '}'
            'lab.press("Arm horizontal"); lab.run(2);')
        driver.find_element(By.CSS_SELECTOR, 'section.sim').screenshot(args.out)
    finally:
        driver.quit()
        server.shutdown()
    print('wrote %s' % args.out)


if __name__ == '__main__':
    main()
