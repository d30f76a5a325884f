// node web/bench/js_step_time.js WASM_DIR MODEL: one lab step driven from JavaScript through
// web/lever.js (mj_forward, the controller's ctrl = qfrc_bias, mj_step), as the page runs it.
// Prints ns per step (best of 5); `make web-bench` runs it after the C++ loops.
'use strict';
const fs = require('fs');
const path = require('path');
const [wasmDir, modelPath] = process.argv.slice(2);
const createLeverModule = require(path.resolve(wasmDir, 'lever_wasm.js'));
const {createLever} = require('../lever.js');

(async () => {
  // node 18+ would fetch() the .wasm by path: hand it the bytes instead
  const mj = await createLever(createLeverModule,
    {wasmBinary: fs.readFileSync(path.resolve(wasmDir, 'lever_wasm.wasm'))});
  const model = mj.MjModel.from_xml_string(fs.readFileSync(modelPath, 'utf8'), modelPath);
  const data = new mj.MjData(model);
  const steps = 100000;
  let best = Infinity;
  for (let run = 0; run < 5; run++) {
    mj.mj_resetData(model, data);
    data.qpos[0] = 0.6;
    data.qpos[1] = -1.2;
    const start = process.hrtime.bigint();
    for (let i = 0; i < steps; i++) {
      mj.mj_forward(model, data);
      data.ctrl[0] = data.qfrc_bias[0];
      data.ctrl[1] = data.qfrc_bias[1];
      mj.mj_step(model, data);
    }
    best = Math.min(best, Number(process.hrtime.bigint() - start) / steps);
  }
  const size = fs.statSync(path.resolve(wasmDir, 'lever_wasm.wasm')).size;
  console.log(`${modelPath}: ${best.toFixed(0)} ns per lab step from JavaScript (best of 5 x ${steps});` +
    ` lever_wasm.wasm ${size} bytes`);
})();
