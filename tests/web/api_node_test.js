// web/lever.js on node against lever's native build: every array the JS API exposes, on every
// model, equals what `lever forward --json` computes for the same state (to lever's 1e-12 bound);
// model edits reach the engine through mj_setConst; views follow the heap when it grows;
// mj_jacSite gives `lever forward`'s site_jacp and site_jacr, and lever's lean calls from qpos
// (lever_body_poses, lever_body_kinematics, lever_jac_site_from_q) its frames, subtree_com, cdof
// and Jacobians; mj_resetDataKeyframe its --key state;
// data.ncon, data.contact and data.efc_J of the gripper, run in wasm until it holds the box, agree
// with the constraint rows `lever forward` computes for the same state; so do those of a pair
// MuJoCo collides by MPR (a cylinder on a box).
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
function close(ours, native, what, bound = 1e-12) {
  compared++;
  if (!(Math.abs(ours - native) <= bound * Math.max(1, Math.abs(native)))) {
    fail(`${what}: wasm ${ours}, native ${native}`);
  }
}

// What the constraint solver decides in a state with contacts (tools/diff's decided_by_solver) is
// held to 1e-10, the project's bound for it (tools/diff's kContactSolverBound), everything else to
// 1e-12. Measured on the gripped box: the solve's inputs (M, efc_J, efc_vel, qacc_smooth) agree to
// the last bit, efc_force to ~30 ulp (the solve's sums ordered differently by native Eigen's SIMD
// and wasm's scalar code, amplified by the grasp's conditioning: four contacts, pyramid rows),
// and qacc of the 0.1 kg box gathers 1/m times that over its rows: 1.1e-12 at an element near 0.
// The sensors that read contact forces or accelerations (touch, force, accelerometer) sum them.
const kSolverDecided = new Set(['qacc', 'qacc_warmstart', 'qfrc_constraint', 'efc_force', 'efc_state',
  'sensordata', 'cacc', 'cfrc_int', 'cfrc_ext']);
const kContactTypeRows = new Set([5, 6, 7]);  // efc_type of a contact row
function boundOf(name, native) {
  const contacts = (native.efc_type || []).some((type) => kContactTypeRows.has(type));
  return contacts && kSolverDecided.has(name) ? 1e-10 : 1e-12;
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
    const bound = boundOf(name, native);
    for (let i = 0; i < ours.length; i++) close(ours[i], theirs[i], `${label}: data.${name}[${i}]`, bound);
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

// lever's lean calls from qpos (lever_body_poses, lever_body_kinematics, lever_jac_site_from_q),
// each on a fresh Data at the state's qpos: the arrays each writes equal `lever forward`'s, and
// those it does not write keep what a new Data holds
function compareLeanCalls(mj, model, qpos, native, label) {
  const flatNative = (name) => native[name].flat(Infinity);
  // a fresh Data at qpos, `call` run on it, then `untouched` compared with what it held before
  const run = (what, call, untouched) => {
    const data = new mj.MjData(model);
    data.qpos.set(qpos);
    const before = untouched.map((name) => Array.from(data[name]));
    call(data);
    untouched.forEach((name, k) => {
      if (data[name].some((x, i) => x !== before[k][i])) fail(`${label}: ${what} wrote data.${name}`);
    });
    return data;
  };
  const compareArrays = (data, names, what) => {
    for (const name of names) {
      const ours = data[name];
      const theirs = flatNative(name);
      if (ours.length !== theirs.length) {
        fail(`${label}: ${what}: data.${name} has ${ours.length} numbers, native ${theirs.length}`);
        continue;
      }
      for (let i = 0; i < ours.length; i++) close(ours[i], theirs[i], `${label}: ${what}: data.${name}[${i}]`);
    }
  };
  const bodyFrames = ['xpos', 'xquat', 'xmat'];
  let data = run('lever_body_poses', (d) => mj.lever_body_poses(model, d),
    ['xipos', 'ximat', 'xanchor', 'xaxis', 'subtree_com', 'cdof', 'site_xpos']);
  compareArrays(data, bodyFrames, 'lever_body_poses');
  data.delete();
  data = run('lever_body_kinematics', (d) => mj.lever_body_kinematics(model, d),
    ['geom_xpos', 'geom_xmat', 'site_xpos', 'site_xmat', 'qfrc_bias']);
  compareArrays(data, [...bodyFrames, 'xipos', 'ximat', 'xanchor', 'xaxis', 'subtree_com', 'cdof'],
    'lever_body_kinematics');
  data.delete();
  const n = 3 * model.nv;
  const jacp = new Float64Array(n);
  const jacr = new Float64Array(n);
  for (let site = 0; site < model.nsite; site++) {
    const what = `lever_jac_site_from_q(${site})`;
    data = run(what, (d) => mj.lever_jac_site_from_q(model, d, jacp, jacr, site), ['ximat', 'cdof', 'geom_xpos']);
    for (let i = 0; i < n; i++) {
      close(jacp[i], native.site_jacp[site * n + i], `${label}: ${what}: jacp[${i}]`);
      close(jacr[i], native.site_jacr[site * n + i], `${label}: ${what}: jacr[${i}]`);
    }
    for (let k = 0; k < 3; k++) {
      close(data.site_xpos[3 * site + k], flatNative('site_xpos')[3 * site + k], `${label}: ${what}: site_xpos[${k}]`);
    }
    data.delete();
  }
  let threw = null;
  data = new mj.MjData(model);
  try {
    mj.lever_jac_site_from_q(model, data, jacp, jacr, model.nsite);
  } catch (e) {
    threw = e;
  }
  if (!(threw instanceof mj.EngineError) || !/site/.test(threw.message)) {
    fail(`${label}: lever_jac_site_from_q at site ${model.nsite} gave ${threw} instead of an EngineError`);
  }
  data.delete();
}

// a dot product's rounding scale: the sum of its terms' magnitudes
function dotScale(a, b) {
  let sum = 0;
  for (let i = 0; i < a.length; i++) sum += Math.abs(a[i] * b[i]);
  return sum;
}
function closeScaled(ours, native, scale, what) {
  compared++;
  if (!(Math.abs(ours - native) <= 1e-12 * Math.max(1, scale))) {
    fail(`${what}: wasm ${ours}, native ${native} (scale ${scale})`);
  }
}


// data.ncon, data.contact and data.efc_J against the rows of `lever forward --json`: each contact
// row names its contact (efc_id), whose dist and includemargin are the row's efc_pos and
// efc_margin; the rows of one contact start at its efc_address and number 1 (condim 1) or
// 2 (condim - 1) (pyramid); efc_J maps native's efc_force to its qfrc_constraint and qvel to its
// efc_vel. Where the command prints contacts itself (ncon, contact), those are compared too.
// Returns the contacts as {geom1, geom2, pos, normal}.
function compareContacts(mj, model, data, native, label) {
  const rowsOf = new Map();
  native.efc_type.forEach((type, r) => {
    if (!kContactTypeRows.has(type)) return;
    const id = native.efc_id[r];
    if (!rowsOf.has(id)) rowsOf.set(id, []);
    rowsOf.get(id).push(r);
  });
  const expectedNcon = native.ncon !== undefined ? native.ncon : rowsOf.size;
  if (data.ncon !== expectedNcon) fail(`${label}: data.ncon ${data.ncon}, native ${expectedNcon}`);
  const contacts = data.contact;
  if (contacts.length !== data.ncon) fail(`${label}: data.contact has ${contacts.length} of ${data.ncon}`);
  for (const [id, rows] of rowsOf) {
    const c = contacts[id];
    if (!c) {
      fail(`${label}: native rows name contact ${id}, the JS data has ${contacts.length}`);
      continue;
    }
    const expectedRows = c.dim === 1 ? 1 : 2 * (c.dim - 1);
    if (rows.length !== expectedRows || rows[0] !== c.efc_address || c.exclude !== 0) {
      fail(`${label}: contact ${id} (dim ${c.dim}, efc_address ${c.efc_address}, exclude ` +
        `${c.exclude}) against native rows ${rows}`);
    }
    for (const r of rows) {
      close(c.dist, native.efc_pos[r], `${label}: contact ${id} dist, row ${r}`);
      close(c.includemargin, native.efc_margin[r], `${label}: contact ${id} includemargin, row ${r}`);
    }
  }
  if (Array.isArray(native.contact)) {
    native.contact.forEach((theirs, i) => {
      for (const [name, value] of Object.entries(theirs)) {
        const ours = contacts[i] && contacts[i][name];
        if (ours === undefined) continue;
        const flat = [value].flat(Infinity);
        const mine = ArrayBuffer.isView(ours) ? Array.from(ours) : [ours];
        if (mine.length !== flat.length) fail(`${label}: contact[${i}].${name} length`);
        flat.forEach((x, k) => close(mine[k], x, `${label}: contact[${i}].${name}[${k}]`));
      }
      // the force in the contact frame (mj_contactForce): decided by the solver, so its bound
      if (theirs.force !== undefined) {
        const force = new Float64Array(6);
        mj.mj_contactForce(model, data, i, force);
        theirs.force.forEach((x, k) =>
          close(force[k], x, `${label}: mj_contactForce(${i})[${k}]`, boundOf('efc_force', native)));
      }
    });
  }
  // efc_J: nefc x nv, row-major
  const nv = model.nv;
  const J = data.efc_J;
  if (J.length !== data.nefc * nv) fail(`${label}: efc_J has ${J.length} numbers for ${data.nefc} x ${nv}`);
  for (let i = 0; i < nv; i++) {
    const column = Array.from({length: data.nefc}, (_, r) => J[r * nv + i]);
    let sum = 0;
    column.forEach((x, r) => (sum += x * native.efc_force[r]));
    // native's own J^T f: efc_J read back exactly, only the sum's order differs
    closeScaled(sum, native.qfrc_constraint[i], dotScale(column, native.efc_force),
      `${label}: (efc_J^T efc_force)[${i}]`);
  }
  for (let r = 0; r < data.nefc; r++) {
    const row = J.subarray(r * nv, (r + 1) * nv);
    let sum = 0;
    row.forEach((x, i) => (sum += x * native.qvel[i]));
    closeScaled(sum, native.efc_vel[r], dotScale(row, native.qvel), `${label}: (efc_J qvel)[${r}]`);
  }
  return contacts.map((c) => ({geom1: c.geom1, geom2: c.geom2, dist: c.dist, pos: Array.from(c.pos),
    normal: Array.from(c.frame.subarray(0, 3))}));
}

// the gripper (a free box, slide fingers) run in wasm: down to the box, grip, lift; at each stage
// the JS views against `lever forward` on the same state
function gripperContacts(mj, root) {
  const file = path.join(root, 'models', 'gripper.xml');
  const model = mj.MjModel.from_xml_string(fs.readFileSync(file, 'utf8'), 'gripper.xml');
  const data = new mj.MjData(model);
  const box = model.name2id('body', 'box');
  const table = model.name2id('geom', 'table');
  const free = model.jnt_qposadr[model.name2id('jnt', 'box')];
  if (data.qpos.length !== model.nq || data.qvel.length !== model.nv || model.nq !== model.nv + 1) {
    fail(`gripper: qpos ${data.qpos.length} (nq ${model.nq}), qvel ${data.qvel.length} (nv ${model.nv}): ` +
      'a free joint has 7 coordinates and 6 dofs');
  }
  mj.mj_resetDataKeyframe(model, data, model.name2id('key', 'open'));
  const run = (ctrl, seconds) => {
    data.ctrl.set(ctrl);
    for (let t = 0; t < seconds / model.opt.timestep; t++) mj.mj_step(model, data);
    mj.mj_forward(model, data);
    const fmt = (v) => Array.from(v, (x) => x.toPrecision(17));
    return nativeForward(file, fmt(data.qpos), fmt(data.qvel), fmt(data.ctrl));
  };
  run([-0.23, 0, 0], 0.6);
  const seen = {};
  for (const [name, ctrl, seconds] of [['gripped', [-0.23, 0.05, 0.05], 0.5], ['lifted', [0, 0.05, 0.05], 0.6]]) {
    const native = run(ctrl, seconds);
    const label = `gripper ${name}`;
    compareData(mj, model, data, native, label);
    const contacts = compareContacts(mj, model, data, native, label);
    const onTable = contacts.filter((c) => c.geom1 === table || c.geom2 === table);
    for (const c of onTable) {
      // the table is the plane z = 0 (geom1, its normal +z into the box): the point lies midway
      // between the plane and the box's deepest point, dist below the plane
      if (c.geom1 !== table) fail(`${label}: the plane is geom2 of a contact`);
      close(c.normal[2], 1, `${label}: a table contact's normal z`);
      close(c.pos[2], c.dist / 2, `${label}: a table contact's height (dist / 2)`);
    }
    const q = data.qpos.subarray(free + 3, free + 7);
    close(Math.hypot(...q), 1, `${label}: the box's quaternion norm`);
    // the finger pads' touch sensors, by name, are their slices of sensordata, as native's
    for (const pad of ['left_touch', 'right_touch']) {
      const sensor = data.sensor(pad);
      const id = model.name2id('sensor', pad);
      if (sensor.id !== id || id < 0 || sensor.data.length !== 1 ||
          sensor.data[0] !== data.sensordata[model.sensor_adr[id]]) {
        fail(`${label}: data.sensor('${pad}') is not sensordata[${model.sensor_adr[id]}]`);
      }
      // touch sums the solver's contact forces: held to the solver's bound (kSolverDecided above)
      close(sensor.data[0], native.sensordata[model.sensor_adr[id]], `${label}: ${pad}`, 1e-10);
    }
    seen[name] = {ncon: data.ncon, onTable: onTable.length, height: data.xpos[3 * box + 2],
      touch: Array.from(data.sensordata)};
  }
  console.log('gripper contacts: ' + JSON.stringify(seen));
  // the physics the views show: gripped on the table, then held in the air by the fingers alone
  if (!(seen.gripped.onTable > 0 && seen.gripped.ncon > seen.gripped.onTable)) {
    fail('gripper: no table and finger contacts after the grip: ' + JSON.stringify(seen.gripped));
  }
  if (!(seen.lifted.onTable === 0 && seen.lifted.ncon > 0 && seen.lifted.height > 0.1)) {
    fail('gripper: the box is not held up by the fingers: ' + JSON.stringify(seen.lifted));
  }
  const pad = model.sensor('right_touch');
  if (!(pad.id === 1 && pad.type === 0 && pad.dim === 1 && pad.adr === 1 && pad.objtype === 6 &&
        pad.objid === model.name2id('site', 'right_pad') && pad.refid === -1)) {
    fail("gripper: model.sensor('right_touch') is not the touch sensor (mjSENS_TOUCH 0) at site " +
      'right_pad: ' + JSON.stringify(pad));
  }
  if (!(model.nsensor === 2 && model.sensor_names.join() === 'left_touch,right_touch' &&
        seen.lifted.touch.every((f) => f > 1))) {
    fail('gripper: the pads do not feel the held box: ' + JSON.stringify(seen.lifted.touch));
  }
  let threw = false;
  try {
    data.sensor('no_such_pad');
  } catch (e) {
    threw = e instanceof RangeError && e.message.includes('left_touch, right_touch');
  }
  if (!threw) fail("gripper: data.sensor('no_such_pad') did not throw a RangeError naming the sensors");
  data.delete();
  model.delete();
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
      compareLeanCalls(mj, model, s.qpos, native, `${file} state ${seed}`);
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
  gripperContacts(mj, root);

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

  // 4. a pair MuJoCo 2.2.2 collides by MPR (a cylinder tilted into a box table): the search is
  //    lever's own in every build, so the contacts equal the native build's
  const cylinderOnBox = '<mujoco><worldbody><geom name="table" type="box" size="0.2 0.2 0.02"/>' +
    '<body pos="0 0 0.1"><freejoint/><geom name="can" type="cylinder" size="0.03 0.05"/></body>' +
    '</worldbody></mujoco>';
  const can = mj.MjModel.from_xml_string(cylinderOnBox, 'cylinder_on_box.xml');
  const canData = new mj.MjData(can);
  const tilted = [0.01, -0.02, 0.068, Math.cos(0.15), Math.sin(0.15), 0, 0];
  canData.qpos.set(tilted);
  canData.qvel.fill(0);
  mj.mj_forward(can, canData);
  const canFile = path.join(require('os').tmpdir(), `cylinder-on-box-${process.pid}.xml`);
  fs.writeFileSync(canFile, cylinderOnBox);
  const canNative = nativeForward(canFile, tilted.map(String), [], []);
  fs.unlinkSync(canFile);
  if (canData.ncon < 1) fail(`a cylinder tilted into a box: ${canData.ncon} contacts in wasm`);
  compareData(mj, can, canData, canNative, 'cylinder on a box');
  compareContacts(mj, can, canData, canNative, 'cylinder on a box');
  canData.delete();
  can.delete();

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
