// lab.js: runs a lesson's lab spec (the JSON of a ```lab``` block, or a knowledge check whose
// questions carry a "sim") on lever's WebAssembly build, with MuJoCo's names in scope for the
// spec's strings: `model`, `data`, `ctx` (the controls' values by param) and `mj`. A readout or a
// plot trace gives either an "expr" or a "sensor" by name (and "index" for one of its several
// numbers): {"label": "left pad (N)", "sensor": "left_touch"} reads data.sensordata.
//
// One step of a simulation is what lesson 5.1's lab does: mj_forward (so that the controller reads
// the current state's qfrc_bias, ...), the controller, mj_step. Between steps (paused, after a
// run, after a button) the page shows the current state under the command the controller gives it
// (mj_forward, controller, mj_forward): the same numbers as `lever simulate --json`'s last row.
//
// A knowledge check (a spec with "questions") is shown whole, in order: each question with its
// input or options, a Check button and its explanation (web/quiz.js), and a question's sim under it.
//
// The view is 3D (web/view3d.js, three.js) where WebGL is available, else the 2D drawing below.
//
// URL: ?spec=URL (default specs/5.1-lab.json), &model=URL (default models/<spec.model>.xml),
// &paused=1 (start paused), &view=2d (the 2D view even with WebGL). window.lab drives the page as
// its controls do: lab.press(label), lab.set(param or label, value), lab.run(seconds),
// lab.readouts(), lab.play(), lab.pause(), lab.reset(), lab.errors(), lab.questions(),
// lab.answer(question, value) -> {correct, explain}, lab.view() (which view, what it drew),
// lab.rate() (frames and simulated seconds per wall second while playing); lab.ready resolves
// when the page is built (or has shown an error); lab.mj is web/lever.js's API itself.
(function () {
  'use strict';

  const params = new URLSearchParams(window.location.search);
  const errorBox = document.getElementById('errors');
  const shownErrors = [];

  /** A problem with the spec, located at a line of its text (0: no line). */
  class SpecError extends Error {
    constructor(message, line) {
      super(message);
      this.name = 'SpecError';
      this.line = line || 0;
    }
  }

  function showError(where, message, line) {
    const text = where + (line ? ', line ' + line : '') + ': ' + message;
    shownErrors.push(text);
    const div = document.createElement('div');
    div.textContent = text;
    errorBox.appendChild(div);
    errorBox.hidden = false;
  }

  function lineAt(text, index) {
    let line = 1;
    for (let i = 0; i < index && i < text.length; i++) if (text[i] === '\n') line++;
    return line;
  }

  // the line of the spec text where a string of it is written (0 if it cannot be found)
  function lineOfString(specText, value) {
    const index = specText.indexOf(JSON.stringify(value).slice(1, -1));
    return index < 0 ? 0 : lineAt(specText, index);
  }

  function parseSpec(text) {
    try {
      return JSON.parse(text);
    } catch (e) {
      let line = 0;
      const byLine = /line (\d+)/.exec(e.message);
      const byPosition = /position (\d+)/.exec(e.message);
      if (byLine) line = Number(byLine[1]);
      else if (byPosition) line = lineAt(text, Number(byPosition[1]));
      throw new SpecError('the spec is not valid JSON: ' + e.message, line);
    }
  }

  async function fetchText(url, what) {
    let response;
    try {
      response = await fetch(url);
    } catch (e) {
      throw new SpecError('cannot load the ' + what + ' ' + url + ': ' + e.message);
    }
    if (!response.ok) {
      throw new SpecError('cannot load the ' + what + ' ' + url + ': HTTP ' + response.status);
    }
    return response.text();
  }

  // ---- small vector helpers for the view -------------------------------------------------------
  function rotate(q, v) {  // quaternion (w, x, y, z) applied to v
    const [w, x, y, z] = q;
    const tx = 2 * (y * v[2] - z * v[1]);
    const ty = 2 * (z * v[0] - x * v[2]);
    const tz = 2 * (x * v[1] - y * v[0]);
    return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz),
      v[2] + w * tz + (x * ty - y * tx)];
  }
  function multiply(a, b) {
    return [a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
      a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
      a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
      a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]];
  }
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const at3 = (array, i) => [array[3 * i], array[3 * i + 1], array[3 * i + 2]];
  const at4 = (array, i) => [array[4 * i], array[4 * i + 1], array[4 * i + 2], array[4 * i + 3]];

  function element(tag, attributes, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attributes || {})) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function formatNumber(value, digits) {
    if (typeof value !== 'number') return String(value);
    return value.toFixed(digits === undefined ? 3 : digits);
  }

  // ---- one simulation: a lab block or a question's sim -------------------------------------------
  class Sim {
    constructor(mj, spec, specText, model, container) {
      this.mj = mj;
      this.spec = spec;
      this.specText = specText;
      this.model = model;
      this.data = new mj.MjData(model);
      this.ctx = {};
      this.running = false;
      this.samples = [];  // {t, values: [per plot, per trace]}
      this.trail = [];
      this.stepsSinceSample = 0;
      this.sampleEvery = Math.max(1, Math.round(0.01 / model.opt.timestep));
      this.compileAll();
      this.build(container);
      for (const c of this.controls) {
        if (c.apply) this.call(c.apply, c.spec.value, 'apply');
      }
      this.reset();
    }

    // every string of the spec becomes a function of (model, data, ctx, mj[, value])
    compile(code, kind) {
      if (typeof code !== 'string') {
        throw new SpecError('the ' + kind + ' must be a string, not ' + JSON.stringify(code),
          lineOfString(this.specText, JSON.stringify(code)));
      }
      const line = lineOfString(this.specText, code);
      let f;
      try {
        f = new Function('model', 'data', 'ctx', 'mj', 'value',
          kind === 'expr' ? 'return (' + code + ');' : code);
      } catch (e) {
        throw new SpecError('the ' + kind + ' "' + code + '" does not compile: ' + e.message, line);
      }
      return {f, code, kind, line};
    }

    // A readout's or a trace's value: its "expr", or "sensor": a sensor's name (with "index",
    // default 0, for one of a sensor's several numbers), read from data.sensordata. Its label
    // defaults to the sensor's name.
    compileValue(item, kind) {
      if (item.sensor === undefined) return {spec: item, expr: this.compile(item.expr, 'expr')};
      const line = lineOfString(this.specText, String(item.sensor));
      const id = this.model.name2id('sensor', item.sensor);
      if (id < 0) {
        const names = this.model.sensor_names.filter((n) => n);
        throw new SpecError('the ' + kind + ' names sensor "' + item.sensor +
          '", which the model does not have' +
          (names.length ? ' (its sensors: ' + names.join(', ') + ')' : ' (it has no sensors)'), line);
      }
      const index = item.index === undefined ? 0 : item.index;
      const dim = this.model.sensor_dim[id];
      if (!(Number.isInteger(index) && index >= 0 && index < dim)) {
        throw new SpecError('the ' + kind + ' reads number ' + JSON.stringify(index) + ' of sensor "' +
          item.sensor + '", which has ' + dim + ' (index 0 to ' + (dim - 1) + ')', line);
      }
      const code = 'data.sensor(' + JSON.stringify(item.sensor) + ').data[' + index + ']';
      const label = item.label || (dim > 1 ? item.sensor + '[' + index + ']' : item.sensor);
      const f = (model, data) => data.sensordata[model.sensor_adr[id] + index];
      return {spec: Object.assign({}, item, {label, expr: code}), expr: {f, code, kind: 'expr', line}};
    }

    compileAll() {
      const s = this.spec;
      this.controller = s.controller ? this.compile(s.controller, 'controller') : null;
      this.setup = s.setup ? this.compile(s.setup, 'setup') : null;
      this.controls = (s.controls || []).map((c) => {
        const type = c.type || 'slider';
        if (!['slider', 'select', 'button'].includes(type)) {
          throw new SpecError('unknown control type "' + type + '" (slider, select or button)',
            lineOfString(this.specText, type));
        }
        if (c.param !== undefined) this.ctx[c.param] = c.value;
        return {
          spec: c,
          type,
          run: c.run ? this.compile(c.run, 'run') : null,
          apply: c.apply ? this.compile(c.apply, 'apply') : null,
        };
      });
      this.readoutSpecs = (s.readouts || []).map((r) => this.compileValue(r, 'readout'));
      this.plotSpecs = (s.plots || []).map((p) => ({
        spec: p,
        traces: (p.traces || []).map((t) => this.compileValue(t, 'trace')),
      }));
      if (s.trail) {
        this.trailSite = this.model.name2id('site', s.trail);
        if (this.trailSite < 0) {
          throw new SpecError('the trail names site "' + s.trail + '", which the model does not have',
            lineOfString(this.specText, s.trail));
        }
      }
    }

    // run one compiled string; an exception stops the simulation and is shown with its line
    call(compiled, value) {
      try {
        return compiled.f(this.model, this.data, this.ctx, this.mj, value);
      } catch (e) {
        this.pause();
        const error = new SpecError('the ' + compiled.kind + ' "' + compiled.code + '" threw ' +
          (e && e.name ? e.name + ': ' : '') + (e && e.message !== undefined ? e.message : e),
        compiled.line);
        error.reported = true;
        showError('spec', error.message, error.line);
        throw error;
      }
    }

    // ---- the simulation ------------------------------------------------------------------------
    settle() {
      const {mj, model, data} = this;
      mj.mj_forward(model, data);
      if (this.controller) {
        this.call(this.controller);
        mj.mj_forward(model, data);
      }
    }

    advance(steps) {
      const {mj, model, data} = this;
      for (let i = 0; i < steps; i++) {
        mj.mj_forward(model, data);
        if (this.controller) this.call(this.controller);
        mj.mj_step(model, data);
        if (++this.stepsSinceSample >= this.sampleEvery) {
          this.stepsSinceSample = 0;
          this.record();
        }
      }
      this.settle();
    }

    record() {
      const t = this.data.time;
      this.samples.push({t, values: this.plotSpecs.map((p) => p.traces.map((tr) => this.call(tr.expr)))});
      const longest = Math.max(0, ...this.plotSpecs.map((p) => p.spec.window || 10));
      while (this.samples.length && this.samples[0].t < t - longest) this.samples.shift();
      if (this.trailSite !== undefined) {
        this.trail.push(at3(this.data.site_xpos, this.trailSite));
        if (this.trail.length > 2000) this.trail.shift();
      }
    }

    reset() {
      this.mj.mj_resetData(this.model, this.data);
      if (this.setup) {
        this.call(this.setup);
        this.syncControls();
      }
      this.samples = [];
      this.trail = [];
      this.stepsSinceSample = 0;
      this.settle();
      this.record();
      this.refresh();
    }

    run(seconds) {
      this.advance(Math.round(seconds / this.model.opt.timestep));
      this.refresh();
    }

    play() {
      this.running = true;
      this.playButton.textContent = 'Pause';
    }

    pause() {
      this.running = false;
      if (this.playButton) this.playButton.textContent = 'Play';
    }

    // what a control does when it changes or is pressed
    press(control) {
      this.call(control.run);
      this.syncControls();
      this.samples = [];
      this.trail = [];
      this.settle();
      this.record();
      this.refresh();
    }

    change(control, value) {
      const c = control.spec;
      if (c.param !== undefined) this.ctx[c.param] = value;
      if (control.output) control.output.textContent = this.controlText(control, value);
      if (control.apply) this.call(control.apply, value);
      if (c.reset) {
        this.reset();
      } else {
        this.settle();
        this.refresh();
      }
    }

    // a button or the setup may set ctx (a pose's targets): the sliders then show the new values
    syncControls() {
      for (const control of this.controls) {
        const param = control.spec.param;
        if (param === undefined || !control.read || control.read() === this.ctx[param]) continue;
        control.write(this.ctx[param]);
        if (control.output) control.output.textContent = this.controlText(control, this.ctx[param]);
      }
    }

    controlText(control, value) {
      const c = control.spec;
      return formatNumber(value, c.digits === undefined ? 2 : c.digits) + (c.unit ? ' ' + c.unit : '');
    }

    readouts() {
      return this.readoutSpecs.map((r) => {
        const value = this.call(r.expr);
        return {label: r.spec.label, value, text: formatNumber(value, r.spec.digits)};
      });
    }

    // ---- the page ------------------------------------------------------------------------------
    build(container) {
      const s = this.spec;
      const root = element('section', {class: 'sim'});
      if (s.title) root.appendChild(element('h2', {}, s.title));
      const layout = element('div', {class: 'layout'});
      const left = element('div');
      const right = element('div', {class: 'controls'});
      layout.append(left, right);
      root.appendChild(layout);

      this.view = element('canvas', {class: 'view', height: String(s.height || 240)});
      this.view.style.height = (s.height || 240) + 'px';
      left.appendChild(this.view);
      const want2d = params.get('view') === '2d' || s.view === '2d';
      this.view3d = want2d || !window.View3D ? null : window.View3D.create(this.view, this.model, s.camera);
      this.view.dataset.view = this.view3d ? '3d' : '2d';
      if (this.view3d) this.view.title = 'drag: turn the camera; wheel: zoom; double click: the lesson\'s view';
      const toolbar = element('div', {class: 'toolbar'});
      this.playButton = element('button', {type: 'button', class: 'play'}, 'Play');
      this.playButton.addEventListener('click', () => (this.running ? this.pause() : this.play()));
      const resetButton = element('button', {type: 'button', class: 'reset'}, 'Reset');
      resetButton.addEventListener('click', () => this.guard(() => this.reset()));
      this.timeText = element('span', {class: 'time'});
      toolbar.append(this.playButton, resetButton, this.timeText);
      this.overlays = Object.assign({}, s.overlays || {});
      for (const name of s.toggles || []) {
        const box = element('input', {type: 'checkbox', 'data-toggle': name});
        box.checked = !!this.overlays[name];
        box.addEventListener('change', () => {
          this.overlays[name] = box.checked;
          this.draw();
        });
        const label = element('label');
        label.append(box, ' ' + name);
        toolbar.appendChild(label);
      }
      left.appendChild(toolbar);
      this.plotCanvases = this.plotSpecs.map(() => {
        const c = element('canvas', {class: 'plot', height: '150'});
        c.style.height = '150px';
        left.appendChild(c);
        return c;
      });

      for (const control of this.controls) right.appendChild(this.buildControl(control));
      this.readoutTable = element('table', {class: 'readouts'});
      this.readoutCells = this.readoutSpecs.map((r) => {
        const row = element('tr');
        const value = element('td', {class: 'value'});
        row.append(element('td', {}, r.spec.label), value);
        this.readoutTable.appendChild(row);
        return value;
      });
      right.appendChild(this.readoutTable);
      if (s.note) root.appendChild(element('p', {class: 'note'}, s.note));
      container.appendChild(root);
      this.root = root;
    }

    buildControl(control) {
      const c = control.spec;
      const div = element('div', {class: 'control'});
      if (control.type === 'button') {
        const b = element('button', {type: 'button'}, c.label);
        b.addEventListener('click', () => this.guard(() => this.press(control)));
        div.appendChild(b);
        return div;
      }
      const row = element('div', {class: 'row'});
      row.appendChild(element('span', {}, c.label));
      div.appendChild(row);
      if (control.type === 'select') {
        const select = element('select');
        (c.options || []).forEach(([label, value], i) => {
          const option = element('option', {value: String(i)}, label);
          if (value === c.value) option.selected = true;
          select.appendChild(option);
        });
        control.read = () => c.options[Number(select.value)][1];
        control.write = (value) => {
          const i = c.options.findIndex(([label, v]) => v === value || label === value);
          if (i < 0) throw new Error('"' + c.label + '" has no option ' + JSON.stringify(value));
          select.value = String(i);
        };
        select.addEventListener('change', () => this.guard(() => this.change(control, control.read())));
        div.appendChild(select);
      } else {
        control.output = element('span', {class: 'output'}, this.controlText(control, c.value));
        row.appendChild(control.output);
        const input = element('input', {type: 'range', min: String(c.min), max: String(c.max),
          step: String(c.step === undefined ? 'any' : c.step), value: String(c.value)});
        control.read = () => Number(input.value);
        control.write = (value) => {
          input.value = String(value);
        };
        input.addEventListener('input', () => this.guard(() => this.change(control, control.read())));
        div.appendChild(input);
      }
      return div;
    }

    guard(action) {
      try {
        action();
      } catch (e) {
        if (!e.reported) showError('lab', e.message, e.line);
      }
    }

    refresh() {
      this.timeText.textContent = 't = ' + this.data.time.toFixed(2) + ' s';
      const values = this.readouts();
      values.forEach((r, i) => (this.readoutCells[i].textContent = r.text));
      this.draw();
    }

    // ---- drawing -------------------------------------------------------------------------------
    // each contact's normal force for the contacts overlay, when the engine gives it
    // (mj_contactForce); otherwise null and the normals are drawn at one length
    normalForces() {
      if (!this.overlays.contacts || !this.mj.mj_contactForce) return null;
      const force = new Float64Array(6);
      return this.data.contact.map((c, i) => {
        this.mj.mj_contactForce(this.model, this.data, i, force);
        return force[0];
      });
    }

    camera(width, height) {
      const cam = this.spec.camera || {};
      const az = ((cam.azimuth === undefined ? 90 : cam.azimuth) * Math.PI) / 180;
      const el = ((cam.elevation === undefined ? -45 : cam.elevation) * Math.PI) / 180;
      const distance = cam.distance || 2;
      const target = cam.target || [0, 0, 0];
      // MuJoCo's free camera: it looks along `forward` at `target` from `distance`
      const forward = [Math.cos(el) * Math.cos(az), Math.cos(el) * Math.sin(az), Math.sin(el)];
      const up = [-Math.sin(el) * Math.cos(az), -Math.sin(el) * Math.sin(az), Math.cos(el)];
      const right = [Math.sin(az), -Math.cos(az), 0];  // = forward x up, as mjv_updateCamera
      const focal = height / 2 / Math.tan((45 / 2) * (Math.PI / 180));  // MuJoCo's fovy: 45 deg
      return {
        project(p) {
          const v = [p[0] - target[0], p[1] - target[1], p[2] - target[2]];
          const depth = Math.max(1e-3, distance + dot(v, forward));
          const s = focal / depth;
          return [width / 2 + dot(v, right) * s, height / 2 - dot(v, up) * s, s];
        },
      };
    }

    draw() {
      if (this.view3d) {
        this.view3d.draw(this.data, this.overlays, this.trail, this.normalForces());
        this.plotCanvases.forEach((c, i) => this.drawPlot(c, this.plotSpecs[i], i));
        return;
      }
      this.draw2d();
    }

    // the fallback without WebGL: the model projected by the same camera onto a 2D canvas
    draw2d() {
      const canvas = this.view;
      const ratio = window.devicePixelRatio || 1;
      const width = Math.max(1, Math.round(canvas.clientWidth * ratio));
      const height = Math.max(1, Math.round(canvas.clientHeight * ratio));
      if (canvas.width !== width) canvas.width = width;
      if (canvas.height !== height) canvas.height = height;
      const g = canvas.getContext('2d');
      g.clearRect(0, 0, width, height);
      const cam = this.camera(width, height);
      const {model, data} = this;
      const line = (a, b, color, w) => {
        const pa = cam.project(a);
        const pb = cam.project(b);
        g.strokeStyle = color;
        g.lineWidth = w;
        g.beginPath();
        g.moveTo(pa[0], pa[1]);
        g.lineTo(pb[0], pb[1]);
        g.stroke();
      };
      const dotAt = (p, r, fill, stroke) => {
        const q = cam.project(p);
        g.beginPath();
        g.arc(q[0], q[1], r * ratio, 0, 2 * Math.PI);
        g.fillStyle = fill;
        g.fill();
        if (stroke) {
          g.strokeStyle = stroke;
          g.lineWidth = ratio;
          g.stroke();
        }
      };
      // geoms
      for (let i = 0; i < model.ngeom; i++) {
        const b = model.geom_bodyid[i];
        const q = multiply(at4(data.xquat, b), at4(model.geom_quat, i));
        const center = add(at3(data.xpos, b), rotate(at4(data.xquat, b), at3(model.geom_pos, i)));
        const size = at3(model.geom_size, i);
        const rgba = at4(model.geom_rgba, i);
        const color = 'rgba(' + rgba.slice(0, 3).map((c) => Math.round(255 * c)).join(',') + ',' +
          rgba[3] + ')';
        const type = model.geom_type[i];
        g.lineCap = 'round';
        if (type === 3 || type === 5) {  // capsule, cylinder: along the geom's z axis
          const half = scale(rotate(q, [0, 0, 1]), size[1]);
          const s = cam.project(center)[2];
          g.lineCap = type === 3 ? 'round' : 'butt';
          line(add(center, scale(half, -1)), add(center, half), color, Math.max(1, 2 * size[0] * s));
        } else if (type === 6) {  // box: its twelve edges
          const corner = (sx, sy, sz) => add(center, rotate(q, [sx * size[0], sy * size[1], sz * size[2]]));
          for (const [a, b2] of [[[-1, -1, -1], [1, -1, -1]], [[-1, 1, -1], [1, 1, -1]],
            [[-1, -1, 1], [1, -1, 1]], [[-1, 1, 1], [1, 1, 1]], [[-1, -1, -1], [-1, 1, -1]],
            [[1, -1, -1], [1, 1, -1]], [[-1, -1, 1], [-1, 1, 1]], [[1, -1, 1], [1, 1, 1]],
            [[-1, -1, -1], [-1, -1, 1]], [[1, -1, -1], [1, -1, 1]], [[-1, 1, -1], [-1, 1, 1]],
            [[1, 1, -1], [1, 1, 1]]]) {
            line(corner(...a), corner(...b2), color, 2 * ratio);
          }
        } else {  // sphere, ellipsoid: a disc of the first radius
          const p = cam.project(center);
          g.beginPath();
          g.arc(p[0], p[1], Math.max(1, size[0] * p[2]), 0, 2 * Math.PI);
          g.fillStyle = color;
          g.fill();
        }
      }
      g.lineCap = 'butt';
      if (this.trail.length > 1) {
        g.strokeStyle = '#e6b800';
        g.lineWidth = 2 * ratio;
        g.beginPath();
        this.trail.forEach((p, i) => {
          const q = cam.project(p);
          if (i === 0) g.moveTo(q[0], q[1]);
          else g.lineTo(q[0], q[1]);
        });
        g.stroke();
      }
      if (this.overlays.frames) {
        for (let b = 1; b < model.nbody; b++) {
          const o = at3(data.xpos, b);
          const qb = at4(data.xquat, b);
          [[1, 0, 0, '#d33'], [0, 1, 0, '#3a3'], [0, 0, 1, '#33d']].forEach(([x, y, z, c]) =>
            line(o, add(o, rotate(qb, [0.1 * x, 0.1 * y, 0.1 * z])), c, 1.5 * ratio));
        }
      }
      if (this.overlays.joints) {
        for (let j = 0; j < model.njnt; j++) dotAt(at3(data.xanchor, j), 5, '#fff', '#333');
      }
      if (this.overlays.com) {
        for (let b = 1; b < model.nbody; b++) {
          const p = cam.project(at3(data.xipos, b));
          const r = 5 * ratio;
          for (let k = 0; k < 4; k++) {
            g.beginPath();
            g.moveTo(p[0], p[1]);
            g.arc(p[0], p[1], r, (k * Math.PI) / 2, ((k + 1) * Math.PI) / 2);
            g.closePath();
            g.fillStyle = k % 2 ? '#fff' : '#000';
            g.fill();
          }
        }
      }
      if (this.overlays.sites) {
        for (let i = 0; i < model.nsite; i++) dotAt(at3(data.site_xpos, i), 3.5, '#c0c', null);
      }
      if (this.overlays.contacts) {
        for (const c of data.contact) {
          const p = Array.from(c.pos);
          line(p, add(p, Array.from(c.frame.subarray(0, 3), (x) => 0.03 * x)), '#0060c0', 1.5 * ratio);
          dotAt(p, 3, '#00a0ff', null);
        }
      }
      this.plotCanvases.forEach((c, i) => this.drawPlot(c, this.plotSpecs[i], i));
    }

    drawPlot(canvas, plot, index) {
      const ratio = window.devicePixelRatio || 1;
      const width = Math.max(1, Math.round(canvas.clientWidth * ratio));
      const height = Math.max(1, Math.round(canvas.clientHeight * ratio));
      if (canvas.width !== width) canvas.width = width;
      if (canvas.height !== height) canvas.height = height;
      const g = canvas.getContext('2d');
      g.clearRect(0, 0, width, height);
      const window_ = plot.spec.window || 10;
      const t1 = Math.max(this.data.time, window_);
      const t0 = t1 - window_;
      const visible = this.samples.filter((s) => s.t >= t0);
      let lo = Infinity;
      let hi = -Infinity;
      for (const s of visible) {
        for (const v of s.values[index]) {
          if (Number.isFinite(v)) {
            lo = Math.min(lo, v);
            hi = Math.max(hi, v);
          }
        }
      }
      if (!(hi > lo)) {
        lo = (Number.isFinite(lo) ? lo : 0) - 1;
        hi = lo + 2;
      }
      const pad = 0.1 * (hi - lo);
      lo -= pad;
      hi += pad;
      const left = 48 * ratio;
      const top = 20 * ratio;  // the legend sits above the frame
      const bottom = height - 18 * ratio;
      const x = (t) => left + ((t - t0) / window_) * (width - left - 8 * ratio);
      const y = (v) => bottom - ((v - lo) / (hi - lo)) * (bottom - top);
      g.font = 10 * ratio + 'px sans-serif';
      g.fillStyle = '#666';
      g.strokeStyle = '#ccc';
      g.lineWidth = ratio;
      g.strokeRect(left, top, width - left - 8 * ratio, bottom - top);
      g.fillText(hi.toPrecision(3), 2, top + 8 * ratio);
      g.fillText(lo.toPrecision(3), 2, bottom);
      g.fillText(t0.toFixed(1) + ' s', left, height - 4 * ratio);
      g.fillText(t1.toFixed(1) + ' s', width - 40 * ratio, height - 4 * ratio);
      g.save();
      g.translate(10 * ratio, height / 2 + 30 * ratio);
      g.rotate(-Math.PI / 2);
      g.fillText(plot.spec.ylabel || '', 0, 0);
      g.restore();
      const colors = ['#2a5db0', '#c0392b', '#27ae60', '#8e44ad'];
      plot.traces.forEach((trace, k) => {
        g.strokeStyle = colors[k % colors.length];
        g.lineWidth = 1.5 * ratio;
        g.setLineDash(trace.spec.dash ? [6 * ratio, 4 * ratio] : []);
        g.beginPath();
        visible.forEach((s, i) => {
          if (i === 0) g.moveTo(x(s.t), y(s.values[index][k]));
          else g.lineTo(x(s.t), y(s.values[index][k]));
        });
        g.stroke();
        g.setLineDash([]);
        g.fillStyle = colors[k % colors.length];
        const legendX = left + k * 130 * ratio;
        g.fillRect(legendX, top - 9 * ratio, 14 * ratio, 2 * ratio);
        g.fillText(trace.spec.label || trace.spec.expr, legendX + 18 * ratio, top - 5 * ratio);
      });
    }
  }

  // ---- the page --------------------------------------------------------------------------------
  const sims = [];
  const questions = [];

  async function start() {
    const specUrl = params.get('spec') || 'specs/5.1-lab.json';
    const wasmUrl = 'build/lever_wasm.wasm';
    const mj = await window.createLever(window.createLeverModule, {
      locateFile: (path) => (path.endsWith('.wasm') ? wasmUrl : path),
    });
    window.lab.mj = mj;
    document.getElementById('engine').textContent = 'lever ' + mj.version + ' (WebAssembly)';
    const specText = await fetchText(specUrl, 'spec');
    const spec = parseSpec(specText);
    const container = document.getElementById('sims');
    const addSim = async (s, where) => {
      if (!s || typeof s !== 'object' || typeof s.model !== 'string') {
        throw new SpecError('a simulation needs "model": the name of a model file',
          lineOfString(specText, '"sim"'));
      }
      const modelUrl = params.get('model') || 'models/' + s.model + '.xml';
      const xml = await fetchText(modelUrl, 'model');
      let model;
      try {
        model = mj.MjModel.from_xml_string(xml, s.model + '.xml');
      } catch (e) {
        if (e instanceof mj.LoadError) {
          showError('model ' + modelUrl, e.message, e.line);
          return;
        }
        throw e;
      }
      sims.push(new Sim(mj, s, specText, model, where));
    };
    if (spec && Array.isArray(spec.questions)) {
      // a knowledge check: every question in order, a question's sim under it
      if (spec.questions.length === 0) throw new SpecError('the knowledge check has no questions');
      if (spec.title) container.appendChild(element('h2', {class: 'check-title'}, spec.title));
      for (const [i, q] of spec.questions.entries()) {
        let question;
        try {
          question = new window.quiz.Question(q, i, container);
        } catch (e) {
          throw e instanceof window.quiz.QuizError ?
            new SpecError(e.message, lineOfString(specText, (q && q.q) || '"questions"')) : e;
        }
        questions.push(question);
        if (q.sim) await addSim(q.sim, question.root);
      }
    } else {
      await addSim(spec, container);
    }
    if (params.get('paused') !== '1') sims.forEach((s) => s.play());
    let last = null;
    const frame = () => {
      // the wall clock now (rAF's own timestamp can lag it when frames are slow); at most 0.25 s
      // per frame: a slow frame is caught up, a hidden tab does not jump ahead
      const now = performance.now();
      const dt = last === null ? 0 : Math.min(0.25, (now - last) / 1000);
      last = now;
      for (const sim of sims) {
        if (!sim.running) continue;
        sim.guard(() => {
          sim.pending = (sim.pending || 0) + dt;
          const steps = Math.floor(sim.pending / sim.model.opt.timestep);
          sim.pending -= steps * sim.model.opt.timestep;
          sim.advance(steps);
          sim.refresh();
          sim.frames = (sim.frames || 0) + 1;
        });
      }
      window.requestAnimationFrame(frame);
    };
    window.requestAnimationFrame(frame);
  }

  function questionFor(index) {
    const question = questions[index];
    if (!question) throw new Error('no question ' + index + ' on this page (' + questions.length + ' questions)');
    return question;
  }

  // frames drawn and simulated seconds per wall second while a sim plays, over `seconds` of wall time
  function measureRate(seconds, index) {
    const sim = simFor(index);
    return new Promise((resolve) => {
      const start = {wall: performance.now(), time: sim.data.time, frames: sim.frames || 0};
      setTimeout(() => {
        const wall = (performance.now() - start.wall) / 1000;
        resolve({wall, frames_per_second: ((sim.frames || 0) - start.frames) / wall,
          sim_seconds_per_wall_second: (sim.data.time - start.time) / wall});
      }, 1000 * seconds);
    });
  }

  function simFor(index) {
    const sim = sims[index || 0];
    if (!sim) throw new Error('no simulation ' + (index || 0) + ' on this page');
    return sim;
  }

  function controlFor(sim, key) {
    const control = sim.controls.find((c) => c.spec.param === key || c.spec.label === key);
    if (!control) throw new Error('no control "' + key + '"');
    return control;
  }

  window.lab = {
    ready: null,
    sims,
    errors: () => shownErrors.slice(),
    press(label, index) {
      const sim = simFor(index);
      const control = sim.controls.find((c) => c.type === 'button' && c.spec.label === label);
      if (!control) throw new Error('no button "' + label + '"');
      sim.press(control);
    },
    set(key, value, index) {
      const sim = simFor(index);
      const control = controlFor(sim, key);
      control.write(value);
      sim.change(control, control.read());
    },
    run(seconds, index) { simFor(index).run(seconds); },
    readouts(index) { return simFor(index).readouts(); },
    time(index) { return simFor(index).data.time; },
    play(index) { simFor(index).play(); },
    pause(index) { simFor(index).pause(); },
    reset(index) { simFor(index).reset(); },
    questions: () => questions.map((q) => q.describe()),
    answer(question, value) { return questionFor(question).answer(value); },
    // which view a sim has ('3d' or '2d'), and for the 3D view what its last frame drew
    view(index) {
      const sim = simFor(index);
      if (!sim.view3d) return {kind: '2d'};
      sim.draw();
      const info = sim.view3d.renderer.info.render;
      return Object.assign({kind: '3d', triangles: info.triangles, calls: info.calls,
        camera: Object.assign({}, sim.view3d.cam)}, sim.view3d.pixelSummary());
    },
    // the contacts overlay of the 3D view: each contact's ball centre and normal's tip
    contactMarkers(index) {
      const sim = simFor(index);
      if (!sim.view3d) return null;
      sim.draw();
      return sim.view3d.contactMarkers();
    },
    orbit(dAzimuth, dElevation, index) { simFor(index).view3d.orbit(dAzimuth, dElevation); },
    zoom(factor, index) { simFor(index).view3d.zoom(factor); },
    rate: measureRate,
  };

  window.addEventListener('error', (event) => showError('page', event.message, event.lineno));
  window.lab.ready = start().then(() => true, (e) => {
    if (!e.reported) showError(e instanceof SpecError ? 'spec' : 'lab', e.message, e.line);
    return false;
  });
})();
