#!/usr/bin/python3
"""The lab page (web/) in a real browser: Debian's chromium, headless, driven by python3-selenium
and chromium-driver, the page served from 127.0.0.1 on a free port by web/serve.py for the length
of one case.

    lab_browser_test.py --lever LEVER --wasm DIR [--screenshot FILE] CASE

CASE is one of the functions named case_* below (ctest runs each as web.<case>). Expected numbers
come from lever's native build, run here through the `lever simulate` command: the browser's
readouts must show the same digits and hold the same raw values to 1e-12.
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile
import urllib.parse
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, 'web'))
import serve  # noqa: E402

from selenium import webdriver  # noqa: E402
from selenium.webdriver.chrome.options import Options  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402

ARGS = None
ARM2 = os.path.join(ROOT, 'models', 'arm2.xml')


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def close(ours, theirs, what):
    # lever's bound: |ours - reference| <= 1e-12 * max(1, |reference|)
    check(abs(ours - theirs) <= 1e-12 * max(1.0, abs(theirs)),
          '%s: browser %.17g, native %.17g (difference %.3g)' % (what, ours, theirs, ours - theirs))


class Browser:
    """The page in headless chromium, served for as long as the `with` block lasts."""

    def __init__(self, query):
        self.query = query

    def __enter__(self):
        self.server, url = serve.start(0, ARGS.wasm)
        options = Options()
        options.binary_location = '/usr/bin/chromium'
        for flag in ('--headless=new', '--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage',
                     '--window-size=1100,820', '--force-device-scale-factor=1'):
            options.add_argument(flag)
        options.set_capability('goog:loggingPrefs', {'browser': 'ALL'})
        try:
            self.driver = webdriver.Chrome(service=Service('/usr/bin/chromedriver'), options=options)
        except Exception:
            self.server.shutdown()
            raise
        self.driver.set_script_timeout(60)
        self.driver.get(url + '?' + self.query)
        self.ready = self.driver.execute_async_script(
            'const done = arguments[arguments.length - 1]; window.lab.ready.then(done);')
        return self

    def __exit__(self, *exc):
        self.driver.quit()
        self.server.shutdown()
        self.server.server_close()

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def errors_shown(self):
        return self.js('return window.lab.errors();')

    def console_errors(self):
        return [e for e in self.driver.get_log('browser') if e['level'] == 'SEVERE']


def native_last_row(*options):
    """The last state of `lever simulate ... --json` (lever's native build)."""
    out = subprocess.run([ARGS.lever, 'simulate', *options, '--json'], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def readouts_match(readouts, expected):
    """Each readout's raw value within 1e-12 of lever's native value, and the same digits shown."""
    for r in readouts:
        native, digits = expected[r['label']]
        close(r['value'], native, r['label'])
        shown = '%.*f' % (digits, native)
        check(r['text'] == shown, '%s shows %s; native gives %s' % (r['label'], r['text'], shown))


def lab_expected(row):
    return {
        'qfrc_bias, shoulder (N m)': (row['qfrc_bias'][0], 3),
        'qfrc_bias, elbow (N m)': (row['qfrc_bias'][1], 3),
        'applied, shoulder (N m)': (row['actuator_force'][0], 2),
        'applied, elbow (N m)': (row['actuator_force'][1], 2),
        'limit force, shoulder (N m)': (row['qfrc_constraint'][0], 3),
    }


LAB = 'paused=1&spec=specs/5.1-lab.json'
CHECK = 'paused=1&spec=specs/5.1-check.json'


# ---- cases ------------------------------------------------------------------------------------

def case_loads_without_console_errors():
    with Browser(LAB) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        check(b.errors_shown() == [], 'errors shown on the page: %s' % b.errors_shown())
        labels = b.js('return [...document.querySelectorAll("button")].map(e => e.textContent);')
        for label in ('Arm horizontal', 'Bent pose', 'Play', 'Reset'):
            check(label in labels, 'no button %r (buttons: %s)' % (label, labels))
        check(len(b.js('return window.lab.readouts();')) == 5, 'the lab has five readouts')
        # play for a moment: the real-time loop runs without error
        b.js('window.lab.play();')
        b.driver.execute_async_script('setTimeout(arguments[arguments.length - 1], 500);')
        check(b.js('return window.lab.time();') > 0, 'playing did not advance the time')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        check(b.errors_shown() == [], 'errors shown after playing: %s' % b.errors_shown())


def case_bent_pose_gravity_compensation_matches_native():
    with Browser(LAB) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.press("Bent pose"); lab.set("gc", 1); lab.run(2);')
        readouts = b.js('return lab.readouts();')
        time = b.js('return lab.time();')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
    row = native_last_row(ARM2, '--qpos', '0.6,-1.2', '--gravity-compensation', '--duration', '2')
    close(time, row['time'], 'time')
    readouts_match(readouts, lab_expected(row))


def case_torques_and_gravity_compensation_match_native():
    # a run that moves: both torques on, from the horizontal pose
    with Browser(LAB) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.press("Arm horizontal"); lab.set("t1", 5); lab.set("t2", -2.5); lab.set("gc", 1);'
             'lab.run(2);')
        readouts = b.js('return lab.readouts();')
        qpos = b.js('return Array.from(lab.sims[0].data.qpos);')
        qvel = b.js('return Array.from(lab.sims[0].data.qvel);')
    row = native_last_row(ARM2, '--qpos', '0,0', '--torque', '5,-2.5', '--gravity-compensation',
                          '--duration', '2')
    check(max(abs(v) for v in row['qpos']) > 0.1, 'the native run should move the arm')
    for i in range(2):
        close(qpos[i], row['qpos'][i], 'qpos[%d]' % i)
        close(qvel[i], row['qvel'][i], 'qvel[%d]' % i)
    readouts_match(readouts, lab_expected(row))


def case_quiz_heavier_link_rests_past_the_stop():
    # the knowledge check's sim: link 2 at 1.6 kg, left to settle for the lesson's 60 s
    with Browser(CHECK) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.set("link 2 mass", 1.6); lab.run(60);')
        readouts = b.js('return lab.readouts();')
        mass = b.js('return lab.sims[0].model.body_mass[2];')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        check(b.errors_shown() == [], 'errors shown: %s' % b.errors_shown())
    check(mass == 1.6, 'body_mass[2] is %r after the slider' % mass)
    # the same run natively: arm2 with link 2 at 1.6 kg, from the sim's setup pose
    with open(ARM2) as f:
        xml = f.read()
    heavier = xml.replace('<inertial pos="0.2 0 0" mass="0.8"', '<inertial pos="0.2 0 0" mass="1.6"')
    check(heavier != xml, 'could not find link 2 inertial in arm2.xml')
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, 'arm2-heavy.xml')
        with open(path, 'w') as f:
            f.write(heavier)
        row = native_last_row(path, '--qpos', '-1.2,-0.3708', '--duration', '60')
    past = 1000 * (-1.2 - row['qpos'][0])
    readouts_match(readouts, {'past the stop (mrad)': (past, 3),
                              'limit force (N m)': (row['qfrc_constraint'][0], 3)})
    # the lesson's printed answer to this question (its three decimals)
    check(readouts[0]['text'] == '0.665', 'past the stop: %s mrad' % readouts[0]['text'])


def count_non_blank(png):
    """Pixels of an RGB(A) PNG that are not the page's white, decoded with zlib (no imaging library)."""
    with open(png, 'rb') as f:
        data = f.read()
    check(data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG')
    pos, idat, width, height, channels = 8, b'', 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b'IHDR':
            width, height, depth, color = struct.unpack('>IIBB', body[:10])
            check(depth == 8 and color in (2, 6), 'unexpected PNG format')
            channels = 3 if color == 2 else 4
        elif kind == b'IDAT':
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    previous = bytearray(stride)
    count = 0
    for y in range(height):
        row_start = y * (stride + 1)
        kind = raw[row_start]
        line = bytearray(raw[row_start + 1:row_start + 1 + stride])
        for i in range(stride):  # undo the PNG filter of this row
            a = line[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        for x in range(width):
            px = line[x * channels:x * channels + 3]
            if px[0] < 250 or px[1] < 250 or px[2] < 250:
                count += 1
        previous = line
    return count, width * height


def case_screenshot_is_not_blank():
    path = ARGS.screenshot or os.path.join(tempfile.gettempdir(), 'lever-lab-%d.png' % os.getpid())
    with Browser(LAB) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.set("t1", 3); lab.press("Arm horizontal"); lab.run(3);')
        b.driver.save_screenshot(path)
        view = b.js('const c = document.querySelector("canvas.view");'
                    'const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;'
                    'let n = 0; for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n++; return n;')
    inked, total = count_non_blank(path)
    print('screenshot %s: %d of %d pixels not blank (%.1f%%); the arm view: %d drawn pixels'
          % (path, inked, total, 100.0 * inked / total, view))
    check(inked > 0.02 * total, 'the screenshot is almost blank: %d of %d pixels' % (inked, total))
    check(view > 1000, 'the arm view has only %d drawn pixels' % view)
    if not ARGS.screenshot:
        os.remove(path)


def data_url(text, kind):
    return 'data:%s,%s' % (kind, urllib.parse.quote(text))


def case_bad_spec_shows_an_error():
    bad = '{"model": "arm2",\n "controls": [\n {"label": "x" "param": "x"}]}'
    with Browser('paused=1&spec=' + urllib.parse.quote(data_url(bad, 'application/json'))) as b:
        shown = b.errors_shown()
        check(not b.ready, 'a spec that does not parse was accepted')
        check(len(shown) == 1 and 'not valid JSON' in shown[0], 'errors shown: %s' % shown)
        check('line 3' in shown[0], 'the error does not name line 3: %s' % shown[0])
        visible = b.js('return !document.getElementById("errors").hidden;')
        check(visible, 'the error box is hidden')


def case_throwing_expression_shows_an_error():
    with open(os.path.join(ROOT, 'web', 'specs', '5.1-lab.json')) as f:
        spec = f.read()
    broken = spec.replace('"expr": "data.qfrc_bias[1]"', '"expr": "data.no_such_field[1]"')
    check(broken != spec, 'could not find the readout to break')
    line = broken[:broken.index('no_such_field')].count('\n') + 1
    with Browser('paused=1&spec=' + urllib.parse.quote(data_url(broken, 'application/json'))) as b:
        shown = b.errors_shown()
    check(any('no_such_field' in s and 'TypeError' in s and ('line %d' % line) in s for s in shown),
          'errors shown: %s' % shown)


def case_refused_model_shows_an_error():
    with open(ARM2) as f:
        xml = f.read().replace('range="-2.6 2.6"', 'rnage="-2.6 2.6"')
    query = 'paused=1&model=' + urllib.parse.quote(data_url(xml, 'application/xml'))
    with Browser(query) as b:
        shown = b.errors_shown()
    line = xml[:xml.index('rnage')].count('\n') + 1
    check(len(shown) == 1 and "unknown attribute 'rnage'" in shown[0] and
          ('line %d' % line) in shown[0], 'errors shown: %s' % shown)


def case_lever_check_matches_native():
    # lesson 5.1's six checks (lever::check) compiled to WebAssembly print what `lever check` prints
    with open(ARM2) as f:
        xml = f.read()
    with Browser(LAB) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        ours = b.js('return lab.mj.lever_check(arguments[0], "models/arm2.xml");', xml)
    native = subprocess.run([ARGS.lever, 'check', 'models/arm2.xml'], cwd=ROOT,
                            capture_output=True, text=True)
    check(native.returncode in (0, 1) and native.stdout, 'lever check failed: %s' % native.stderr)
    check(ours == native.stdout, 'the browser\'s check differs from lever check:\n%s\n---\n%s'
          % (ours, native.stdout))


def main():
    global ARGS
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--lever', required=True, help="lever's native command")
    parser.add_argument('--wasm', required=True, help='folder with lever_wasm.js and lever_wasm.wasm')
    parser.add_argument('--screenshot', help='keep the screenshot here')
    parser.add_argument('case')
    ARGS = parser.parse_args()
    case = globals().get('case_' + ARGS.case)
    if case is None:
        sys.exit('no case %r' % ARGS.case)
    try:
        case()
    except Failure as e:
        print('FAILED: %s: %s' % (ARGS.case, e))
        sys.exit(1)
    print('passed: %s' % ARGS.case)


if __name__ == '__main__':
    main()
