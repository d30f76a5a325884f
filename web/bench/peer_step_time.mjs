// node web/bench/peer_step_time.mjs --lever WASM_DIR --mujoco MUJOCO_JS_DIR --out FILE.json
//     [--commit ID] [--rounds N] MODEL.xml...
//
// lever's WebAssembly build (through web/lever.js, as the lab runs it) against MuJoCo's official
// WebAssembly build (npm mujoco-js, which `make web-bench` installs pinned into build-web), in one
// node process, on the same models. One lab step is what the lab does (web/lab.js): mj_forward,
// the controller (it reads data and writes ctrl), mj_step, all called from JavaScript on each
// engine's own API:
//   - a model with a keyframe starts from keyframe 0 (MuJoCo's compiled key_qpos, key_ctrl, given
//     to both engines) and its controller writes the keyframe's ctrl (panda7's servos hold the
//     home pose);
//   - otherwise the lab's Bent pose (qpos[0] = 0.6, qpos[1] = -1.2) under gravity compensation,
//     ctrl = qfrc_bias (lesson 5.1's lab on arm2).
// Each round times the same number of steps on both engines from the same start, alternating
// which goes first; the report takes the medians of the CPU time over the rounds (lever's over
// MuJoCo's; the wall-clock medians are in the JSON too). Writes
// FILE.json for bench/report.cpp (`lever_bench_report --web FILE.json`) and prints a summary.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import {createRequire} from 'node:module';
import {pathToFileURL} from 'node:url';

const require = createRequire(import.meta.url);

function usage(message) {
  console.error(`peer_step_time.mjs: ${message}\n` +
    'usage: node web/bench/peer_step_time.mjs --lever WASM_DIR --mujoco MUJOCO_JS_DIR ' +
    '--out FILE.json [--commit ID] [--rounds N] MODEL.xml...');
  process.exit(2);
}

const options = {rounds: 15, commit: 'unknown'};
const models = [];
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; i++) {
  const arg = argv[i];
  if (['--lever', '--mujoco', '--out', '--commit', '--rounds'].includes(arg)) {
    if (i + 1 >= argv.length) usage(`${arg} needs a value`);
    options[arg.slice(2)] = argv[++i];
  } else if (arg.startsWith('--')) {
    usage(`unknown option ${arg}`);
  } else {
    models.push(arg);
  }
}
if (!options.lever || !options.mujoco || !options.out) usage('--lever, --mujoco and --out are needed');
if (models.length === 0) usage('no model');
if (!fs.existsSync(path.join(options.mujoco, 'package.json'))) {
  usage(`no npm package in ${options.mujoco} (make web-bench installs mujoco-js into build-web)`);
}
if (!fs.existsSync(path.join(options.lever, 'lever_wasm.js'))) {
  usage(`no lever_wasm.js in ${options.lever} (make web builds it)`);
}
const rounds = Number(options.rounds);
if (!Number.isInteger(rounds) || rounds < 1) usage('--rounds must be a positive integer');

function quantile(values, q) {
  const v = [...values].sort((a, b) => a - b);
  const pos = q * (v.length - 1);
  const lo = Math.floor(pos);
  const hi = Math.min(lo + 1, v.length - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

// ---- the two engines, behind the same three calls ---------------------------------------------

async function loadLever(wasmDir) {
  const createLeverModule = require(path.resolve(wasmDir, 'lever_wasm.js'));
  const {createLever} = require('../lever.js');
  // node 18+ would fetch() the .wasm by path: hand it the bytes instead
  const wasm = path.resolve(wasmDir, 'lever_wasm.wasm');
  const mj = await createLever(createLeverModule, {wasmBinary: fs.readFileSync(wasm)});
  return {mj, bytes: fs.statSync(wasm).size};
}

async function loadMujoco(packageDir) {
  const meta = JSON.parse(fs.readFileSync(path.join(packageDir, 'package.json'), 'utf8'));
  const entry = path.join(packageDir, meta.main || 'dist/mujoco_wasm.js');
  const {default: loadModule} = await import(pathToFileURL(entry).href);
  const mj = await loadModule();
  mj.FS.mkdir('/models');
  mj.FS.mount(mj.MEMFS, {root: '.'}, '/models');
  return {mj, packageVersion: meta.version, version: mj.mj_versionString(),
    bytes: fs.statSync(entry).size};
}

// One engine on one model: reset() puts the start state, run(n) does n lab steps.
function rig(mj, model, data, start) {
  const nu = model.nu;
  const hold = start.ctrl;  // null: gravity compensation
  const step = hold ?
    () => {
      mj.mj_forward(model, data);
      data.ctrl.set(hold);
      mj.mj_step(model, data);
    } :
    () => {
      mj.mj_forward(model, data);
      const ctrl = data.ctrl;
      const bias = data.qfrc_bias;
      for (let i = 0; i < nu; i++) ctrl[i] = bias[i];
      mj.mj_step(model, data);
    };
  return {
    reset() {
      mj.mj_resetData(model, data);
      data.qpos.set(start.qpos);
      if (hold) data.ctrl.set(hold);
    },
    run(n) {
      for (let i = 0; i < n; i++) step();
    },
    setQvel(value) {
      data.qvel.fill(value);
    },
    qpos: () => Array.from(data.qpos),
  };
}

// ns per step of `steps` lab steps: CPU time of the process (as the native benchmarks report CPU
// time: on a shared machine, wall-clock time also counts the other processes' turns) and wall time
function timeRun(engine, steps) {
  engine.reset();
  const cpuBegin = process.cpuUsage();
  const wallBegin = process.hrtime.bigint();
  engine.run(steps);
  const wall = Number(process.hrtime.bigint() - wallBegin);
  const cpu = process.cpuUsage(cpuBegin);
  return {cpu: (cpu.user + cpu.system) * 1e3 / steps, wall: wall / steps};
}

// ---- measuring ----------------------------------------------------------------------------------

const lever = await loadLever(options.lever);
const mujoco = await loadMujoco(options.mujoco);
const result = {
  date: new Date().toISOString(),
  lever_commit: options.commit,
  node: process.version,
  cpu_model: os.cpus()[0]?.model ?? 'unknown',
  num_cpus: os.cpus().length,
  load_avg: os.loadavg(),
  mujoco_js: mujoco.packageVersion,
  mujoco_version: mujoco.version,
  lever_wasm_bytes: lever.bytes,
  mujoco_js_bytes: mujoco.bytes,
  rounds,
  models: {},
};

for (const file of models) {
  const name = path.basename(file, '.xml');
  const xml = fs.readFileSync(file, 'utf8');
  mujoco.mj.FS.writeFile(`/models/${name}.xml`, xml);
  const mjModel = mujoco.mj.MjModel.loadFromXML(`/models/${name}.xml`);
  const mjData = new mujoco.mj.MjData(mjModel);
  const lvModel = lever.mj.MjModel.from_xml_string(xml, file);
  const lvData = new lever.mj.MjData(lvModel);
  if (lvModel.nq !== mjModel.nq || lvModel.nu !== mjModel.nu) {
    throw new Error(`${file}: lever and MuJoCo disagree on nq or nu`);
  }
  // the start state, from MuJoCo's compiled model
  const start = {qpos: new Float64Array(mjModel.qpos0), ctrl: null};
  if (mjModel.nkey > 0) {
    start.qpos = new Float64Array(mjModel.key_qpos.subarray(0, mjModel.nq));
    start.ctrl = new Float64Array(mjModel.key_ctrl.subarray(0, mjModel.nu));
  } else {
    for (let i = 0; i < Math.min(2, mjModel.nq); i++) start.qpos[i] = i === 0 ? 0.6 : -1.2;
  }
  const engines = {
    lever: rig(lever.mj, lvModel, lvData, start),
    mujoco: rig(mujoco.mj, mjModel, mjData, start),
  };

  // the same work: one second of simulated time on both, from the start set moving (every joint
  // at 0.5 rad/s: at rest, the lab's gravity compensation would hold arm2 still)
  const check = Math.round(1 / mjModel.opt.timestep);
  for (const e of Object.values(engines)) {
    e.reset();
    e.setQvel(0.5);
    e.run(check);
  }
  const a = engines.lever.qpos();
  const b = engines.mujoco.qpos();
  const qposDiff = Math.max(...a.map((x, i) => Math.abs(x - b[i])));

  // warm up: node runs new wasm code from a baseline compiler first and swaps in optimized code
  // later (lever's after about 0.4 s of steps on a loaded machine, several times faster): a
  // second of steps each, then size the rounds from lever's last warm-up runs, about 50 ms each
  const leverWarm = [];
  for (const who of ['lever', 'mujoco']) {
    const begin = process.cpuUsage();
    let spent = 0;
    while (spent < 1e6) {  // µs
      const t = timeRun(engines[who], 2000);
      if (who === 'lever') leverWarm.push(t.cpu);
      const used = process.cpuUsage(begin);
      spent = used.user + used.system;
    }
  }
  const steps = Math.max(1000, Math.round(5e7 / quantile(leverWarm.slice(-5), 0.5)));
  const cpu = {lever: [], mujoco: []};
  const wall = {lever: [], mujoco: []};
  for (let r = 0; r < rounds; r++) {
    const order = r % 2 === 0 ? ['lever', 'mujoco'] : ['mujoco', 'lever'];
    for (const who of order) {
      const t = timeRun(engines[who], steps);
      cpu[who].push(t.cpu);
      wall[who].push(t.wall);
    }
  }
  const stats = (v) => ({median: quantile(v, 0.5), iqr: (quantile(v, 0.75) - quantile(v, 0.25)) /
    quantile(v, 0.5)});
  const l = stats(cpu.lever);
  const m = stats(cpu.mujoco);
  result.models[name] = {
    steps_per_round: steps,
    controller: start.ctrl ? 'keyframe 0, its ctrl held' : 'the Bent pose, ctrl = qfrc_bias',
    lever_ns: l.median, lever_iqr: l.iqr,
    mujoco_ns: m.median, mujoco_iqr: m.iqr,
    ratio: l.median / m.median,
    lever_wall_ns: quantile(wall.lever, 0.5), mujoco_wall_ns: quantile(wall.mujoco, 0.5),
    qpos_max_diff_after_1s: qposDiff,
  };
  console.log(`${name}: lever ${l.median.toFixed(0)} ns, MuJoCo ${mujoco.version} ` +
    `${m.median.toFixed(0)} ns per lab step (median of ${rounds} x ${steps}): ` +
    `${(l.median / m.median).toFixed(3)}; |qpos difference| after 1 s: ${qposDiff.toExponential(1)}`);
  mjData.delete();
  mjModel.delete();
}

fs.writeFileSync(options.out + '.part', JSON.stringify(result, null, 1) + '\n');
fs.renameSync(options.out + '.part', options.out);
console.log(`peer_step_time.mjs: wrote ${options.out}`);
