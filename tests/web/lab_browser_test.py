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
import re
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
PANDA7 = os.path.join(ROOT, 'models', 'panda7.xml')
GRIPPER = os.path.join(ROOT, 'models', 'gripper.xml')
CHECK_SPEC = os.path.join(ROOT, 'web', 'specs', '5.1-check.json')


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

    def __init__(self, query, flags=()):
        self.query = query
        self.flags = flags

    def __enter__(self):
        self.server, url = serve.start(0, ARGS.wasm)
        options = Options()
        options.binary_location = '/usr/bin/chromium'
        # WebGL on SwiftShader, Chromium's CPU renderer: the 3D view is drawn without a GPU
        for flag in ('--headless=new', '--no-sandbox', '--use-angle=swiftshader',
                     '--enable-unsafe-swiftshader', '--disable-dev-shm-usage',
                     '--window-size=1100,820', '--force-device-scale-factor=1') + tuple(self.flags):
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
    """Each readout's raw value within 1e-12 of lever's native value (or the bound given third: the
    contact solver's for what it decides), and the same digits shown."""
    for r in readouts:
        native, digits, *bound = expected[r['label']]
        if bound:
            check(abs(r['value'] - native) <= bound[0] * max(1.0, abs(native)),
                  '%s: browser %.17g, native %.17g' % (r['label'], r['value'], native))
        else:
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
PANDA = 'paused=1&spec=specs/5.2-lab.json'
GRIP = 'paused=1&spec=specs/5.3-lab.json'


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
        # (polled, not a fixed wait: on a loaded machine headless Chromium's first animation
        # frame can come later than half a second)
        b.js('window.lab.play();')
        advanced = b.driver.execute_async_script(
            'const done = arguments[arguments.length - 1], start = performance.now();'
            'const poll = () => window.lab.time() > 0 ? done(true)'
            '  : performance.now() - start > 20000 ? done(false) : setTimeout(poll, 50);'
            'poll();')
        check(advanced, 'playing did not advance the time within 20 s')
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
    # the 2D view, which the page falls back to in a browser without WebGL (view_3d_renders tests
    # the 3D one)
    with Browser(LAB, flags=('--disable-3d-apis',)) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        check(b.js('return lab.view().kind;') == '2d', 'without WebGL the page did not fall back to 2D')
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


def case_unknown_sensor_shows_an_error():
    with open(os.path.join(ROOT, 'web', 'specs', '5.3-lab.json')) as f:
        spec = f.read()
    broken = spec.replace('"sensor": "right_touch"', '"sensor": "rigth_touch"')
    check(broken != spec, 'could not find the sensor readout to break')
    line = broken[:broken.index('rigth_touch')].count('\n') + 1
    with Browser('paused=1&spec=' + urllib.parse.quote(data_url(broken, 'application/json'))) as b:
        shown = b.errors_shown()
    check(any('sensor "rigth_touch"' in s and 'left_touch, right_touch' in s and ('line %d' % line) in s
              for s in shown), 'errors shown: %s' % shown)


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


# ---- the knowledge check ------------------------------------------------------------------------

def check_spec():
    with open(CHECK_SPEC) as f:
        return json.load(f)


def wrong_answers(q):
    """Answers the grader must refuse: every other option, or a number just outside the tolerance."""
    if q['kind'] == 'numeric':
        return [q['answer'] + 1.5 * q['tol'], q['answer'] - 1.5 * q['tol'], -q['answer']]
    return [i for i in range(len(q['options'])) if i != q['answer']]


def right_answers(q):
    if q['kind'] == 'numeric':  # inside the tolerance on either side
        return [q['answer'], q['answer'] + 0.5 * q['tol'], q['answer'] - 0.5 * q['tol']]
    return [q['answer']]


def case_check_shows_every_question():
    spec = check_spec()
    with Browser(CHECK) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        check(b.errors_shown() == [], 'errors shown: %s' % b.errors_shown())
        listed = b.js('return lab.questions();')
        blocks = b.js('return [...document.querySelectorAll("section.question-block")].map(e => ({'
                      'kind: e.dataset.kind, text: e.querySelector(".prompt").textContent,'
                      'inputs: e.querySelectorAll("input.numeric").length,'
                      'options: [...e.querySelectorAll("label.option")].map(l => l.textContent.trim()),'
                      'unit: (e.querySelector(".unit") || {}).textContent,'
                      'tolerance: (e.querySelector(".tolerance") || {}).textContent,'
                      'sims: e.querySelectorAll("section.sim").length,'
                      'explainHidden: e.querySelector(".explain").hidden,'
                      'buttons: [...e.querySelectorAll("button.check")].length}));')
        title = b.js('return (document.querySelector(".check-title") || {}).textContent;')
        katex = b.js('return document.querySelectorAll(".question-block .katex").length;')
        inertial = b.js('return [...document.querySelectorAll(".question-block[data-question=\'1\'] '
                        '.prompt code")].map(e => e.textContent);')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
    questions = spec['questions']
    check(title == spec['title'], 'the check\'s title: %r' % title)
    check(len(listed) == len(questions) == len(blocks),
          '%d questions in the spec, %d listed, %d shown' % (len(questions), len(listed), len(blocks)))
    for i, (q, shown, item) in enumerate(zip(questions, blocks, listed)):
        where = 'question %d' % (i + 1)
        check(shown['kind'] == q['kind'] == item['kind'], '%s: kind %s, shown %s' % (where, q['kind'], shown))
        check('answer' not in item, '%s: lab.questions() tells the answer' % where)
        check(shown['buttons'] == 1 and shown['explainHidden'], '%s: one Check button, '
              'the explanation hidden until then: %s' % (where, shown))
        check(shown['sims'] == (1 if 'sim' in q else 0), '%s: %d sims shown' % (where, shown['sims']))
        if q['kind'] == 'numeric':
            check(shown['inputs'] == 1 and shown['unit'] == q['unit'], '%s: input and unit %s' % (where, shown))
            check(('%g' % q['tol']) in shown['tolerance'] and q['unit'] in shown['tolerance'],
                  '%s: tolerance shown as %r' % (where, shown['tolerance']))
        else:
            check(len(shown['options']) == len(q['options']), '%s: options shown %s' % (where, shown['options']))
            for option, text in zip(q['options'], shown['options']):
                # the option's text as written (tags that are not HTML stay visible)
                check(text == option, '%s: option %r shown as %r' % (where, option, text))
    # the lesson's HTML: <code> is an element, "<inertial>" inside it stays text
    check('<inertial>' in inertial, 'question 2 code elements: %s' % inertial)
    # the lesson's math: question 1's explanation has $\tau = m g c = 2 \times ...$
    check(katex >= 1, 'no KaTeX-typeset formula on the page')


def case_check_each_question_right_and_wrong():
    spec = check_spec()
    with Browser(CHECK) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        for i, q in enumerate(spec['questions']):
            where = 'question %d' % (i + 1)
            for value in wrong_answers(q):
                got = b.js('return lab.answer(arguments[0], arguments[1]);', i, value)
                state = b.js('const e = document.querySelectorAll("section.question-block")[arguments[0]];'
                             'return [e.classList.contains("wrong"), e.querySelector(".verdict").textContent,'
                             '!e.querySelector(".explain").hidden];', i)
                check(got['correct'] is False, '%s: %r graded right' % (where, value))
                check(got['explain'] == q['explain'], '%s: the explanation returned differs' % where)
                check(state[0] and state[2], '%s: after a wrong answer the page shows %s' % (where, state))
            for value in right_answers(q):
                got = b.js('return lab.answer(arguments[0], arguments[1]);', i, value)
                state = b.js('const e = document.querySelectorAll("section.question-block")[arguments[0]];'
                             'return [e.classList.contains("right"), e.querySelector(".verdict").textContent,'
                             '!e.querySelector(".explain").hidden, e.classList.contains("wrong")];', i)
                check(got['correct'] is True, '%s: %r graded wrong' % (where, value))
                check(state[0] and state[2] and not state[3], '%s: after a right answer the page shows %s'
                      % (where, state))
            # what a script may not answer: a question's other kind of value, an option that is not there
            bad = 'x' if q['kind'] == 'numeric' else len(q['options'])
            refused = b.js('try { lab.answer(arguments[0], arguments[1]); return null; }'
                           'catch (e) { return e.message; }', i, bad)
            check(refused, '%s: lab.answer(%r) was accepted' % (where, bad))
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        check(b.errors_shown() == [], 'errors shown: %s' % b.errors_shown())


def case_check_answered_by_clicks():
    # the student's way: type or choose, then click Check
    spec = check_spec()
    from selenium.webdriver.common.by import By
    with Browser(CHECK) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        blocks = b.driver.find_elements(By.CSS_SELECTOR, 'section.question-block')
        for i, (q, block) in enumerate(zip(spec['questions'], blocks)):
            for value, expected in ((wrong_answers(q)[0], 'wrong'), (q['answer'], 'right')):
                if q['kind'] == 'numeric':
                    field = block.find_element(By.CSS_SELECTOR, 'input.numeric')
                    field.clear()
                    field.send_keys(repr(value))
                else:
                    block.find_elements(By.CSS_SELECTOR, 'label.option input')[value].click()
                block.find_element(By.CSS_SELECTOR, 'button.check').click()
                classes = block.get_attribute('class').split()
                check(expected in classes, 'question %d, %r clicked: classes %s' % (i + 1, value, classes))
                check(block.find_element(By.CSS_SELECTOR, '.explain').is_displayed(),
                      'question %d: no explanation after Check' % (i + 1))
        # Check with nothing entered: no grade, a hint
        b.driver.get(b.driver.current_url)
        check(b.driver.execute_async_script(
            'const done = arguments[arguments.length - 1]; window.lab.ready.then(done);'), 'reload')
        block = b.driver.find_elements(By.CSS_SELECTOR, 'section.question-block')[0]
        block.find_element(By.CSS_SELECTOR, 'button.check').click()
        classes = block.get_attribute('class').split()
        verdict = block.find_element(By.CSS_SELECTOR, '.verdict').text
        check('right' not in classes and 'wrong' not in classes and 'number' in verdict,
              'Check with an empty answer: %s, %r' % (classes, verdict))


def case_check_html_runs_no_script():
    # a knowledge check whose text tries every way in: none runs, the allowed tags keep no attribute
    hostile = {'title': 'hostile', 'questions': [
        {'kind': 'mcq',
         'q': '<p onclick="window.pwned = 1">Pick <script>window.pwned = 2</script>'
              '<img src="x" onerror="window.pwned = 3"><b style="color:red" onmouseover="x()">one</b>'
              '<iframe src="javascript:window.pwned = 4"></iframe> $\\href{javascript:window.pwned=5}{link}$</p>',
         'options': ['<svg onload="window.pwned = 6">a', '<a href="javascript:window.pwned = 7">b</a>'],
         'answer': 0,
         'explain': '<p><script>window.pwned = 8</script><em>fine</em> &lt;script&gt;</p>'}]}
    text = json.dumps(hostile)
    with Browser('paused=1&spec=' + urllib.parse.quote(data_url(text, 'application/json'))) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.answer(0, 0); lab.answer(0, 1);')
        for option in b.js('return [...document.querySelectorAll("label.option")];'):
            option.click()
        b.driver.execute_async_script('setTimeout(arguments[arguments.length - 1], 300);')
        pwned = b.js('return window.pwned;')
        elements = b.js('const root = document.querySelector(".question-block");'
                        'return [...root.querySelectorAll("*")].filter(e => !e.closest(".katex"))'
                        '.map(e => [e.tagName.toLowerCase(), [...e.attributes].map(a => a.name)]);')
        links = b.js('return document.querySelectorAll(".question-block a").length;')
        prompt = b.js('return document.querySelector(".question-block .prompt").textContent;')
        explain = b.js('return document.querySelector(".question-block .explain").textContent;')
    check(pwned is None, 'a script in the question ran: window.pwned = %r' % pwned)
    check(links == 0, 'a link was made from the question')
    tags = {tag for tag, _ in elements}
    for tag in ('script', 'img', 'iframe', 'svg', 'a'):
        check(tag not in tags, 'a <%s> element was made from the question' % tag)
    for tag, attributes in elements:
        if tag in ('p', 'b', 'em'):
            check(attributes == [], '<%s> kept the attributes %s' % (tag, attributes))
    check('<script>window.pwned = 2</script>' in prompt, 'the script is not shown as text: %r' % prompt)
    check('fine <script>' in explain, 'entities in the explanation: %r' % explain)



def case_check_bad_question_shows_an_error():
    # a question the page cannot ask: its problem shown with the line of the spec it is on
    bad = ('{"title": "t", "questions": [\n'
           '{"kind": "numeric", "q": "fine", "answer": 1, "tol": 0.1, "explain": ""},\n'
           '{"kind": "mcq", "q": "which?", "options": ["a", "b"], "answer": 2}]}')
    with Browser('paused=1&spec=' + urllib.parse.quote(data_url(bad, 'application/json'))) as b:
        shown = b.errors_shown()
        check(not b.ready, 'a question whose answer is not one of its options was accepted')
    check(len(shown) == 1 and 'question 2' in shown[0] and 'line 3' in shown[0],
          'errors shown: %s' % shown)

# ---- the 3D view --------------------------------------------------------------------------------

def drawn_geoms(b):
    """Each geom's position and z axis (a capsule's or cylinder's) as three.js draws it, and qpos."""
    geoms = b.js('return lab.sims[0].view3d.geoms.map(g => { g.updateMatrixWorld();'
                 'const e = g.matrixWorld.elements; return [e[12], e[13], e[14], e[8], e[9], e[10]]; });')
    return geoms, b.js('return Array.from(lab.sims[0].data.qpos);')


def check_geoms_where_lever_puts_them(path, geoms, qpos):
    """MuJoCo's geom_xpos and geom_xmat's z column from lever's native body poses (lever forward)
    and the model's geom frames (lever model): the view draws every geom there."""
    native = native_forward(path, qpos)
    model = json.loads(subprocess.run([ARGS.lever, 'model', path, '--json'], check=True,
                                      capture_output=True, text=True).stdout)
    check(len(geoms) == model['ngeom'], '%d geoms drawn of %d' % (len(geoms), model['ngeom']))
    for i, drawn in enumerate(geoms):
        body = model['geom_bodyid'][i]
        xmat = native['xmat'][9 * body:9 * body + 9]
        pos = model['geom_pos'][3 * i:3 * i + 3]
        w, x, y, z = model['geom_quat'][4 * i:4 * i + 4]
        geom_z = [2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)]  # R(quat) e_z
        for k in range(3):
            row = xmat[3 * k:3 * k + 3]
            close(drawn[k], native['xpos'][3 * body + k] + sum(r * p for r, p in zip(row, pos)),
                  'geom %d position[%d]' % (i, k))
            close(drawn[3 + k], sum(r * a for r, a in zip(row, geom_z)), 'geom %d z axis[%d]' % (i, k))
    return model


def case_view_3d_renders():
    with Browser(LAB) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.press("Bent pose");')
        view = b.js('return lab.view();')
        check(view['kind'] == '3d', 'the lab has no 3D view in headless chromium: %s' % view)
        geoms, qpos = drawn_geoms(b)
        b.js('for (const box of document.querySelectorAll("input[data-toggle]")) if (!box.checked) box.click();')
        overlays = b.js('return lab.view();')
        b.js('lab.orbit(60, -20);')
        turned = b.js('return lab.view();')
        b.js('lab.zoom(2);')
        zoomed = b.js('return lab.view();')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
    check_geoms_where_lever_puts_them(ARM2, geoms, qpos)
    print('3D view: %d triangles in %d draw calls, %d pixels drawn; turned %d; zoomed out %d'
          % (view['triangles'], view['calls'], view['inked'], turned['inked'], zoomed['inked']))
    check(view['triangles'] > 100 and view['inked'] > 2000, 'the 3D view drew almost nothing: %s' % view)
    check(overlays['checksum'] != view['checksum'], 'the overlays drew nothing')
    check(turned['camera']['azimuth'] != view['camera']['azimuth'] and
          turned['camera']['elevation'] == view['camera']['elevation'] - 20, 'orbit: %s' % turned['camera'])
    check(zoomed['camera']['distance'] == 2 * turned['camera']['distance'], 'zoom: %s' % zoomed['camera'])
    check(zoomed['inked'] < turned['inked'], 'twice as far, the arm should cover fewer pixels')


def case_view_3d_every_geom_type():
    # tests/models/geoms_inertia.xml has every primitive geom type; the Menagerie-style model has
    # mesh geoms whose files are absent (drawn as nothing: lever gave them no size)
    spec = data_url('{"model": "any", "camera": {"azimuth": 120, "elevation": -25, "distance": 1.2,'
                    '"target": [0.1, 0, 0.2]}}', 'application/json')
    for path in (os.path.join(ROOT, 'tests', 'models', 'geoms_inertia.xml'),
                 os.path.join(ROOT, 'tests', 'menagerie', 'panda_style.xml')):
        with open(path) as f:
            xml = f.read()
        # the page has no MPR (mesh pairs): it refuses a model whose meshes can collide, so the
        # collision meshes are drawn here with their collisions off
        xml = xml.replace('<geom type="mesh" group="3"/>',
                          '<geom type="mesh" group="3" contype="0" conaffinity="0"/>')
        query = 'paused=1&spec=%s&model=%s' % (urllib.parse.quote(spec),
                                                urllib.parse.quote(data_url(xml, 'application/xml')))
        with Browser(query) as b:
            check(b.ready, '%s: the page did not get ready: %s' % (path, b.errors_shown()))
            view = b.js('return lab.view();')
            geoms, qpos = drawn_geoms(b)
            meshes = b.js('return lab.sims[0].view3d.geoms.map(g => g.children.length);')
            check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        model = check_geoms_where_lever_puts_them(path, geoms, qpos)
        check(view['kind'] == '3d' and view['inked'] > 500, '%s: %s' % (path, view))
        for i, (kind, parts) in enumerate(zip(model['geom_type'], meshes)):
            sized = all(x > 0 for x in model['geom_size'][3 * i:3 * i + 3 if kind in (4, 6, 7) else 3 * i + 1])
            # a capsule is a tube and two caps; every other sized geom one shape; a mesh lever did
            # not read, none
            expected = 3 if kind == 3 else (1 if sized else 0)
            check(parts == expected, '%s: geom %d (type %d) drawn with %d shapes' % (path, i, kind, parts))
        print('%s: %d geoms of types %s, %d triangles' % (os.path.basename(path), model['ngeom'],
                                                         sorted(set(model['geom_type'])), view['triangles']))


def native_forward(model, qpos, qvel=None, ctrl=None):
    args = [ARGS.lever, 'forward', model, '--json', '--qpos', ','.join(repr(x) for x in qpos)]
    if qvel is not None:
        args += ['--qvel', ','.join(repr(x) for x in qvel)]
    if ctrl is not None:
        args += ['--ctrl', ','.join(repr(x) for x in ctrl)]
    out = subprocess.run(args, capture_output=True, text=True)
    check(out.returncode in (0, 1) and out.stdout, 'lever forward failed: %s' % out.stderr)
    return json.loads(out.stdout)


# ---- lesson 5.2's lab: panda7 --------------------------------------------------------------------

def smallest_singular_value(native, site, nv):
    """sigma_min of [jacp; jacr] of `site` from `lever forward --json`, by numpy's SVD (LAPACK)."""
    import numpy
    n = 3 * nv
    jac = numpy.array(native['site_jacp'][site * n:(site + 1) * n] +
                      native['site_jacr'][site * n:(site + 1) * n]).reshape(6, nv)
    return numpy.linalg.svd(jac, compute_uv=False)[-1]


def panda_expected(row, sigma):
    expected = {}
    for j in range(7):
        expected['qfrc_bias, joint%d (N m)' % (j + 1)] = (row['qfrc_bias'][j], 3)
        expected['actuator_force, joint%d (N m)' % (j + 1)] = (row['actuator_force'][j], 3)
    expected['smallest singular value of J(ee)'] = (sigma, 4)
    return expected


def panda_run_matches_native(b, targets, gravity_compensation, seconds):
    """The page's state after `seconds` against `lever simulate` from keyframe home."""
    qpos = b.js('return Array.from(lab.sims[0].data.qpos);')
    qvel = b.js('return Array.from(lab.sims[0].data.qvel);')
    readouts = b.js('return lab.readouts();')
    options = ['--key', 'home', '--ctrl', ','.join(repr(t) for t in targets), '--duration', str(seconds)]
    if gravity_compensation:
        options.append('--gravity-compensation')
    row = native_last_row(PANDA7, *options)
    home = native_last_row(PANDA7, '--key', 'home', '--steps', '0')['qpos']
    check(max(abs(a - b_) for a, b_ in zip(row['qpos'], home)) > 0.1, 'the native run should move the arm')
    for i in range(7):
        close(qpos[i], row['qpos'][i], 'qpos[%d]' % i)
        close(qvel[i], row['qvel'][i], 'qvel[%d]' % i)
    native = native_forward(PANDA7, row['qpos'], row['qvel'], row['ctrl'])
    sigma = smallest_singular_value(native, 0, 7)
    readouts_match(readouts, panda_expected(row, sigma))
    return row


def case_panda_lab_matches_native():
    targets = [0.3, 0.4, -0.2, -1.2, 0.5, 1.9, -0.7853]
    with Browser(PANDA) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        check(b.js('return lab.view().kind;') == '3d', 'panda7 is not shown in 3D')
        # Reset and Home put every slider on the keyframe's targets
        sliders = b.js('return [1, 2, 3, 4, 5, 6, 7].map(j => Number(document.querySelectorAll('
                       '".controls input[type=range]")[j - 1].value));')
        home = native_last_row(PANDA7, '--key', 'home', '--steps', '0')
        for j in range(7):
            close(sliders[j], home['ctrl'][j], 'joint%d slider at home' % (j + 1))
        b.js('lab.press("Home");' + ''.join('lab.set("q%d", %r);' % (j + 1, t) for j, t in enumerate(targets)) +
             'lab.run(1.5);')
        check(b.js('return lab.time();') > 1.49, 'the run did not advance')
        panda_run_matches_native(b, targets, True, 1.5)
        # gravity compensation off: the servos alone, from home again
        b.js('lab.set("gc", 0); lab.press("Home");' +
             ''.join('lab.set("q%d", %r);' % (j + 1, t) for j, t in enumerate(targets)) + 'lab.run(1);')
        panda_run_matches_native(b, targets, False, 1)
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        check(b.errors_shown() == [], 'errors shown: %s' % b.errors_shown())


def case_panda_singular_pose_buttons():
    with Browser(PANDA) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        shown = {}
        for button in ('Home', 'Singular: joint2 at 0', 'Nearly straight up'):
            b.js('lab.press(arguments[0]);', button)
            readout = b.js('return lab.readouts().find(r => r.label.startsWith("smallest singular"));')
            qpos = b.js('return Array.from(lab.sims[0].data.qpos);')
            targets = b.js('return [1, 2, 3, 4, 5, 6, 7].map(j => lab.sims[0].ctx["q" + j]);')
            check(targets == qpos, '%s: the targets %s are not the pose %s' % (button, targets, qpos))
            sigma = smallest_singular_value(native_forward(PANDA7, qpos), 0, 7)
            close(readout['value'], sigma, '%s: smallest singular value' % button)
            shown[button] = sigma
        # held by gravity compensation, the singular pose stays singular
        b.js('lab.press("Singular: joint2 at 0"); lab.run(1);')
        moved = b.js('return Array.from(lab.sims[0].data.qpos);')
    print('smallest singular value of J(ee): %s' % ', '.join('%s %.3g' % kv for kv in shown.items()))
    check(shown['Singular: joint2 at 0'] < 1e-3 * shown['Home'], 'the singular pose is not singular: %s' % shown)
    # joint4 cannot reach 0 (its range ends at -0.0698 rad): close to the singularity, not on it
    check(0 < shown['Nearly straight up'] < shown['Home'], 'straight up is not nearer singular than home: %s'
          % shown)
    drift = max(abs(a - b_) for a, b_ in zip(moved, [0, 0, 2.048, -0.4762, -2.1231, 0.5167, 0]))
    check(drift < 1e-3, 'gravity compensation let the arm drift %.3g rad from the pose' % drift)


def case_panda_real_time():
    # plays as a student sees it for a few seconds: the frame rate and the simulated seconds per wall
    # second (printed for the record; speed is not asserted in a test: a loaded machine is slower)
    with Browser(PANDA) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        b.js('lab.play();')
        rate = b.driver.execute_async_script(
            'const done = arguments[arguments.length - 1];'
            'setTimeout(() => lab.rate(4).then(done), 500);')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        check(b.errors_shown() == [], 'errors shown: %s' % b.errors_shown())
    print('panda7 in headless chromium (SwiftShader WebGL): %.1f frames per second, %.3f simulated seconds '
          'per wall second over %.1f s' % (rate['frames_per_second'], rate['sim_seconds_per_wall_second'],
                                          rate['wall']))
    check(rate['frames_per_second'] > 0 and rate['sim_seconds_per_wall_second'] > 0,
          'the lab did not run: %s' % rate)


# ---- lesson 5.3's lab: the gripper, contacts --------------------------------------------------

CONTACT_TYPES = (5, 6, 7)  # efc_type of a contact row: frictionless, pyramidal, elliptic


def native_contact_rows(native):
    """Contact index -> its rows in `lever forward --json` (efc_id of each contact row)."""
    rows = {}
    for r, (kind, cid) in enumerate(zip(native['efc_type'], native['efc_id'])):
        if kind in CONTACT_TYPES:
            rows.setdefault(cid, []).append(r)
    return rows


def gripper_state(b):
    """The page's state, its contacts (lever's data.contact), the 3D view's markers, its readouts."""
    return b.js('const d = lab.sims[0].data; return {qpos: Array.from(d.qpos), qvel: Array.from(d.qvel),'
                'ctrl: Array.from(d.ctrl), ncon: d.ncon, contacts: d.contact.map(c => ({pos: Array.from(c.pos),'
                'normal: Array.from(c.frame.subarray(0, 3)), dist: c.dist, geom1: c.geom1, geom2: c.geom2})),'
                'markers: lab.contactMarkers(), readouts: lab.readouts(),'
                'box: lab.sims[0].model.name2id("body", "box"), table: lab.sims[0].model.name2id("geom", "table")};')


def normal_per_newton():
    """The 3D view's scale of a contact's normal line, m per N (view3d.js's NORMAL_PER_NEWTON)."""
    with open(os.path.join(ROOT, 'web', 'view3d.js'), encoding='utf-8') as f:
        text = f.read()
    return float(re.search(r'NORMAL_PER_NEWTON = ([0-9.eE+-]+)', text).group(1))


def check_contacts_drawn_and_read(state, label):
    """The markers on lever's contacts, the contacts those of lever's native rows, the readouts
    native's. Returns the native forward."""
    native = native_forward(GRIPPER, state['qpos'], state['qvel'], state['ctrl'])
    rows = native_contact_rows(native)
    ncon = native.get('ncon', len(rows))
    check(state['ncon'] == ncon == len(state['contacts']), '%s: ncon %d, native %d, %d contacts in data.contact'
          % (label, state['ncon'], ncon, len(state['contacts'])))
    for cid, contact_rows in rows.items():
        for r in contact_rows:  # a contact row's efc_pos is its contact's dist
            close(state['contacts'][cid]['dist'], native['efc_pos'][r], '%s: contact %d dist' % (label, cid))
    if isinstance(native.get('contact'), list):  # where `lever forward` prints contacts itself
        for i, theirs in enumerate(native['contact']):
            for k in range(3):
                close(state['contacts'][i]['pos'][k], theirs['pos'][k], '%s: contact %d pos' % (label, i))
    markers = state['markers']
    check(len(markers) == ncon, '%s: %d contact markers drawn for %d contacts' % (label, len(markers), ncon))
    lengths = []
    for i, (marker, contact) in enumerate(zip(markers, state['contacts'])):
        check(marker['pos'] == contact['pos'], '%s: marker %d at %s, contact at %s'
              % (label, i, marker['pos'], contact['pos']))
        # the normal's line: its tip is held in float32 (a WebGL vertex), 1e-7 of its ~0.1 m
        d = [t - p for t, p in zip(marker['tip'], contact['pos'])]
        length = sum(x * x for x in d) ** 0.5
        lengths.append(length)
        check(length > 0 and all(abs(x / length - n) < 1e-5 for x, n in zip(d, contact['normal'])),
              '%s: marker %d points along %s, the normal is %s' % (label, i, d, contact['normal']))
    # each normal scaled by its contact's normal force (mj_contactForce), as native computes it
    forces = [c['force'][0] for c in native.get('contact', [])]
    check(len(forces) == len(lengths), '%s: native prints %d contact forces for %d normals'
          % (label, len(forces), len(lengths)))
    for i, (length, force) in enumerate(zip(lengths, forces)):
        check(abs(length - normal_per_newton() * force) < 1e-6,
              '%s: normal %d drawn %.9f m long for a normal force of %.9f N (%g m per N)'
              % (label, i, length, force, normal_per_newton()))
    box = state['box']
    penetration = min([0.0] + [native['efc_pos'][r[0]] for r in rows.values()])
    readouts_match(state['readouts'], {
        'contacts (ncon)': (ncon, 0),
        'box height (m)': (native['xpos'][3 * box + 2], 4),
        'left finger servo force (N)': (native['actuator_force'][1], 3),
        'right finger servo force (N)': (native['actuator_force'][2], 3),
        'deepest penetration (mm)': (1000 * penetration, 3),
        # touch sums contact forces: the solver's outputs, held to its bound (tools/diff's
        # kContactSolverBound; api_node_test.js says why wasm and native differ there at all)
        'left pad touch (N)': (native['sensordata'][0], 3, 1e-10),
        'right pad touch (N)': (native['sensordata'][1], 3, 1e-10),
    })
    return native


def case_gripper_contacts_match_native():
    with Browser(GRIP) as b:
        check(b.ready, 'the page did not get ready: %s' % b.errors_shown())
        check(b.js('return lab.view().kind;') == '3d', 'the gripper is not shown in 3D')
        check(b.js('const m = lab.sims[0].model; return [m.nq, m.nv, lab.sims[0].data.qpos.length,'
                   'lab.sims[0].data.qvel.length];') == [10, 9, 10, 9], 'qpos/qvel not sized for the free box')
        b.js('lab.press("Down to the box"); lab.run(0.6); lab.press("Grip"); lab.run(0.5);')
        gripped = gripper_state(b)
        shown = b.js('return lab.view();')
        b.js('document.querySelector("input[data-toggle=contacts]").click();')
        hidden = b.js('return [lab.view(), lab.contactMarkers()];')
        b.js('document.querySelector("input[data-toggle=contacts]").click(); lab.press("Lift"); lab.run(0.6);')
        lifted = gripper_state(b)
        geoms, qpos = drawn_geoms(b)  # the free box drawn at its qpos (position, quaternion)
        b.js('lab.play();')  # the real-time loop on a model with contacts
        b.driver.execute_async_script('setTimeout(arguments[arguments.length - 1], 500);')
        check(b.console_errors() == [], 'console errors: %s' % b.console_errors())
        check(b.errors_shown() == [], 'errors shown: %s' % b.errors_shown())
        # the grip-force plot's sensor trace is the left pad's touch, sampled as the readouts are
        traces = b.js('const p = lab.sims[0].plotSpecs[1]; return p.traces.map(t => t.spec.label);')
        check(traces == ['left pad touch (N)', 'left servo force (N)'], 'grip plot traces: %s' % traces)
    check_contacts_drawn_and_read(gripped, 'gripped')
    check_contacts_drawn_and_read(lifted, 'lifted')
    check_geoms_where_lever_puts_them(GRIPPER, geoms, qpos)
    check(hidden[1] == [] and hidden[0]['checksum'] != shown['checksum'],
          'turning the contacts overlay off changed nothing')
    # the lesson's physics: on the table and between the fingers, then held up by the fingers alone
    table_contacts = [sum(1 for c in s['contacts'] if s['table'] in (c['geom1'], c['geom2']))
                      for s in (gripped, lifted)]
    heights = [s['readouts'][1]['value'] for s in (gripped, lifted)]
    # the pads feel the grip: held up, each reads what its servo pushes, to 1 %
    readout = {r['label']: r['value'] for r in lifted['readouts']}
    for side in ('left', 'right'):
        touch, servo = readout[side + ' pad touch (N)'], abs(readout[side + ' finger servo force (N)'])
        check(touch > 1.0 and abs(touch - servo) <= 0.01 * servo,
              'lifted: the %s pad reads %.4f N, its servo pushes %.4f N' % (side, touch, servo))
    print('gripper: %d contacts (%d on the table) gripped at box height %.4f m; %d (%d) lifted at %.4f m'
          % (gripped['ncon'], table_contacts[0], heights[0], lifted['ncon'], table_contacts[1], heights[1]))
    check(table_contacts[0] > 0 and gripped['ncon'] > table_contacts[0], 'gripped: no table and finger contacts')
    check(table_contacts[1] == 0 and lifted['ncon'] > 0 and heights[1] > 0.1, 'lifted: the box is not held up')


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
