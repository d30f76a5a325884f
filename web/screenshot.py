#!/usr/bin/python3
"""Take the README's pictures of the lab: web/screenshot.py OUT.png [--spec SPEC] [--build DIR]

Headless chromium (selenium, WebGL on SwiftShader) on the page served by serve.py, the first
simulation's section cropped:
  specs/5.1-lab.json (the default): arm2 let go from the horizontal with gravity compensation off,
      so that it falls onto its shoulder stop, 2 s later, every overlay on;
  specs/5.2-lab.json: panda7 from its home keyframe sent to other targets, 1.5 s later, holding
      them with gravity compensation, the ee trail behind it;
  specs/5.3-lab.json: the gripper down on the box, closed on it and lifted, its contacts drawn.
Any other spec is shot as it loads; --script JS runs JS (window.lab's API) first instead.
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

SCENES = {
    'specs/5.1-lab.json': 'lab.press("Arm horizontal"); lab.run(2);',
    'specs/5.2-lab.json': 'lab.press("Home"); lab.set("q1", 0.6); lab.set("q2", 0.5); '
                          'lab.set("q4", -1.9); lab.set("q6", 2.2); lab.run(1.5);',
    'specs/5.3-lab.json': 'lab.press("Down to the box"); lab.run(0.6); lab.press("Grip"); lab.run(0.5); '
                          'lab.press("Lift"); lab.run(0.3);',
}
ALL_OVERLAYS = ('for (const box of document.querySelectorAll("input[data-toggle]")) {'
                '  if (!box.checked) box.click();'
                '}')


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('out')
    parser.add_argument('--spec', default='specs/5.1-lab.json', help='the spec, relative to web/')
    parser.add_argument('--script', default=None, help='JavaScript to run before the picture')
    parser.add_argument('--build', default=None)
    args = parser.parse_args()
    script = args.script if args.script is not None else SCENES.get(args.spec, '')
    if args.spec == 'specs/5.1-lab.json' and args.script is None:
        script = ALL_OVERLAYS + script
    server, url = serve.start(0, args.build)
    options = Options()
    options.binary_location = '/usr/bin/chromium'
    for flag in ('--headless=new', '--no-sandbox', '--use-angle=swiftshader',
                 '--enable-unsafe-swiftshader', '--disable-dev-shm-usage',
                 '--window-size=1000,1500', '--force-device-scale-factor=1'):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service('/usr/bin/chromedriver'), options=options)
    try:
        driver.get(url + '?paused=1&spec=' + args.spec)
        ready = driver.execute_async_script(
            'const done = arguments[arguments.length - 1]; window.lab.ready.then(done);')
        if not ready:
            sys.exit('the page did not get ready: %s' % driver.execute_script('return lab.errors()'))
        driver.execute_script(script)
        errors = driver.execute_script('return lab.errors()')
        if errors:
            sys.exit('the page shows errors: %s' % errors)
        driver.find_element(By.CSS_SELECTOR, 'section.sim').screenshot(args.out)
    finally:
        driver.quit()
        server.shutdown()
    print('wrote %s' % args.out)


if __name__ == '__main__':
    main()
