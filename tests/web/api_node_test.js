// web/lever.js on node against lever's native build: every array the JS API exposes, on every
// model, equals what `lever forward --json` computes for the same state (to lever's 1e-12 bound);
// model edits reach the engine through mj_setConst; views follow the heap when it grows;
// mj_jacSite gives `lever forward`'s site_jacp and site_jacr; mj_resetDataKeyframe its --key state.
//   node api_node_test.js LEVER WASM_DIR REPO_ROOT
'use strict';
const fs = require('fs');
const path = require('path');
const {execFileSync} = require('child_process');

const [lever, wasmDir, root] = process.argv.slice(2);
const createLeverModule = require(path.resolve(wasmDir, 'lever_wasm.js'));
const {createLever} = require(path.resolve(root, 'web', 'lever.js'));

let failures = 0;
let compared = 0;
function fail(message) {
  failures++;
  console.log('FAILED: ' + message);
}
function close(ours, native, what) {
  compared++;
  if (!(Math.abs(ours - native) <= 1e-12 * Math.max(1, Math.abs(native)))) {
    fail(`${what}: wasm ${ours}, native ${native}`);
  }
}

function nativeForward(file, qpos, qvel, ctrl, key) {
  const args = ['forward', file, '--json'];
  if (key) args.push('--key=' + key);
  if (qpos.length) args.push('--qpos=' + qpos.join(','));
  if (qvel.length) args.push('--qvel=' + qvel.join(','));
  if (ctrl.length) args.push('--ctrl=' + ctrl.join(','));
  let out;
  try {
    out = execFileSync(lever, args, {encoding: 'utf8'});
  } catch (e) {
    out = e.stdout;  // exit 1: a warning; the JSON is still printed
  }
  return JSON.parse(out);
}

// a deterministic state inside the joint ranges
function stateOf(model, seed) {
  // a hinge's or a slide's coordinate inside its range when it has one; any other coordinate
  // (a free joint's position, a quaternion's numbers, normalized by forward) 0.3 sin(...)
  const qpos = [];
  const qvel = [];
  const ctrl = [];
  for (let i = 0; i < model.nq; i++) qpos.push(0.3 * Math.sin(i + seed));
  for (let j = 0; j < model.njnt; j++) {
    const lo = model.jnt_range[2 * j];
    const hi = model.jnt_range[2 * j + 1];
    const u = 0.5 + 0.4 * Math.sin(1.7 * (j + 1) * seed);
    if (hi > lo) qpos[model.jnt_qposadr[j]] = lo + u * (hi - lo);
  }
  for (let i = 0; i < model.nv; i++) qvel.push(0.8 * Math.cos(2.3 * (i + 1) + seed));
  for (let a = 0; a < model.nu; a++) ctrl.push(2 * Math.sin(a + seed));
  return {qpos, qvel, ctrl};
}

// every array `lever forward --json` prints that the JS data also has (mjData's names, flattened
// row-major on both sides); not energy, which the command computes after forward (compute_energy)
// and mj_forward leaves alone, as MuJoCo's does without its energy flag
function compareData(mj, model, data, native, label) {
  let arrays = 0;
  for (const name of Object.keys(native)) {
    if (name === 'energy') continue;
    const ours = data[name];
    if (!ArrayBuffer.isView(ours) || !Array.isArray(native[name])) continue;
    arrays++;
    const theirs = native[name].flat(Infinity);
    if (ours.length !== theirs.length) {
      fail(`${label}: data.${name} has ${ours.length} numbers, native ${theirs.length}`);
      continue;
    }
    for (let i = 0; i < ours.length; i++) close(ours[i], theirs[i], `${label}: data.${name}[${i}]`);
  }
  if (arrays < 20) fail(`${label}: only ${arrays} arrays in common with lever forward --json`);
}

// mj_jacSite for every site: the native command's site_jacp and site_jacr (nsite x 3 x nv)
function compareJacobians(mj, model, data, native, label) {
  const n = 3 * model.nv;
  const jacp = new Float64Array(n);
  const jacr = new Float64Array(n);
  for (let site = 0; site < model.nsite; site++) {
    mj.mj_jacSite(model, data, jacp, jacr, site);
    for (let i = 0; i < n; i++) {
      close(jacp[i], native.site_jacp[site * n + i], `${label}: jacp of site ${site} [${i}]`);
      close(jacr[i], native.site_jacr[site * n + i], `${label}: jacr of site ${site} [${i}]`);
    }
  }
  for (const bad of [-1, model.nsite]) {
    let threw = null;
    try {
      mj.mj_jacSite(model, data, jacp, null, bad);
    } catch (e) {
      threw = e;
    }
    if (!(threw instanceof mj.EngineError) || !/site/.test(threw.message)) {
      fail(`${label}: mj_jacSite at site ${bad} gave ${threw} instead of an EngineError`);
    }
  }
}

(async () => {
  const mj = await createLever(createLeverModule,
    {wasmBinary: fs.readFileSync(path.resolve(wasmDir, 'lever_wasm.wasm'))});
  const files = [];
  for (const dir of ['models', 'tests/models']) {
    for (const f of fs.readdirSync(path.join(root, dir)).sort()) {
      if (f.endsWith('.xml')) files.push(path.join(dir, f));
    }
  }
  // 1. every exposed Data array on every model, at two states
  for (const file of files) {
    const model = mj.MjModel.from_xml_string(fs.readFileSync(path.join(root, file), 'utf8'), file);
    const data = new mj.MjData(model);
    for (const seed of [1, 2]) {
      const s = stateOf(model, seed);
      data.qpos.set(s.qpos);
      data.qvel.set(s.qvel);
      data.ctrl.set(s.ctrl);
      mj.mj_forward(model, data);
      const fmt = (v) => v.map((x) => x.toPrecision(17));
      const native = nativeForward(path.join(root, file), fmt(s.qpos), fmt(s.qvel), fmt(s.ctrl));
      compareData(mj, model, data, native, `${file} state ${seed}`);
      compareJacobians(mj, model, data, native, `${file} state ${seed}`);
    }
    for (let key = 0; key < model.nkey; key++) {
      // a keyframe's state, then forward: what `lever forward --key NAME` computes
      mj.mj_resetDataKeyframe(model, data, key);
      mj.mj_forward(model, data);
      const name = model.key_names[key];
      compareData(mj, model, data, nativeForward(path.join(root, file), [], [], [], name),
        `${file} keyframe ${name}`);
    }
    data.delete();
    model.delete();
  }

  // 2. qvel.fill(0) writes lever's Data; body_mass + mj_setConst reaches the engine
  const arm2 = path.join(root, 'models', 'arm2.xml');
  const xml = fs.readFileSync(arm2, 'utf8');
  const model = mj.MjModel.from_xml_string(xml, 'arm2.xml');
  const data = new mj.MjData(model);
  data.qvel.set([3, -2]);
  data.qvel.fill(0);
  data.qpos.set([0.6, -1.2]);
  mj.mj_forward(model, data);
  compareData(mj, model, data, nativeForward(arm2, ['0.6', '-1.2'], [], []), 'arm2 after fill(0)');
  model.body_mass[2] = 1.6;
  mj.mj_setConst(model, data);
  if (data.qpos[0] !== model.qpos0[0]) fail('mj_setConst did not leave qpos at qpos0 (as MuJoCo)');
  if (Math.abs(model.body_subtreemass[1] - 2.6) > 1e-15) {
    fail('body_subtreemass[1] after mj_setConst: ' + model.body_subtreemass[1]);
  }
  data.qpos.set([0.6, -1.2]);
  mj.mj_forward(model, data);
  const heavy = path.join(require('os').tmpdir(), `arm2-heavy-${process.pid}.xml`);
  const heavyXml = xml.replace('<inertial pos="0.2 0 0" mass="0.8"', '<inertial pos="0.2 0 0" mass="1.6"');
  if (heavyXml === xml) fail('could not find link 2 inertial in arm2.xml');
  fs.writeFileSync(heavy, heavyXml);
  const heavyNative = nativeForward(heavy, ['0.6', '-1.2'], [], []);
  fs.unlinkSync(heavy);
  compareData(mj, model, data, heavyNative, 'arm2 at 1.6 kg');

  // 3. the heap grows (models kept alive until it does): views are rebuilt, writes still land
  const before = mj.Module.HEAPU8.buffer.byteLength;
  const kept = [];
  const big = fs.readFileSync(path.join(root, 'models', 'chain20.xml'), 'utf8');
  while (mj.Module.HEAPU8.buffer.byteLength === before && kept.length < 20000) {
    kept.push(mj.MjModel.from_xml_string(big, 'chain20.xml'));
  }
  if (mj.Module.HEAPU8.buffer.byteLength === before) fail('the heap never grew');
  data.qpos.set([0.6, -1.2]);
  data.qvel.fill(0);
  mj.mj_forward(model, data);
  if (data.qpos.buffer !== mj.Module.HEAPU8.buffer) fail('data.qpos still views the old heap');
  let noKey = null;
  try {
    mj.mj_resetDataKeyframe(model, data, 0);  // arm2 has no keyframe
  } catch (e) {
    noKey = e;
  }
  if (!(noKey instanceof mj.EngineError)) fail('mj_resetDataKeyframe on a model without keyframes: ' + noKey);
  data.qpos.set([0.6, -1.2]);
  data.qvel.fill(0);
  mj.mj_forward(model, data);
  compareData(mj, model, data, heavyNative, 'arm2 at 1.6 kg, after the heap grew');
  for (const m of kept) m.delete();

  console.log(`${compared} numbers compared on ${files.length} models; heap ${before} -> ` +
    `${mj.Module.HEAPU8.buffer.byteLength} bytes after ${kept.length} extra models`);
  if (failures) {
    console.log(`${failures} failures`);
    process.exit(1);
  }
  console.log('passed');
})().catch((e) => {
  console.log('FAILED: ' + (e.stack || e));
  process.exit(1);
});
