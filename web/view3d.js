// view3d.js: a model drawn in 3D with three.js (Debian's libjs-three, served with the page at
// vendor/three/), from MuJoCo's free camera (window.View3D).
//
//   const view = View3D.create(canvas, model, camera);   // null when WebGL is not available
//   view.draw(data, overlays, trail, normalForces);       // after every change of the state
//
// Geoms as MuJoCo draws them: sphere, capsule, ellipsoid, cylinder, box; a mesh geom as the box
// lever sized it by (its bounding box, when lever read the mesh). Each geom's pose is its body's
// (data.xpos, data.xquat) composed with the geom's own (model.geom_pos, model.geom_quat), as
// MuJoCo's geom_xpos and geom_xmat are. The camera is MuJoCo's free camera: it looks along
// forward = (cos el cos az, cos el sin az, sin el) at `target` from `distance`, with 45 degrees of
// vertical field of view (mjvCamera; azimuth and elevation in degrees). Dragging changes azimuth
// and elevation, the wheel the distance, a double click restores the spec's camera.
//
// The contacts overlay draws each of data.contact's points (pos) as a small ball and its normal
// (frame's first row, from geom1 into geom2) as a line from it: CONTACT_NORMAL long, or scaled by
// the contact's normal force when draw() is given one per contact (N -> m by NORMAL_PER_NEWTON).
(function (root) {
  'use strict';

  const GEOM = {plane: 0, sphere: 2, capsule: 3, ellipsoid: 4, cylinder: 5, box: 6, mesh: 7};
  const AXIS_LENGTH = 0.1;  // m: the frames overlay, as the 2D view draws it
  const MARKER = 0.02;      // m: radius of the joint, com and site markers
  const TRAIL_POINTS = 2000;
  const CONTACT_MARKER = 0.004;    // m: radius of a contact point's ball
  const CONTACT_NORMAL = 0.03;     // m: a normal's length when no force is given
  const NORMAL_PER_NEWTON = 0.01;  // m per N of normal force

  function freeCamera(spec) {
    const c = spec || {};
    return {
      azimuth: c.azimuth === undefined ? 90 : c.azimuth,
      elevation: c.elevation === undefined ? -45 : c.elevation,
      distance: c.distance || 2,
      target: (c.target || [0, 0, 0]).slice(),
    };
  }

  // a sphere whose octants alternate black and white: MuJoCo's centre-of-mass marker
  function comGeometry(THREE) {
    const g = new THREE.SphereBufferGeometry(MARKER, 16, 12);
    const p = g.getAttribute('position');
    const colors = new Float32Array(p.count * 3);
    for (let i = 0; i < p.count; i++) {
      const sign = Math.sign(p.getX(i) || 1) * Math.sign(p.getY(i) || 1) * Math.sign(p.getZ(i) || 1);
      colors.fill(sign > 0 ? 0.95 : 0.05, 3 * i, 3 * i + 3);
    }
    g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    return g;
  }

  // WebGL drawn by the CPU (SwiftShader, as in headless Chromium): multisampling there costs more
  // than half the frame rate, so the view goes without it
  function softwareRendering() {
    const gl = document.createElement('canvas').getContext('webgl');
    if (!gl) return false;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const name = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    const lose = gl.getExtension('WEBGL_lose_context');
    if (lose) lose.loseContext();
    return /swiftshader|llvmpipe|software/i.test(String(name));
  }

  class View3D {
    /** The view on `canvas`, or null when three.js or WebGL is missing (the page then draws in 2D). */
    static create(canvas, model, camera) {
      const THREE = root.THREE;
      if (!THREE) return null;
      let renderer;
      try {
        const antialias = !softwareRendering();
        const context = canvas.getContext('webgl', {antialias});
        if (!context) return null;
        renderer = new THREE.WebGLRenderer({canvas, context, antialias});
      } catch (e) {
        return null;
      }
      return new View3D(THREE, renderer, canvas, model, camera);
    }

    constructor(THREE, renderer, canvas, model, camera) {
      this.THREE = THREE;
      this.renderer = renderer;
      this.canvas = canvas;
      this.model = model;
      this.specCamera = freeCamera(camera);
      this.cam = freeCamera(camera);
      renderer.setClearColor(0xeef1f4, 1);  // a tint, so that white links stand out
      this.scene = new THREE.Scene();
      this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
      this.scene.add(new THREE.AmbientLight(0xffffff, 0.45));
      const headlight = new THREE.DirectionalLight(0xffffff, 0.55);  // follows the camera
      this.camera.add(headlight);
      this.scene.add(this.camera);
      const sun = new THREE.DirectionalLight(0xffffff, 0.35);
      sun.position.set(0.3, -0.5, 1);
      this.scene.add(sun);
      const grid = new THREE.GridHelper(4, 20, 0xc2c8ce, 0xd8dde2);  // the floor z = 0, 20 cm squares
      grid.rotation.x = Math.PI / 2;
      this.scene.add(grid);
      this.buildGeoms();
      this.buildOverlays();
      this.listen();
    }

    buildGeoms() {
      const THREE = this.THREE;
      const m = this.model;
      this.geoms = [];
      for (let i = 0; i < m.ngeom; i++) {
        const size = [m.geom_size[3 * i], m.geom_size[3 * i + 1], m.geom_size[3 * i + 2]];
        const rgba = [0, 1, 2, 3].map((k) => m.geom_rgba[4 * i + k]);
        const material = new THREE.MeshPhongMaterial({
          color: new THREE.Color(rgba[0], rgba[1], rgba[2]), shininess: 30,
          transparent: rgba[3] < 1, opacity: rgba[3]});
        const group = new THREE.Group();
        const add = (geometry, rotateToZ, position) => {
          const mesh = new THREE.Mesh(geometry, material);
          if (rotateToZ) mesh.rotation.x = Math.PI / 2;  // three's cylinders run along y
          if (position) mesh.position.set(0, 0, position);
          group.add(mesh);
        };
        switch (m.geom_type[i]) {
          case GEOM.plane:  // a plane's size: half-lengths in x and y (0: infinite, drawn as 2 m)
            add(new THREE.PlaneBufferGeometry(2 * (size[0] || 1), 2 * (size[1] || 1)));
            material.side = THREE.DoubleSide;
            break;
          case GEOM.sphere:
            add(new THREE.SphereBufferGeometry(size[0], 24, 16));
            break;
          case GEOM.ellipsoid: {
            add(new THREE.SphereBufferGeometry(1, 24, 16));
            group.children[0].scale.set(size[0], size[1], size[2]);
            break;
          }
          case GEOM.capsule:  // radius size[0], half-length size[1] along z, with round ends
            add(new THREE.CylinderBufferGeometry(size[0], size[0], 2 * size[1], 24, 1, true), true);
            add(new THREE.SphereBufferGeometry(size[0], 24, 12), false, size[1]);
            add(new THREE.SphereBufferGeometry(size[0], 24, 12), false, -size[1]);
            break;
          case GEOM.cylinder:
            add(new THREE.CylinderBufferGeometry(size[0], size[0], 2 * size[1], 32), true);
            break;
          case GEOM.box:
          case GEOM.mesh:  // the box lever sized it by; size 0 when lever did not read the mesh
            if (size[0] > 0 && size[1] > 0 && size[2] > 0) {
              add(new THREE.BoxBufferGeometry(2 * size[0], 2 * size[1], 2 * size[2]));
            }
            break;
          default:
            break;
        }
        group.matrixAutoUpdate = true;
        this.scene.add(group);
        this.geoms.push(group);
      }
    }

    buildOverlays() {
      const THREE = this.THREE;
      const m = this.model;
      const onTop = (object) => {  // overlays show through the links, as in the 2D view
        object.renderOrder = 10;
        object.traverse((o) => {
          if (o.material) o.material.depthTest = false;
        });
        this.scene.add(object);
        return object;
      };
      // frames: three axes per body (red x, green y, blue z)
      const frameGeometry = new THREE.BufferGeometry();
      frameGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(m.nbody * 18), 3));
      const frameColors = new Float32Array(m.nbody * 18);
      const axisColor = [[0.85, 0.2, 0.2], [0.2, 0.65, 0.2], [0.2, 0.2, 0.85]];
      for (let b = 0; b < m.nbody; b++) {
        for (let k = 0; k < 3; k++) {
          frameColors.set(axisColor[k], 18 * b + 6 * k);
          frameColors.set(axisColor[k], 18 * b + 6 * k + 3);
        }
      }
      frameGeometry.setAttribute('color', new THREE.BufferAttribute(frameColors, 3));
      this.frames = onTop(new THREE.LineSegments(frameGeometry,
        new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors})));
      const markers = (count, geometry, material) => {
        const group = new THREE.Group();
        for (let i = 0; i < count; i++) group.add(new THREE.Mesh(geometry, material));
        return onTop(group);
      };
      const ball = new THREE.SphereBufferGeometry(MARKER, 16, 12);
      this.joints = markers(m.njnt, ball, new THREE.MeshBasicMaterial({color: 0xffffff}));
      const jointRings = markers(m.njnt, new THREE.SphereBufferGeometry(MARKER * 1.25, 16, 12),
        new THREE.MeshBasicMaterial({color: 0x333333, side: THREE.BackSide}));
      this.jointRings = jointRings;
      this.coms = markers(Math.max(0, m.nbody - 1), comGeometry(THREE),
        new THREE.MeshBasicMaterial({vertexColors: THREE.VertexColors}));
      this.sites = markers(m.nsite, new THREE.SphereBufferGeometry(MARKER * 0.7, 12, 8),
        new THREE.MeshBasicMaterial({color: 0xcc00cc}));
      // the trail: a line through the last TRAIL_POINTS positions of the trail site
      const trailGeometry = new THREE.BufferGeometry();
      trailGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * TRAIL_POINTS), 3));
      trailGeometry.setDrawRange(0, 0);
      this.trail = onTop(new THREE.Line(trailGeometry, new THREE.LineBasicMaterial({color: 0xe6b800})));
      this.trail.frustumCulled = false;
      this.frames.frustumCulled = false;
      // contacts: balls added as more contacts appear, normals as one set of line segments
      this.contactBall = new THREE.SphereBufferGeometry(CONTACT_MARKER, 12, 8);
      this.contactMaterial = new THREE.MeshBasicMaterial({color: 0x00a0ff, depthTest: false});
      this.contactPoints = onTop(new THREE.Group());
      this.contactNormals = onTop(new THREE.LineSegments(new THREE.BufferGeometry(),
        new THREE.LineBasicMaterial({color: 0x0060c0})));
      this.contactNormals.frustumCulled = false;
    }

    // the contacts of data (see the file's comment); normalForces: one number per contact, or null
    drawContacts(data, visible, normalForces) {
      const THREE = this.THREE;
      const contacts = visible ? data.contact : [];
      while (this.contactPoints.children.length < contacts.length) {
        const ball = new THREE.Mesh(this.contactBall, this.contactMaterial);
        ball.renderOrder = 10;
        this.contactPoints.add(ball);
      }
      let segments = this.contactNormals.geometry.getAttribute('position');
      if (!segments || segments.count < 2 * contacts.length) {
        const capacity = Math.max(16, 2 * contacts.length);
        segments = new THREE.BufferAttribute(new Float32Array(3 * capacity), 3);
        this.contactNormals.geometry.setAttribute('position', segments);
      }
      this.contactPoints.children.forEach((ball, i) => (ball.visible = i < contacts.length));
      contacts.forEach((c, i) => {
        const p = c.pos;
        const n = c.frame;  // its first row is the normal
        const length = normalForces ? NORMAL_PER_NEWTON * normalForces[i] : CONTACT_NORMAL;
        this.contactPoints.children[i].position.set(p[0], p[1], p[2]);
        segments.setXYZ(2 * i, p[0], p[1], p[2]);
        segments.setXYZ(2 * i + 1, p[0] + length * n[0], p[1] + length * n[1], p[2] + length * n[2]);
      });
      segments.needsUpdate = true;
      this.contactNormals.geometry.setDrawRange(0, 2 * contacts.length);
      this.contactPoints.visible = this.contactNormals.visible = visible;
    }

    /** What the contacts overlay shows now (for tests): each ball's centre and its normal's tip. */
    contactMarkers() {
      if (!this.contactPoints.visible) return [];
      const segments = this.contactNormals.geometry.getAttribute('position');
      return this.contactPoints.children.filter((ball) => ball.visible).map((ball, i) => ({
        pos: [ball.position.x, ball.position.y, ball.position.z],
        tip: [segments.getX(2 * i + 1), segments.getY(2 * i + 1), segments.getZ(2 * i + 1)],
      }));
    }

    // mouse: drag to orbit (azimuth, elevation), wheel to zoom (distance), double click to reset
    listen() {
      let last = null;
      this.canvas.addEventListener('pointerdown', (event) => {
        last = [event.clientX, event.clientY];
        this.canvas.setPointerCapture(event.pointerId);
      });
      this.canvas.addEventListener('pointermove', (event) => {
        if (!last) return;
        const dx = event.clientX - last[0];
        const dy = event.clientY - last[1];
        last = [event.clientX, event.clientY];
        this.orbit(-0.4 * dx, -0.4 * dy);
      });
      const stop = () => {
        last = null;
      };
      this.canvas.addEventListener('pointerup', stop);
      this.canvas.addEventListener('pointercancel', stop);
      this.canvas.addEventListener('wheel', (event) => {
        event.preventDefault();
        this.zoom(Math.exp(0.001 * event.deltaY));
      }, {passive: false});
      this.canvas.addEventListener('dblclick', () => {
        this.cam = freeCamera(this.specCamera);
        this.render();
      });
    }

    /** Turn the camera by degrees of azimuth and elevation (kept short of the poles). */
    orbit(dAzimuth, dElevation) {
      this.cam.azimuth = ((this.cam.azimuth + dAzimuth + 540) % 360) - 180;
      this.cam.elevation = Math.max(-89, Math.min(89, this.cam.elevation + dElevation));
      this.render();
    }

    /** Multiply the camera's distance to its target by `factor`. */
    zoom(factor) {
      this.cam.distance = Math.max(0.05, Math.min(50, this.cam.distance * factor));
      this.render();
    }

    placeCamera() {
      const {azimuth, elevation, distance, target} = this.cam;
      const az = (azimuth * Math.PI) / 180;
      const el = (elevation * Math.PI) / 180;
      const forward = [Math.cos(el) * Math.cos(az), Math.cos(el) * Math.sin(az), Math.sin(el)];
      const up = [-Math.sin(el) * Math.cos(az), -Math.sin(el) * Math.sin(az), Math.cos(el)];
      this.camera.position.set(target[0] - distance * forward[0], target[1] - distance * forward[1],
        target[2] - distance * forward[2]);
      this.camera.up.set(up[0], up[1], up[2]);
      this.camera.lookAt(target[0], target[1], target[2]);
    }

    resize() {
      const ratio = root.devicePixelRatio || 1;
      const width = Math.max(1, this.canvas.clientWidth);
      const height = Math.max(1, this.canvas.clientHeight);
      const size = this.renderer.getSize(new this.THREE.Vector2());
      if (size.x !== width || size.y !== height || this.renderer.getPixelRatio() !== ratio) {
        this.renderer.setPixelRatio(ratio);
        this.renderer.setSize(width, height, false);
        this.camera.aspect = width / height;
        this.camera.updateProjectionMatrix();
      }
    }

    /** Move everything to data's state and render. */
    draw(data, overlays, trail, normalForces) {
      const m = this.model;
      const at = (array, i, n) => Array.from(array.subarray(n * i, n * i + n));
      for (let i = 0; i < m.ngeom; i++) {
        const b = m.geom_bodyid[i];
        const bodyQuat = this.quaternion(at(data.xquat, b, 4));
        const position = new this.THREE.Vector3(...at(m.geom_pos, i, 3)).applyQuaternion(bodyQuat)
          .add(new this.THREE.Vector3(...at(data.xpos, b, 3)));
        this.geoms[i].position.copy(position);
        this.geoms[i].quaternion.copy(bodyQuat.multiply(this.quaternion(at(m.geom_quat, i, 4))));
      }
      const frame = this.frames.geometry.getAttribute('position');
      for (let b = 0; b < m.nbody; b++) {
        const o = at(data.xpos, b, 3);
        const r = at(data.xmat, b, 9);  // row-major: column k is body axis k
        for (let k = 0; k < 3; k++) {
          frame.setXYZ(6 * b + 2 * k, o[0], o[1], o[2]);
          frame.setXYZ(6 * b + 2 * k + 1, o[0] + AXIS_LENGTH * r[k], o[1] + AXIS_LENGTH * r[3 + k],
            o[2] + AXIS_LENGTH * r[6 + k]);
        }
      }
      frame.needsUpdate = true;
      this.frames.visible = !!overlays.frames;
      for (let j = 0; j < m.njnt; j++) {
        this.joints.children[j].position.set(...at(data.xanchor, j, 3));
        this.jointRings.children[j].position.set(...at(data.xanchor, j, 3));
      }
      this.joints.visible = this.jointRings.visible = !!overlays.joints;
      for (let b = 1; b < m.nbody; b++) this.coms.children[b - 1].position.set(...at(data.xipos, b, 3));
      this.coms.visible = !!overlays.com;
      for (let s = 0; s < m.nsite; s++) this.sites.children[s].position.set(...at(data.site_xpos, s, 3));
      this.sites.visible = !!overlays.sites;
      this.drawContacts(data, !!overlays.contacts, normalForces || null);
      const line = this.trail.geometry.getAttribute('position');
      const points = trail.slice(-TRAIL_POINTS);
      points.forEach((p, i) => line.setXYZ(i, p[0], p[1], p[2]));
      line.needsUpdate = true;
      this.trail.geometry.setDrawRange(0, points.length);
      this.render();
    }

    quaternion(q) {  // MuJoCo's (w, x, y, z) as three's (x, y, z, w)
      return new this.THREE.Quaternion(q[1], q[2], q[3], q[0]);
    }

    render() {
      this.resize();
      this.placeCamera();
      this.renderer.render(this.scene, this.camera);
    }

    /**
     * What the last frame drew (for tests; call it right after draw(), in the same task): how many
     * pixels differ from the background, and a checksum (FNV-1a) of the whole picture.
     */
    pixelSummary() {
      const gl = this.renderer.getContext();
      const width = gl.drawingBufferWidth;
      const height = gl.drawingBufferHeight;
      const pixels = new Uint8Array(4 * width * height);
      gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
      let checksum = 0x811c9dc5;
      for (let i = 0; i < pixels.length; i++) checksum = Math.imul(checksum ^ pixels[i], 0x01000193) >>> 0;
      const background = this.renderer.getClearColor().toArray().map((c) => Math.round(255 * c));
      let count = 0;
      for (let i = 0; i < pixels.length; i += 4) {
        const difference = Math.abs(pixels[i] - background[0]) + Math.abs(pixels[i + 1] - background[1]) +
          Math.abs(pixels[i + 2] - background[2]);
        if (difference > 12) count++;
      }
      return {inked: count, checksum};
    }
  }

  root.View3D = View3D;
})(window);
