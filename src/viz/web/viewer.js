// faze4 viewer: draws a run's scene and motion with WebGL2. No dependencies.
//
// Data (written by src/viz/scene.rs): a scene blob ("F4VZ", version, JSON header, mesh arrays)
// and fixed-size f32 sample records: t, tool xyz, target xyz (NaN: none), q (dof), then per
// slot a world pose (12 floats, column-major 3x4). Export mode reads both from the page; live
// mode fetches the scene and follows the run over Server-Sent Events.
//
// URL fragment: #t=1.5 starts there, &paused holds it, &view=azimuth,elevation,distance (deg, deg, m)
// sets the camera.
'use strict';
(() => {
  const $ = (id) => document.getElementById(id);
  const config = JSON.parse($('faze4-config').textContent);
  const live = config.mode === 'live';

  // ---------------------------------------------------------------- state
  const state = {
    scene: null, // { header, gpu }
    stride: 0,
    samples: new Float32Array(0),
    count: 0,
    t: 0,
    playing: true,
    speed: 1,
    follow: live,
    summary: config.summary || null,
    ended: !live,
    connected: false,
    message: live ? 'waiting for the simulation…' : '',
    run: null,
  };

  // fragment: #t=1.0&paused&view=az,el,dist
  const fragment = new URLSearchParams(location.hash.replace(/^#/, ''));
  if (fragment.has('t')) {
    state.t = Math.max(0, parseFloat(fragment.get('t')) || 0);
    state.follow = false;
  }
  if (fragment.has('paused')) state.playing = false;

  // ---------------------------------------------------------------- data
  function base64Bytes(s) {
    s = s.trim();
    if (!s) return new Uint8Array(0);
    const bin = atob(s);
    const out = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out;
  }

  function parseScene(bytes) {
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const magic = String.fromCharCode(bytes[0], bytes[1], bytes[2], bytes[3]);
    if (magic !== 'F4VZ') throw new Error('not a faze4 scene');
    if (dv.getUint32(4, true) !== 2) throw new Error('unknown scene format ' + dv.getUint32(4, true));
    const len = dv.getUint32(8, true);
    const header = JSON.parse(new TextDecoder().decode(bytes.subarray(12, 12 + len)));
    const start = (12 + len + 3) & ~3;
    return { header, blob: bytes.slice(start).buffer };
  }

  function appendSamples(bytes) {
    if (!state.stride || bytes.length === 0) return;
    const floats = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 4);
    const n = floats.length / state.stride;
    const need = (state.count + n) * state.stride;
    if (need > state.samples.length) {
      const grown = new Float32Array(Math.max(need, state.samples.length * 2, 64 * state.stride));
      grown.set(state.samples.subarray(0, state.count * state.stride));
      state.samples = grown;
    }
    state.samples.set(floats, state.count * state.stride);
    const first = state.count;
    state.count += n;
    if (gpu) gpu.trailAppend(first);
  }

  function resetSamples(stride) {
    state.stride = stride;
    state.samples = new Float32Array(0);
    state.count = 0;
    if (gpu) gpu.trailReset();
  }

  const sampleTime = (k) => state.samples[k * state.stride];
  const lastTime = () => (state.count ? sampleTime(state.count - 1) : 0);
  const duration = () => {
    const run = state.scene && state.scene.header.run;
    return Math.max(lastTime(), run && run.duration ? run.duration : 0);
  };

  // index of the last sample with time <= t
  function sampleAt(t) {
    let lo = 0;
    let hi = state.count - 1;
    if (hi < 0) return -1;
    if (t < sampleTime(0)) return 0;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (sampleTime(mid) <= t) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }

  // ---------------------------------------------------------------- math (column-major 4x4)
  function mul(a, b) {
    const o = new Float32Array(16);
    for (let c = 0; c < 4; c++)
      for (let r = 0; r < 4; r++)
        o[c * 4 + r] = a[r] * b[c * 4] + a[4 + r] * b[c * 4 + 1] + a[8 + r] * b[c * 4 + 2] + a[12 + r] * b[c * 4 + 3];
    return o;
  }
  function perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2);
    const o = new Float32Array(16);
    o[0] = f / aspect;
    o[5] = f;
    o[10] = (far + near) / (near - far);
    o[11] = -1;
    o[14] = (2 * far * near) / (near - far);
    return o;
  }
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const norm = (a) => {
    const l = Math.hypot(a[0], a[1], a[2]) || 1;
    return [a[0] / l, a[1] / l, a[2] / l];
  };
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  function lookAt(eye, target, up) {
    const f = norm(sub(target, eye));
    const s = norm(cross(f, up));
    const u = cross(s, f);
    return new Float32Array([
      s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
      -dot(s, eye), -dot(u, eye), dot(f, eye), 1,
    ]);
  }
  function poseMatrix(p, o = 0) {
    return new Float32Array([
      p[o], p[o + 1], p[o + 2], 0, p[o + 3], p[o + 4], p[o + 5], 0,
      p[o + 6], p[o + 7], p[o + 8], 0, p[o + 9], p[o + 10], p[o + 11], 1,
    ]);
  }

  // ---------------------------------------------------------------- camera
  const deg = Math.PI / 180;
  const camera = { target: [0.08, -0.3, 0.3], dist: 1.5, az: -50 * deg, el: 22 * deg };
  let cameraHome = null;
  function homeCamera(header) {
    if (header.board) {
      const c = header.board.center;
      camera.target = [c[0] - 0.02, (c[1] - 0.21) / 2, c[2] - 0.12];
      camera.dist = 1.45;
      camera.az = 30 * deg;
      camera.el = 18 * deg;
    } else {
      camera.target = [0.08, -0.3, 0.32];
      camera.dist = 1.45;
      camera.az = -50 * deg;
      camera.el = 20 * deg;
    }
    if (fragment.has('view')) {
      const v = fragment.get('view').split(',').map(parseFloat);
      if (Number.isFinite(v[0])) camera.az = v[0] * deg;
      if (Number.isFinite(v[1])) camera.el = v[1] * deg;
      if (Number.isFinite(v[2])) camera.dist = v[2];
    }
    cameraHome = JSON.parse(JSON.stringify(camera));
  }
  function eye() {
    const ce = Math.cos(camera.el);
    return [
      camera.target[0] + camera.dist * ce * Math.cos(camera.az),
      camera.target[1] + camera.dist * ce * Math.sin(camera.az),
      camera.target[2] + camera.dist * Math.sin(camera.el),
    ];
  }

  // ---------------------------------------------------------------- WebGL
  const canvas = $('view');
  const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true, premultipliedAlpha: false });
  let gpu = null;

  const MESH_VS = `#version 300 es
    layout(location = 0) in vec3 a_pos;
    layout(location = 1) in vec2 a_oct;
    layout(location = 2) in vec4 a_inst;
    uniform mat4 u_viewproj, u_model;
    uniform vec3 u_min, u_ext;
    uniform bool u_instanced;
    out vec3 v_n, v_p;
    vec3 octDecode(vec2 e) {
      vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
      float t = max(-n.z, 0.0);
      n.x += n.x >= 0.0 ? -t : t;
      n.y += n.y >= 0.0 ? -t : t;
      return normalize(n);
    }
    void main() {
      vec3 p = u_min + a_pos * u_ext;
      vec3 n = octDecode(a_oct);
      vec4 w;
      if (u_instanced) { w = vec4(a_inst.xyz + p * a_inst.w, 1.0); v_n = n; }
      else { w = u_model * vec4(p, 1.0); v_n = mat3(u_model) * n; }
      v_p = w.xyz;
      gl_Position = u_viewproj * w;
    }`;
  const MESH_FS = `#version 300 es
    precision highp float;
    in vec3 v_n, v_p;
    uniform vec4 u_color;
    uniform vec3 u_eye, u_key, u_fill;
    out vec4 o;
    void main() {
      vec3 n = normalize(v_n);
      vec3 v = normalize(u_eye - v_p);
      if (dot(n, v) < 0.0) n = -n;
      float d = 0.75 * max(dot(n, u_key), 0.0) + 0.3 * max(dot(n, u_fill), 0.0);
      float hemi = 0.5 + 0.5 * n.z;
      float s = pow(max(dot(n, normalize(u_key + v)), 0.0), 48.0) * 0.22;
      o = vec4(u_color.rgb * (0.22 + 0.16 * hemi + d) + vec3(s), u_color.a);
    }`;
  const GROUND_VS = `#version 300 es
    layout(location = 0) in vec2 a_xy;
    uniform mat4 u_viewproj;
    uniform vec2 u_centre;
    out vec2 v_xy;
    void main() { v_xy = u_centre + a_xy * 2.0; gl_Position = u_viewproj * vec4(v_xy, 0.0, 1.0); }`;
  const GROUND_FS = `#version 300 es
    precision highp float;
    in vec2 v_xy;
    uniform vec2 u_centre;
    out vec4 o;
    void main() {
      vec2 g = v_xy / 0.1;
      vec2 w = abs(fract(g - 0.5) - 0.5) / fwidth(g);
      float line = 1.0 - min(min(w.x, w.y), 1.0);
      float fade = clamp(1.0 - length(v_xy - u_centre) / 1.8, 0.0, 1.0);
      o = vec4(mix(vec3(0.30, 0.33, 0.38), vec3(0.55, 0.60, 0.68), line), (0.35 + 0.4 * line) * fade);
    }`;

  function program(vs, fs) {
    const p = gl.createProgram();
    for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
      const s = gl.createShader(type);
      gl.shaderSource(s, src);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      gl.attachShader(p, s);
    }
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    const u = {};
    const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < n; i++) {
      const name = gl.getActiveUniform(p, i).name;
      u[name] = gl.getUniformLocation(p, name);
    }
    return { p, u };
  }

  function makeGpu(header, blob) {
    const meshProg = program(MESH_VS, MESH_FS);
    const groundProg = program(GROUND_VS, GROUND_FS);
    const buffer = (target, data) => {
      const b = gl.createBuffer();
      gl.bindBuffer(target, b);
      gl.bufferData(target, data, gl.STATIC_DRAW);
      return b;
    };
    const meshes = header.meshes.map((m) => {
      const pos = buffer(gl.ARRAY_BUFFER, new Uint16Array(blob, m.pos, m.vertices * 3));
      const nrm = buffer(gl.ARRAY_BUFFER, new Int8Array(blob, m.nrm, m.vertices * 2));
      const idxData = m.index_bytes === 2 ? new Uint16Array(blob, m.idx, m.indices) : new Uint32Array(blob, m.idx, m.indices);
      const idx = buffer(gl.ELEMENT_ARRAY_BUFFER, idxData);
      const ext = [0, 1, 2].map((a) => m.max[a] - m.min[a]);
      return { pos, nrm, idx, count: m.indices, type: m.index_bytes === 2 ? gl.UNSIGNED_SHORT : gl.UNSIGNED_INT, min: m.min, ext };
    });
    function vao(mesh, instances) {
      const v = gl.createVertexArray();
      gl.bindVertexArray(v);
      gl.bindBuffer(gl.ARRAY_BUFFER, mesh.pos);
      gl.enableVertexAttribArray(0);
      gl.vertexAttribPointer(0, 3, gl.UNSIGNED_SHORT, true, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, mesh.nrm);
      gl.enableVertexAttribArray(1);
      gl.vertexAttribPointer(1, 2, gl.BYTE, true, 0, 0);
      if (instances) {
        gl.bindBuffer(gl.ARRAY_BUFFER, instances);
        gl.enableVertexAttribArray(2);
        gl.vertexAttribPointer(2, 4, gl.FLOAT, false, 0, 0);
        gl.vertexAttribDivisor(2, 1);
      }
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, mesh.idx);
      gl.bindVertexArray(null);
      return v;
    }
    const visuals = header.visuals.map((v) => ({
      vao: vao(meshes[v.mesh]),
      mesh: meshes[v.mesh],
      slot: v.slot,
      placement: poseMatrix(v.placement),
      color: v.color,
    }));
    // instanced spheres: the reference path (static), the trail (grows), the target (one)
    const sphere = meshes[header.sphere_mesh];
    const instanced = (capacity) => {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, capacity * 16, gl.DYNAMIC_DRAW);
      return { buf: b, vao: vao(sphere, b), capacity, count: 0 };
    };
    const ref = header.reference;
    const refSet = instanced(Math.max(1, ref.length / 3));
    {
      const data = new Float32Array((ref.length / 3) * 4);
      for (let k = 0; k < ref.length / 3; k++) {
        data.set([ref[3 * k], ref[3 * k + 1], ref[3 * k + 2], header.radii.reference], 4 * k);
      }
      gl.bindBuffer(gl.ARRAY_BUFFER, refSet.buf);
      gl.bufferSubData(gl.ARRAY_BUFFER, 0, data);
      refSet.count = ref.length / 3;
    }
    const targetSet = instanced(1);
    let trail = instanced(1024);
    const trailRadius = header.radii.trail;
    function trailWrite(first) {
      const n = state.count - first;
      if (n <= 0) return;
      if (state.count > trail.capacity) {
        gl.deleteBuffer(trail.buf);
        gl.deleteVertexArray(trail.vao);
        trail = instanced(Math.max(state.count, trail.capacity * 2));
        first = 0;
      }
      const data = new Float32Array((state.count - first) * 4);
      for (let k = first; k < state.count; k++) {
        const o = k * state.stride;
        data.set([state.samples[o + 1], state.samples[o + 2], state.samples[o + 3], trailRadius], 4 * (k - first));
      }
      gl.bindBuffer(gl.ARRAY_BUFFER, trail.buf);
      gl.bufferSubData(gl.ARRAY_BUFFER, first * 16, data);
      trail.count = state.count;
    }
    const quad = gl.createVertexArray();
    gl.bindVertexArray(quad);
    buffer(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1]));
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);

    const dof = header.joints.length;
    const slotBase = 7 + dof;
    // after the slots' poses, one flag per slot: 1 while its link's collision geometry intersects
    const collidingBase = slotBase + 12 * header.slots.length;
    const COLLIDING = [0.93, 0.11, 0.09, 1.0];
    return {
      trailAppend: trailWrite,
      trailReset() {
        trail.count = 0;
      },
      draw(viewproj, eyePos, k, frac) {
        const s = state.samples;
        const o0 = k * state.stride;
        const o1 = Math.min(k + 1, state.count - 1) * state.stride;
        const forward = norm(sub(camera.target, eyePos));
        const right = norm(cross(forward, [0, 0, 1]));
        const up = cross(right, forward);
        const key = norm([0.35 * right[0] + 0.8 * up[0] - 0.5 * forward[0], 0.35 * right[1] + 0.8 * up[1] - 0.5 * forward[1], 0.35 * right[2] + 0.8 * up[2] - 0.5 * forward[2]]);
        const fill = norm([-right[0] - 0.2 * forward[0], -right[1] - 0.2 * forward[1], 0.3]);
        gl.useProgram(meshProg.p);
        const u = meshProg.u;
        gl.uniformMatrix4fv(u.u_viewproj, false, viewproj);
        gl.uniform3fv(u.u_eye, eyePos);
        gl.uniform3fv(u.u_key, key);
        gl.uniform3fv(u.u_fill, fill);
        gl.uniform1i(u.u_instanced, 0);
        const pose = new Float32Array(12);
        for (const v of visuals) {
          let model = v.placement;
          let color = v.color;
          if (v.slot >= 0) {
            if (k < 0) continue;
            const a = o0 + slotBase + 12 * v.slot;
            const b = o1 + slotBase + 12 * v.slot;
            for (let i = 0; i < 12; i++) pose[i] = s[a + i] + (s[b + i] - s[a + i]) * frac;
            model = mul(poseMatrix(pose), v.placement);
            if (s[o0 + collidingBase + v.slot] > 0) color = COLLIDING;
          }
          gl.uniformMatrix4fv(u.u_model, false, model);
          gl.uniform3fv(u.u_min, v.mesh.min);
          gl.uniform3fv(u.u_ext, v.mesh.ext);
          gl.uniform4fv(u.u_color, color);
          gl.bindVertexArray(v.vao);
          gl.drawElements(gl.TRIANGLES, v.mesh.count, v.mesh.type, 0);
        }
        gl.uniform1i(u.u_instanced, 1);
        gl.uniform3fv(u.u_min, sphere.min);
        gl.uniform3fv(u.u_ext, sphere.ext);
        const spheres = (set, count, color) => {
          if (count <= 0) return;
          gl.uniform4fv(u.u_color, color);
          gl.bindVertexArray(set.vao);
          gl.drawElementsInstanced(gl.TRIANGLES, sphere.count, sphere.type, 0, count);
        };
        spheres(refSet, refSet.count, [0.42, 0.55, 1.0, 1.0]);
        if (k >= 0) {
          spheres(trail, Math.min(k + 1, trail.count), [1.0, 0.84, 0.3, 1.0]);
          const tx = s[o0 + 4];
          if (Number.isFinite(tx)) {
            gl.bindBuffer(gl.ARRAY_BUFFER, targetSet.buf);
            gl.bufferSubData(gl.ARRAY_BUFFER, 0, new Float32Array([tx, s[o0 + 5], s[o0 + 6], header.radii.target]));
            spheres(targetSet, 1, [1.0, 0.36, 0.45, 1.0]);
          }
        }
        // the ground last, blended over what is drawn, without writing depth
        gl.enable(gl.BLEND);
        gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
        gl.depthMask(false);
        gl.useProgram(groundProg.p);
        gl.uniformMatrix4fv(groundProg.u.u_viewproj, false, viewproj);
        gl.uniform2fv(groundProg.u.u_centre, [camera.target[0], camera.target[1]]);
        gl.bindVertexArray(quad);
        gl.drawArrays(gl.TRIANGLES, 0, 6);
        gl.depthMask(true);
        gl.disable(gl.BLEND);
        gl.bindVertexArray(null);
      },
    };
  }

  function setScene(bytes) {
    const { header, blob } = parseScene(bytes);
    state.scene = { header };
    if (state.stride !== header.stride) resetSamples(header.stride);
    $('title').textContent = `faze4 · ${header.name}` + (header.run.command ? ` · ${header.run.command}` : '');
    $('legend').classList.toggle('hidden', !header.board);
    homeCamera(header);
    if (gl) {
      gpu = makeGpu(header, blob);
      gpu.trailAppend(0);
    }
  }

  // ---------------------------------------------------------------- controls
  let drag = null;
  canvas.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.button === 1 || e.shiftKey };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x;
    const dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) {
      const f = norm(sub(camera.target, eye()));
      const r = norm(cross(f, [0, 0, 1]));
      const up = cross(r, f);
      const k = (camera.dist * 1.2) / canvas.clientHeight;
      for (let a = 0; a < 3; a++) camera.target[a] += (-dx * r[a] + dy * up[a]) * k;
    } else {
      camera.az -= dx * 0.008;
      camera.el = Math.max(-1.5, Math.min(1.5, camera.el + dy * 0.008));
    }
  });
  const endDrag = () => (drag = null);
  canvas.addEventListener('pointerup', endDrag);
  canvas.addEventListener('pointercancel', endDrag);
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    camera.dist = Math.max(0.1, Math.min(20, camera.dist * Math.exp(e.deltaY * 0.0012)));
  }, { passive: false });
  canvas.addEventListener('dblclick', () => {
    if (cameraHome) Object.assign(camera, JSON.parse(JSON.stringify(cameraHome)));
  });

  // ---------------------------------------------------------------- player
  const playButton = $('play');
  const scrub = $('scrub');
  const liveButton = $('live');
  liveButton.classList.toggle('hidden', !live);
  function setPlaying(p) {
    state.playing = p;
    if (p && !live && state.t >= lastTime()) state.t = 0;
  }
  playButton.addEventListener('click', () => {
    setPlaying(!state.playing);
    if (!state.playing) state.follow = false;
  });
  liveButton.addEventListener('click', () => {
    state.follow = true;
    state.playing = true;
  });
  scrub.addEventListener('input', () => {
    state.t = parseFloat(scrub.value);
    state.follow = false;
  });
  $('speed').addEventListener('change', (e) => (state.speed = parseFloat(e.target.value)));
  window.addEventListener('keydown', (e) => {
    if (e.code === 'Space' && e.target.tagName !== 'SELECT') {
      e.preventDefault();
      playButton.click();
    }
  });

  function summaryText(s) {
    if (!s) return '';
    const f = (v, d) => v.map((x) => (x == null ? '–' : x.toFixed(d))).join(' ');
    let text = `max tracking error (rad): ${f(s.max_tracking_error_rad, 4)}\nsaturation (%): ${f(s.saturation_pct, 2)}`;
    if (s.path_deviation_mm) text += `\npath deviation: max ${s.path_deviation_mm.max.toFixed(2)} mm, mean ${s.path_deviation_mm.mean.toFixed(2)} mm`;
    if (s.diverged) text += `\ndiverged at t = ${s.diverged.t.toFixed(4)} s, joint J${s.diverged.joint}`;
    const c = s.clearance;
    if (c && c.links) {
      const what = c.geometry === 'hull' ? 'convex hulls' : 'exact meshes';
      text += `\nself-clearance (${what}): ${c.links[0]}–${c.links[1]} ${(c.min_m * 1e3).toFixed(2)} mm at t = ${c.t.toFixed(2)} s`;
    }
    if (s.verdict && s.verdict.collides) text += `\n${s.verdict.reasons[0]}`;
    return text;
  }

  // ---------------------------------------------------------------- frame loop
  let last = performance.now();
  let reported = '';
  let drawn = '';
  function frame(now) {
    const wall = Math.min(0.1, (now - last) / 1000);
    last = now;
    if (state.follow) state.t = lastTime();
    else if (state.playing) {
      state.t += wall * state.speed;
      const end = live && !state.ended ? lastTime() : duration();
      if (state.t >= end) {
        state.t = end;
        if (!live || state.ended) state.playing = false;
      }
    }
    const dur = duration();
    scrub.max = String(dur || 1);
    scrub.value = String(state.t);
    playButton.innerHTML = state.playing ? '&#10074;&#10074;' : '&#9654;';
    liveButton.classList.toggle('on', state.follow);
    $('time').textContent = `${state.t.toFixed(2)} / ${dur.toFixed(2)} s`;

    let k = -1;
    let frac = 0;
    if (state.count) {
      k = sampleAt(state.t);
      if (k + 1 < state.count) {
        const t0 = sampleTime(k);
        const t1 = sampleTime(k + 1);
        frac = t1 > t0 ? Math.max(0, Math.min(1, (state.t - t0) / (t1 - t0))) : 0;
      }
    }
    let status = state.message;
    if (live && state.scene) {
      status = state.ended ? 'run finished' : state.connected ? 'live' : 'reconnecting…';
      if (!state.connected && state.ended) status = 'run finished (server closed)';
    }
    if (k >= 0 && state.scene) {
      const o = k * state.stride;
      const dof = state.scene.header.joints.length;
      const q = Array.from(state.samples.subarray(o + 7, o + 7 + dof), (x) => x.toFixed(3)).join(' ');
      const tool = [1, 2, 3].map((i) => state.samples[o + i].toFixed(3)).join(' ');
      status = (status ? status + '\n' : '') + `q (rad): ${q}\ntool (m): ${tool}`;
    }
    $('status').textContent = status;
    $('info').textContent = summaryText(state.summary);

    const dpr = window.devicePixelRatio || 1;
    const w = Math.round(canvas.clientWidth * dpr);
    const h = Math.round(canvas.clientHeight * dpr);
    // draw only when something on screen changed (paused views cost nothing)
    const look = [k, frac, state.count, w, h, camera.az, camera.el, camera.dist, ...camera.target, !!gpu].join(' ');
    if (gl && look !== drawn) {
      drawn = look;
      if (canvas.width !== w || canvas.height !== h) {
        canvas.width = w;
        canvas.height = h;
      }
      gl.viewport(0, 0, w, h);
      gl.clearColor(0, 0, 0, 0);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      gl.enable(gl.DEPTH_TEST);
      if (gpu) {
        const e = eye();
        const vp = mul(perspective(38 * deg, w / Math.max(1, h), 0.01, 50), lookAt(e, camera.target, [0, 0, 1]));
        gpu.draw(vp, e, k, frac);
      }
    }
    // for scripts and tests: what is on screen
    const shown = gpu && k >= 0 ? `t=${sampleTime(k).toFixed(3)}` : 'empty';
    if (shown !== reported) {
      reported = shown;
      document.title = `faze4 ${shown}`;
    }
    requestAnimationFrame(frame);
  }

  // ---------------------------------------------------------------- sources
  function fail(message) {
    state.message = message;
    $('status').textContent = message;
    console.error(message);
  }
  if (!gl) fail('WebGL2 is not available in this browser');

  if (!live) {
    try {
      setScene(base64Bytes($('faze4-scene').textContent));
      appendSamples(base64Bytes($('faze4-samples').textContent));
      if (state.t > lastTime()) state.t = lastTime();
    } catch (e) {
      fail('cannot read the embedded run: ' + e.message);
    }
  } else {
    let sceneRun = null;
    const source = new EventSource('events');
    source.addEventListener('run', (e) => {
      const info = JSON.parse(e.data);
      state.connected = true;
      state.ended = false;
      state.summary = null;
      resetSamples(info.stride);
      if (info.run !== sceneRun) {
        sceneRun = info.run;
        fetch('scene?run=' + info.run)
          .then((r) => {
            if (!r.ok) throw new Error('HTTP ' + r.status);
            return r.arrayBuffer();
          })
          .then((buf) => {
            if (sceneRun === info.run) setScene(new Uint8Array(buf));
          })
          .catch((err) => fail('cannot load the scene: ' + err.message));
      }
    });
    source.addEventListener('samples', (e) => appendSamples(base64Bytes(e.data)));
    source.addEventListener('end', (e) => {
      state.ended = true;
      state.summary = JSON.parse(e.data);
    });
    source.addEventListener('open', () => (state.connected = true));
    source.addEventListener('error', () => (state.connected = false));
  }
  requestAnimationFrame(frame);
})();
