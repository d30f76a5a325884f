// lever.js: lever's WebAssembly build (build-web/web/wasm/lever_wasm.js) with MuJoCo's names, so
// that the lesson's expressions run unchanged:
//
//   const mj = await createLever(createLeverModule, {wasmBinary});   // wasmBinary: optional
//   const model = mj.MjModel.from_xml_string(xmlText, 'arm2.xml');   // throws mj.LoadError
//   const data = new mj.MjData(model);
//   data.qpos[0] = 0.6; data.qvel.fill(0);
//   mj.mj_forward(model, data);  data.qfrc_bias[0];
//   model.body_mass[2] = 1.6; mj.mj_setConst(model, data);           // lever::set_const
//
// Arrays are typed-array views onto lever's own Model and Data, one for each row of lever's field
// table (engine/include/lever/fields.hpp): Float64Array, Int32Array for ids and counts, Uint8Array
// for flags, flat in MuJoCo's row-major layout: data.xpos[3 * body + k]. Scalars
// (data.time, data.nefc, data.ncon, model.opt.timestep) are read and written as numbers. The
// efc_ arrays (efc_J: nefc x nv) have data.nefc rows at each access. data.contact is an array of
// the data.ncon current contacts, each with MuJoCo's mjContact fields viewed in place (pos,
// frame: the normal then two tangents, friction, solref, solimp as typed arrays; dist, dim,
// geom1, geom2, includemargin, exclude, efc_address, mu as numbers). data.sensordata holds every
// sensor's numbers (model.sensor_adr, sensor_dim; names in model.sensor_names), and
// data.sensor('left_touch').data is one sensor's, model.sensor('left_touch') its description, as
// in MuJoCo's Python. A view is rebuilt
// whenever the wasm heap has grown or mj_setConst() has run, so keeping `data.qpos` in a variable
// across those is the one thing to avoid (as with MuJoCo's own views).
(function (root) {
  'use strict';

  /** A model lever refuses: `message` is lever's diagnostic, `line` its line (0 if none). */
  class LoadError extends Error {
    constructor(message, line) {
      super(message);
      this.name = 'LoadError';
      this.line = line;
    }
  }

  /** An engine call that failed (sizes that do not match, an invalid model after an edit). */
  class EngineError extends Error {
    constructor(message) {
      super(message);
      this.name = 'EngineError';
    }
  }

  async function createLever(createLeverModule, options) {
    const Module = await createLeverModule(options || {});
    const typed = {f64: 'HEAPF64', i32: 'HEAP32', u8: 'HEAPU8'};
    const bytes = {f64: 8, i32: 4, u8: 1};

    // Defines a getter (and for scalars a setter) on `target` for each field `source.fields()`
    // lists; `generation()` tells when the addresses may have changed.
    function attachFields(target, source, generation) {
      let views = null;
      let buffer = null;
      let seen = -1;
      function current() {
        const heap = Module.HEAPU8.buffer;
        const g = generation();
        if (views && buffer === heap && seen === g) return views;
        views = {};
        const list = source.fields();
        for (let i = 0; i < list.size(); i++) {
          const f = list.get(i);
          const heapView = Module[typed[f.type]];
          const start = f.address / bytes[f.type];
          const length = f.cols === 0 ? 1 : f.rows * f.cols;
          views[f.name] = {scalar: f.cols === 0 && !f.live_rows, view: heapView.subarray(start, start + length)};
          if (f.live_rows) {  // efc_ arrays: as many rows as data.nefc says now
            const nefc = f.live_rows / 4;
            const cols = f.cols;
            views[f.name].live = () => heapView.subarray(start, start + Module.HEAP32[nefc] * cols);
          }
        }
        list.delete();
        buffer = heap;
        seen = g;
        return views;
      }
      const names = current();
      for (const name of Object.keys(names)) {
        const path = name.split('.');
        let owner = target;
        if (path.length === 2) {
          owner = target[path[0]] || (target[path[0]] = {});
        }
        const key = path[path.length - 1];
        if (names[name].scalar) {
          Object.defineProperty(owner, key, {
            enumerable: true,
            get: () => current()[name].view[0],
            set: (value) => { current()[name].view[0] = value; },
          });
        } else {
          Object.defineProperty(owner, key, {
            enumerable: true,
            get: () => {
              const v = current()[name];
              return v.live ? v.live() : v.view;
            },
          });
        }
      }
    }

    class MjModel {
      constructor(wasmModel) {
        this._wasm = wasmModel;
        for (const size of ['nq', 'nv', 'nu', 'nbody', 'njnt', 'ngeom', 'nsite', 'nkey', 'nsensor',
          'nsensordata']) {
          this[size] = wasmModel.size(size);
        }
        for (const kind of ['body', 'jnt', 'geom', 'site', 'actuator', 'sensor', 'key']) {
          const list = wasmModel.names(kind);
          const names = [];
          for (let i = 0; i < list.size(); i++) names.push(list.get(i));
          list.delete();
          this[kind + '_names'] = names;
        }
        attachFields(this, wasmModel, () => wasmModel.generation());
      }

      /** Load MJCF text; throws LoadError with lever's message and line. */
      static from_xml_string(xml, filename) {
        const wasmModel = Module.WasmModel.load(xml, filename || 'model.xml');
        if (!wasmModel.ok()) {
          const error = new LoadError(wasmModel.error(), wasmModel.error_line());
          wasmModel.delete();
          throw error;
        }
        return new MjModel(wasmModel);
      }

      /** Index of a named object (kind: body, jnt, geom, site, actuator, sensor, key), or -1. */
      name2id(kind, name) {
        return this[kind + '_names'].indexOf(name);
      }

      /**
       * Sensor `name` (or its index), as MuJoCo's Python model.sensor(name): {id, name, type, dim,
       * adr, objtype, objid, reftype, refid, cutoff, noise} (mjtSensor and mjtObj numbers). Throws
       * for a sensor the model does not have.
       */
      sensor(name) {
        const id = typeof name === 'number' ? name : this.name2id('sensor', name);
        if (!(id >= 0 && id < this.nsensor)) {
          throw new RangeError('the model has no sensor ' + JSON.stringify(name) +
            (this.nsensor ? ' (its sensors: ' + this.sensor_names.map((n, i) => n || '#' + i).join(', ') + ')'
              : ' (it has no sensors)'));
        }
        const s = {id, name: this.sensor_names[id]};
        for (const key of ['type', 'dim', 'adr', 'objtype', 'objid', 'reftype', 'refid', 'cutoff', 'noise']) {
          s[key] = this['sensor_' + key][id];
        }
        return s;
      }

      delete() {
        this._wasm.delete();
      }
    }

    // lever::Contact's members (offset in bytes, type, count), the same for every Data
    const contactMembers = (() => {
      const list = Module.contact_layout();
      const members = [];
      for (let i = 0; i < list.size(); i++) {
        const m = list.get(i);
        members.push({name: m.name, type: m.type, offset: m.offset, count: m.count});
      }
      list.delete();
      return members;
    })();

    /** Contact `index` of a WasmData: an object whose fields are views into its data.contact. */
    function contactView(wasmData, index) {
      const base = wasmData.contact_address() + index * wasmData.contact_stride();
      const contact = {};
      for (const m of contactMembers) {
        const heap = () => Module[typed[m.type]];
        const start = (base + m.offset) / bytes[m.type];
        if (m.count) {
          Object.defineProperty(contact, m.name, {
            enumerable: true,
            get: () => heap().subarray(start, start + m.count),
          });
        } else {
          Object.defineProperty(contact, m.name, {
            enumerable: true,
            get: () => heap()[start],
            set: (value) => { heap()[start] = value; },
          });
        }
      }
      return contact;
    }

    class MjData {
      constructor(model) {
        this._model = model;
        this._wasm = new Module.WasmData(model._wasm);
        attachFields(this, this._wasm, () => 0);
      }

      /**
       * Sensor `name` (or its index), as MuJoCo's Python data.sensor(name): {id, name, data}, data
       * its numbers, a view into data.sensordata from sensor_adr, sensor_dim long. Throws for a
       * sensor the model does not have.
       */
      sensor(name) {
        const s = this._model.sensor(name);
        return {id: s.id, name: s.name, data: this.sensordata.subarray(s.adr, s.adr + s.dim)};
      }

      /** The data.ncon current contacts (a new array of views at each access). */
      get contact() {
        const n = Math.min(this.ncon, this._wasm.contact_capacity());
        const list = [];
        for (let i = 0; i < n; i++) list.push(contactView(this._wasm, i));
        return list;
      }

      delete() {
        this._wasm.delete();
      }
    }

    function check(message) {
      if (message) throw new EngineError(message);
    }

    const mj = {
      version: Module.version,
      Module,
      LoadError,
      EngineError,
      MjModel,
      MjData,
      mj_step(model, data) { check(data._wasm.step()); },
      mj_forward(model, data) { check(data._wasm.forward()); },
      mj_resetData(model, data) { check(data._wasm.reset()); },
      /** lever::reset_keyframe: time, qpos, qvel and ctrl of keyframe `key` (its index). */
      mj_resetDataKeyframe(model, data, key) { check(data._wasm.reset_keyframe(key)); },
      /**
       * lever::jac_site at data's current kinematics (run mj_forward first), as MuJoCo's
       * mj_jacSite: fills jacp and jacr (3 x nv each, row-major; either may be null).
       */
      mj_jacSite(model, data, jacp, jacr, site) {
        check(data._wasm.jac_site(site));
        const n = 3 * model.nv;
        const start = data._wasm.jac_address() / 8;
        if (jacp) jacp.set(Module.HEAPF64.subarray(start, start + n));
        if (jacr) jacr.set(Module.HEAPF64.subarray(start + n, start + 2 * n));
      },
      // lever's lean calls from data.qpos (lever/kinematics.hpp), for a controller that needs
      // less than mj_forward; each writes what the native call writes, bit for bit.
      /** lever::body_poses: each body's frame alone (data.xpos, xquat, xmat). */
      lever_body_poses(model, data) { check(data._wasm.body_poses()); },
      /**
       * lever::body_kinematics: mj_kinematics and mj_comPos without the geom and site frames (the
       * body, inertial and joint frames, subtree_com, cdof): what M, the bias forces and inverse
       * dynamics read.
       */
      lever_body_kinematics(model, data) { check(data._wasm.body_kinematics()); },
      /**
       * lever::jac_site_from_q: a site's Jacobians (as mj_jacSite: jacp and jacr, 3 x nv each,
       * row-major; either may be null) and its frame (data.site_xpos, site_xmat) from data.qpos,
       * placing only the bodies of the site's tree (no mj_forward needed first).
       */
      lever_jac_site_from_q(model, data, jacp, jacr, site) {
        check(data._wasm.jac_site_from_q(site));
        const n = 3 * model.nv;
        const start = data._wasm.jac_address() / 8;
        if (jacp) jacp.set(Module.HEAPF64.subarray(start, start + n));
        if (jacr) jacr.set(Module.HEAPF64.subarray(start + n, start + 2 * n));
      },
      // lever::set_const after editing model parameters (body_mass, ...). As MuJoCo 2.2.2's
      // mj_setConst, which computes its constants in `data` at qpos0, it leaves data.qpos at
      // qpos0 (and the outputs of that pose in data); qvel, ctrl and time are kept.
      mj_setConst(model, data) {
        check(model._wasm.set_const());
        data.qpos.set(model.qpos0);
        check(data._wasm.forward());
      },
      /** Contact id's force in its frame into result (6 numbers), as mj_contactForce. */
      mj_contactForce(model, data, id, result) {
        check(data._wasm.contact_force(id));
        const start = data._wasm.contact_force_address() / 8;
        result.set(Module.HEAPF64.subarray(start, start + 6));
      },
      /** n steps in one call into wasm (the same as n calls of mj_step). */
      mj_steps(model, data, n) { check(data._wasm.steps(n)); },
      /** `lever check` on MJCF text (lesson 5.1's six checks, lesson 5.2's two, lesson 5.3's contacts): its text, or its JSON. */
      lever_check(xml, filename, json) {
        return Module.check_model_text(xml, filename || 'model.xml', !!json);
      },
      /** lever's warnings since the last reset, one per line ("" if none). */
      warnings(data) { return data._wasm.warnings(); },
    };
    return mj;
  }

  root.createLever = createLever;
  if (typeof module !== 'undefined' && module.exports) module.exports = {createLever};
})(typeof window !== 'undefined' ? window : globalThis);
