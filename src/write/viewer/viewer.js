// karigami viewer: the build's lattice in 3-D, its assembly steps, a part
// finder and the cut sheets. Plain WebGL 1 and Canvas 2-D; no network.
(function () {
  "use strict";
  var D = JSON.parse(document.getElementById("karigami-data").textContent);
  var $ = function (id) { return document.getElementById(id); };

  // ---- The model -------------------------------------------------------
  var NC = D.cells.length / 7;
  var NS = D.strips.place.length / 5;
  var NV = D.points.length / 3 - NC;
  // Positions are written as differences from the point before, in mm to
  // 0.001: summed in whole micrometres, so they come back exactly.
  function positions(d) {
    var out = new Float64Array(d.length), at = [0, 0, 0];
    for (var k = 0; k < d.length; k++) { at[k % 3] += Math.round(d[k] * 1000); out[k] = at[k % 3] / 1000; }
    return out;
  }
  var NSTEPS = D.steps.length;
  var T = D.fab.thickness, W = D.fab.width, M = D.fab.end_margin;
  // Each cell's seven numbers are written as differences from the cell before.
  var CELLS = new Int32Array(D.cells.length);
  for (var k0 = 0; k0 < D.cells.length; k0++) CELLS[k0] = D.cells[k0] + (k0 >= 7 ? CELLS[k0 - 7] : 0);
  var cellOf = function (c, k) { return CELLS[7 * c + k]; };
  // The cells of each step, in index order (the guide's order).
  var cellsOf = D.steps.map(function () { return []; });
  for (var c0 = 0; c0 < NC; c0++) cellsOf[cellOf(c0, 6)].push(c0);
  // A strip's ID from its cell's row and column (runs of cells in one row
  // with consecutive columns) and its rod, A then B per cell.
  function pad(n, w) { var t = String(n); while (t.length < w) t = "0" + t; return t; }
  var cellName = [], runs = D.strips.ids;
  for (var q = 2; q < runs.length; q += 3) {
    for (var n = 0; n < runs[q + 2]; n++) cellName.push("R" + pad(runs[q], runs[0]) + "-C" + pad(runs[q + 1] + n, runs[1]) + "-");
  }
  var strips = [], atX = 0, atY = 0; // places: differences, in 0.0001 mm
  for (var i = 0; i < NS; i++) {
    var c = i >> 1, f = D.strips.place.slice(5 * i, 5 * i + 5), sh = D.strips.shapes[f[0]];
    var type = (i & 1) ? "B" : "A";
    atX += Math.round(f[2] * 1e4); atY += Math.round(f[3] * 1e4);
    strips.push({
      i: i, id: cellName[c] + type, type: type, length: sh[0], legs: [sh[1], sh[2]], sheet: f[1],
      x: atX / 1e4, y: atY / 1e4, rotated: !!f[4], cut: sh[3], part: sh[4] || null,
      cell: c, step: cellOf(c, 6), layer: cellOf(c, 4 + (i & 1)),
      start: (i & 1) ? cellOf(c, 1) : cellOf(c, 0), end: (i & 1) ? cellOf(c, 2) : cellOf(c, 3)
    });
  }
  var byId = {};
  strips.forEach(function (s) { byId[s.id] = s; });
  // Eyelets: one per scissor pivot, one per vertex joint closed in a step.
  var eyelets = [];
  for (var c = 0; c < NC; c++) {
    eyelets.push({ at: NV + c, cell: c, top: Math.max(cellOf(c, 4), cellOf(c, 5)), step: cellOf(c, 6) });
  }
  // Joints per step: [vertex, key, rods bottom to top], from the flat
  // list (vertex and rods written as differences).
  var keyOf = [], keyRuns = D.keys;
  for (var q2 = 0; q2 < keyRuns.length; q2 += 3) {
    // As the guide writes them: [row,column], or [k] on a helix.
    for (var n2 = 0; n2 < keyRuns[q2 + 2]; n2++) {
      keyOf.push(D.kind === "helix" ? "[" + (keyRuns[q2 + 1] + n2) + "]"
        : "[" + keyRuns[q2] + "," + (keyRuns[q2 + 1] + n2) + "]");
    }
  }
  var jointsOf = D.steps.map(function (st) {
    var out = [], J = st.joints, v = 0;
    for (var a = 0; a < J.length;) {
      v += J[a];
      var rods = [], r = 0;
      for (var b = 0; b < J[a + 1]; b++) { r += J[a + 2 + b]; rods.push(r); }
      a += 2 + rods.length;
      out.push([v, keyOf[v], rods]);
    }
    return out;
  });
  jointsOf.forEach(function (joints, k) {
    joints.forEach(function (j) {
      var top = 0;
      j[2].forEach(function (r) { top = Math.max(top, strips[r].layer); });
      eyelets.push({ at: j[0], cell: j[2][0] >> 1, top: top, step: k });
    });
  });

  // ---- State -------------------------------------------------------------
  var state = {
    step: NSTEPS,          // 1-based: strips of steps 1..step are built
    selected: -1,
    matches: [],           // strip indices found by the search
    matchSet: null,
    sheet: 1,
    theta: D.deploy ? D.deploy.theta_design : null,
    shape: "designed"
  };
  var designed = positions(D.points);
  var P = designed;        // the positions drawn now

  // ---- Small vector helpers ------------------------------------------------
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
  function mul(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function len(a) { return Math.sqrt(dot(a, a)); }
  function norm(a, fallback) { var l = len(a); return l > 1e-12 ? mul(a, 1 / l) : (fallback || [0, 0, 1]); }
  function pt(k) { return [P[3 * k], P[3 * k + 1], P[3 * k + 2]]; }
  function rotate(v, axis, ang) { // Rodrigues
    var c = Math.cos(ang), s = Math.sin(ang);
    return add(add(mul(v, c), mul(cross(axis, v), s)), mul(axis, dot(axis, v) * (1 - c)));
  }

  // ---- Geometry: ribbons of the strips' real width, stacked by layer --------
  var geo = null; // {pos, nrm, line (centre lines), eye, centre, radius}
  var stackSign = 1;
  (function () {
    // Layers go up towards the first view, so "A under B" reads as seen.
    var f = D.camera.forward, s = 0;
    for (var c = 0; c < NC; c++) s += dot(cellNormalRaw(c), f);
    stackSign = s > 0 ? -1 : 1;
  })();
  function cellNormalRaw(c) {
    var ul = pt(cellOf(c, 0)), ur = pt(cellOf(c, 1)), ll = pt(cellOf(c, 2));
    return norm(cross(sub(ur, ul), sub(ll, ul)));
  }
  function buildGeometry() {
    var pos = new Float32Array(NS * 36), nrm = new Float32Array(NS * 36);
    var line = new Float64Array(NS * 12); // start tip, pivot, end tip, start hole
    var cn = [];
    for (var c = 0; c < NC; c++) cn.push(mul(cellNormalRaw(c), stackSign));
    var BIG = Number.MAX_VALUE, lo = [BIG, BIG, BIG], hi = [-BIG, -BIG, -BIG];
    for (var k = 0; k < P.length / 3; k++) {
      for (var a = 0; a < 3; a++) { lo[a] = Math.min(lo[a], P[3 * k + a]); hi[a] = Math.max(hi[a], P[3 * k + a]); }
    }
    var centre = mul(add(lo, hi), 0.5);
    var radius = 0;
    for (k = 0; k < P.length / 3; k++) radius = Math.max(radius, len(sub(pt(k), centre)));
    radius += W;
    var v = 0;
    function quad(a, b, across, n) {
      var q = [sub(a, across), add(a, across), add(b, across), sub(a, across), add(b, across), sub(b, across)];
      for (var j = 0; j < 6; j++) {
        for (var x = 0; x < 3; x++) { pos[3 * v + x] = q[j][x] - centre[x]; nrm[3 * v + x] = n[x]; }
        v++;
      }
    }
    strips.forEach(function (s) {
      var n = cn[s.cell];
      var off = mul(n, (s.layer + 0.5) * T);
      var S = add(pt(s.start), off), Q = add(pt(NV + s.cell), off), E = add(pt(s.end), off);
      var d1 = norm(sub(Q, S), [1, 0, 0]), d2 = norm(sub(E, Q), d1);
      var s0 = sub(S, mul(d1, M)), e0 = add(E, mul(d2, M));
      quad(s0, Q, mul(norm(cross(n, d1), [0, 1, 0]), W / 2), n);
      quad(Q, e0, mul(norm(cross(n, d2), [0, 1, 0]), W / 2), n);
      var L = [s0, Q, e0, S];
      for (var j = 0; j < 4; j++) for (var x = 0; x < 3; x++) line[12 * s.i + 3 * j + x] = L[j][x] - centre[x];
    });
    var eye = new Float32Array(eyelets.length * 3);
    eyelets.forEach(function (e, i) {
      var p = add(pt(e.at), mul(cn[e.cell], (e.top + 1) * T + 0.05));
      for (var x = 0; x < 3; x++) eye[3 * i + x] = p[x] - centre[x];
    });
    geo = { pos: pos, nrm: nrm, line: line, eye: eye, centre: centre, radius: radius };
  }

  // ---- Colours ---------------------------------------------------------------
  var NEW = [214, 40, 40], SEL = [21, 101, 192], FOUND = [245, 170, 0], GHOST = [222, 220, 214];
  function stepColour(k) { // blue -> teal -> green -> olive: never the red of "new"
    var t = NSTEPS > 1 ? k / (NSTEPS - 1) : 0;
    var h = 215 - 150 * t, s = 0.55, l = 0.42 + 0.08 * Math.sin(Math.PI * t);
    var f = function (n) {
      var q = (n + h / 30) % 12, a = s * Math.min(l, 1 - l);
      return Math.round(255 * (l - a * Math.max(-1, Math.min(q - 3, 9 - q, 1))));
    };
    return [f(0), f(8), f(4)];
  }
  function mix(a, b, t) { return [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t]; }
  function built(s) { return s.step < state.step; }
  function shown(s) { return built(s) || s.i === state.selected || (state.matchSet !== null && state.matchSet[s.i]); }
  function stripColour(s) {
    if (s.i === state.selected) return SEL;
    if (state.matchSet !== null) return state.matchSet[s.i] ? FOUND : mix(stepColour(s.step), GHOST, 0.75);
    if (s.step === state.step - 1) return NEW;
    return mix(stepColour(s.step), GHOST, 0.2);
  }

  // ---- WebGL -------------------------------------------------------------
  var canvas = $("view");
  var gl = null;
  try {
    gl = canvas.getContext("webgl", { antialias: true, alpha: false }) ||
      canvas.getContext("experimental-webgl", { antialias: true, alpha: false });
  } catch (e) { gl = null; }
  var prog = null, eyeProg = null, buf = {};
  function shader(type, src) {
    var s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    return s;
  }
  function program(vs, fs) {
    var p = gl.createProgram();
    gl.attachShader(p, shader(gl.VERTEX_SHADER, vs));
    gl.attachShader(p, shader(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(p);
    return p;
  }
  if (gl) {
    prog = program(
      "attribute vec3 a_pos; attribute vec3 a_nrm; attribute vec4 a_col;" +
      "uniform mat4 u_mvp; uniform vec3 u_light; varying vec4 v_col;" +
      "void main(){ gl_Position = u_mvp * vec4(a_pos, 1.0);" +
      " float d = abs(dot(normalize(a_nrm), u_light));" +
      " v_col = vec4(a_col.rgb * (0.5 + 0.5 * d), a_col.a); }",
      "precision mediump float; varying vec4 v_col;" +
      "void main(){ if (v_col.a < 0.5) discard; gl_FragColor = vec4(v_col.rgb, 1.0); }");
    eyeProg = program(
      "attribute vec3 a_pos; attribute vec4 a_col; uniform mat4 u_mvp; uniform float u_size;" +
      "uniform vec3 u_eye; uniform float u_lift; varying vec4 v_col;" +
      // A ring is drawn facing the eye, lifted towards it by its radius so
      // that the strips it holds do not cut it.
      "void main(){ gl_Position = u_mvp * vec4(a_pos + normalize(u_eye - a_pos) * u_lift, 1.0);" +
      " gl_PointSize = a_col.a > 0.5 ? max(3.0, u_size / gl_Position.w) : 0.0; v_col = a_col; }",
      "precision mediump float; varying vec4 v_col; uniform float u_hole;" +
      "void main(){ if (v_col.a < 0.5) discard; vec2 q = gl_PointCoord * 2.0 - 1.0; float r = length(q);" +
      " if (r > 1.0 || r < u_hole) discard;" +
      " float rim = smoothstep(u_hole, 1.0, r); gl_FragColor = vec4(v_col.rgb * (1.15 - 0.45 * abs(rim - 0.5) * 2.0), 1.0); }");
    ["pos", "nrm", "col", "eye", "eyeCol"].forEach(function (k) { buf[k] = gl.createBuffer(); });
    canvas.addEventListener("webglcontextlost", function (e) { e.preventDefault(); });
  } else {
    $("nogl").hidden = false;
    $("nogl").textContent = "This browser cannot draw WebGL, so the 3-D view is off. The steps, the part finder and the cut sheets still work.";
  }
  function uploadGeometry() {
    if (!gl) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, buf.pos); gl.bufferData(gl.ARRAY_BUFFER, geo.pos, gl.DYNAMIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, buf.nrm); gl.bufferData(gl.ARRAY_BUFFER, geo.nrm, gl.DYNAMIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, buf.eye); gl.bufferData(gl.ARRAY_BUFFER, geo.eye, gl.DYNAMIC_DRAW);
  }
  var colours = new Uint8Array(NS * 48), eyeColours = new Uint8Array(eyelets.length * 4);
  function uploadColours() {
    strips.forEach(function (s) {
      var c = stripColour(s), a = shown(s) ? 255 : 0;
      for (var j = 0; j < 12; j++) {
        var o = 48 * s.i + 4 * j;
        colours[o] = c[0]; colours[o + 1] = c[1]; colours[o + 2] = c[2]; colours[o + 3] = a;
      }
    });
    eyelets.forEach(function (e, i) {
      var c = e.step === state.step - 1 ? [226, 176, 60] : [176, 141, 60];
      eyeColours.set([c[0], c[1], c[2], e.step < state.step ? 255 : 0], 4 * i);
    });
    if (!gl) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, buf.col); gl.bufferData(gl.ARRAY_BUFFER, colours, gl.DYNAMIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, buf.eyeCol); gl.bufferData(gl.ARRAY_BUFFER, eyeColours, gl.DYNAMIC_DRAW);
  }

  // ---- Camera: orbit about a target, trackball style ---------------------
  var FOV = 35 * Math.PI / 180;
  var cam = { target: [0, 0, 0], dist: 1, right: [1, 0, 0], up: [0, 1, 0], fwd: [0, 0, -1] };
  var axisSign = { x: 1, y: 1, z: 1 };
  function cssSize() { return [Math.max(1, canvas.clientWidth), Math.max(1, canvas.clientHeight)]; }
  // Back off until every point is in view (with a margin for the strips).
  function fitDistance() {
    var s = cssSize(), aspect = s[0] / s[1], t = Math.tan(FOV / 2), need = 0;
    var L = geo.line;
    for (var k = 0; k < L.length; k += 3) {
      var p = [L[k], L[k + 1], L[k + 2]];
      var x = Math.abs(dot(p, cam.right)) + W, y = Math.abs(dot(p, cam.up)) + W, z = dot(p, cam.fwd);
      need = Math.max(need, y / t - z, x / (t * aspect) - z);
    }
    return Math.max(need * 1.04, geo.radius * 0.1);
  }
  function setBasis(fwd, up) {
    cam.fwd = norm(fwd);
    cam.right = norm(cross(cam.fwd, up), [1, 0, 0]);
    cam.up = cross(cam.right, cam.fwd);
  }
  function resetView() {
    var c = D.camera;
    setBasis(c.forward, c.up);
    cam.target = [0, 0, 0];
    cam.dist = fitDistance();
    render();
  }
  function axisView(axis) {
    var s = axisSign[axis];
    axisSign[axis] = -s;
    var f = { x: [-s, 0, 0], y: [0, s, 0], z: [0, 0, -s] }[axis];
    setBasis(f, axis === "z" ? [0, 1, 0] : [0, 0, 1]);
    cam.target = [0, 0, 0];
    cam.dist = fitDistance();
    render();
  }
  function matrices() {
    var s = cssSize(), aspect = s[0] / s[1];
    var eye = sub(cam.target, mul(cam.fwd, cam.dist));
    var near = Math.max(cam.dist * 0.01, cam.dist - 2.5 * geo.radius), far = cam.dist + 2.5 * geo.radius;
    var f = 1 / Math.tan(FOV / 2);
    var r = cam.right, u = cam.up, b = mul(cam.fwd, -1);
    // view: rows right, up, back; then perspective (column-major for GL)
    var tx = -dot(r, eye), ty = -dot(u, eye), tz = -dot(b, eye);
    var A = (far + near) / (near - far), B = 2 * far * near / (near - far);
    var m = new Float32Array(16);
    var rows = [[f / aspect * r[0], f / aspect * r[1], f / aspect * r[2], f / aspect * tx],
      [f * u[0], f * u[1], f * u[2], f * ty],
      [A * b[0], A * b[1], A * b[2], A * tz + B],
      [-b[0], -b[1], -b[2], -tz]];
    for (var i = 0; i < 4; i++) for (var j = 0; j < 4; j++) m[4 * j + i] = rows[i][j];
    return { m: m, rows: rows, f: f, size: s };
  }
  // A model point to CSS pixels of the canvas and its depth.
  function project(mx, p) {
    var R = mx.rows, x = 0, y = 0, w = 0;
    for (var j = 0; j < 3; j++) { x += R[0][j] * p[j]; y += R[1][j] * p[j]; w += R[3][j] * p[j]; }
    x += R[0][3]; y += R[1][3]; w += R[3][3];
    return [(x / w + 1) / 2 * mx.size[0], (1 - y / w) / 2 * mx.size[1], w];
  }

  var pending = false;
  function render() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(draw);
  }
  function draw() {
    pending = false;
    if (!gl) return;
    var dpr = Math.min(window.devicePixelRatio || 1, 2);
    var s = cssSize();
    var w = Math.round(s[0] * dpr), h = Math.round(s[1] * dpr);
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.984, 0.98, 0.969, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    var mx = matrices();
    var light = norm(add(add(mul(cam.fwd, -1), mul(cam.up, 0.6)), mul(cam.right, 0.3)));
    gl.useProgram(prog);
    gl.uniformMatrix4fv(gl.getUniformLocation(prog, "u_mvp"), false, mx.m);
    gl.uniform3fv(gl.getUniformLocation(prog, "u_light"), light);
    attr(prog, "a_pos", buf.pos, 3, gl.FLOAT, false);
    attr(prog, "a_nrm", buf.nrm, 3, gl.FLOAT, false);
    attr(prog, "a_col", buf.col, 4, gl.UNSIGNED_BYTE, true);
    gl.drawArrays(gl.TRIANGLES, 0, NS * 12);
    off(prog, ["a_pos", "a_nrm", "a_col"]);
    gl.useProgram(eyeProg);
    gl.uniformMatrix4fv(gl.getUniformLocation(eyeProg, "u_mvp"), false, mx.m);
    gl.uniform1f(gl.getUniformLocation(eyeProg, "u_size"), D.fab.flange * mx.f * h / 2);
    gl.uniform1f(gl.getUniformLocation(eyeProg, "u_hole"), D.fab.hole / D.fab.flange);
    gl.uniform3fv(gl.getUniformLocation(eyeProg, "u_eye"), sub(cam.target, mul(cam.fwd, cam.dist)));
    gl.uniform1f(gl.getUniformLocation(eyeProg, "u_lift"), D.fab.flange * 0.6);
    attr(eyeProg, "a_pos", buf.eye, 3, gl.FLOAT, false);
    attr(eyeProg, "a_col", buf.eyeCol, 4, gl.UNSIGNED_BYTE, true);
    gl.drawArrays(gl.POINTS, 0, eyelets.length);
    off(eyeProg, ["a_pos", "a_col"]);
  }
  function attr(p, name, b, n, type, normalized) {
    var loc = gl.getAttribLocation(p, name);
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, n, type, normalized, 0, 0);
  }
  function off(p, names) { names.forEach(function (n) { gl.disableVertexAttribArray(gl.getAttribLocation(p, n)); }); }

  // ---- Picking: the nearest drawn strip under a point -----------------------
  function linePoint(i, j) { var o = 12 * i + 3 * j, L = geo.line; return [L[o], L[o + 1], L[o + 2]]; }
  // On a strip's ribbon, the nearest to the eye wins; failing that (a
  // finger is wider than a strip), the nearest on screen within `slop` px.
  function pick(x, y, slop) {
    var mx = matrices(), best = -1, bestDepth = Number.MAX_VALUE, near = -1, nearDist = Number.MAX_VALUE;
    strips.forEach(function (s) {
      if (!shown(s)) return;
      var a = project(mx, linePoint(s.i, 0)), q = project(mx, linePoint(s.i, 1)), e = project(mx, linePoint(s.i, 2));
      [[a, q], [q, e]].forEach(function (seg) {
        var p0 = seg[0], p1 = seg[1];
        if (p0[2] <= 0 || p1[2] <= 0) return;
        var dx = p1[0] - p0[0], dy = p1[1] - p0[1], l2 = dx * dx + dy * dy;
        var t = l2 > 0 ? Math.max(0, Math.min(1, ((x - p0[0]) * dx + (y - p0[1]) * dy) / l2)) : 0;
        var dist = Math.hypot(p0[0] + t * dx - x, p0[1] + t * dy - y);
        var depth = p0[2] + t * (p1[2] - p0[2]);
        var halfPx = Math.max(W / 2 * mx.f * mx.size[1] / 2 / depth, 0.5);
        if (dist <= halfPx) {
          if (depth < bestDepth) { best = s.i; bestDepth = depth; }
        } else if (dist - halfPx <= slop && dist - halfPx < nearDist) {
          near = s.i; nearDist = dist - halfPx;
        }
      });
    });
    return best >= 0 ? best : near;
  }
  function clientOf(p) {
    var r = canvas.getBoundingClientRect();
    return [r.left + p[0], r.top + p[1]];
  }

  // ---- Pointer: orbit, pan, zoom, tap ------------------------------------------
  var pointers = {}, gesture = null;
  function local(e) { var r = canvas.getBoundingClientRect(); return [e.clientX - r.left, e.clientY - r.top]; }
  canvas.addEventListener("pointerdown", function (e) {
    canvas.setPointerCapture && canvas.setPointerCapture(e.pointerId);
    pointers[e.pointerId] = local(e);
    var ids = Object.keys(pointers);
    gesture = { moved: 0, t: Date.now(), pan: e.button === 2 || e.shiftKey, many: ids.length > 1 || (gesture && gesture.many), start: local(e), touch: e.pointerType === "touch" };
    canvas.classList.add("dragging");
    hideTip();
  });
  canvas.addEventListener("pointermove", function (e) {
    var p = local(e);
    if (!pointers[e.pointerId]) { if (e.pointerType === "mouse") hover(p); return; }
    var ids = Object.keys(pointers);
    var old = pointers[e.pointerId];
    var dx = p[0] - old[0], dy = p[1] - old[1];
    if (ids.length === 2) {
      var other = pointers[ids[0] == e.pointerId ? ids[1] : ids[0]];
      var before = Math.hypot(old[0] - other[0], old[1] - other[1]);
      var after = Math.hypot(p[0] - other[0], p[1] - other[1]);
      if (before > 0 && after > 0) cam.dist *= before / after;
      panBy(dx / 2, dy / 2);
    } else if (gesture && gesture.pan) {
      panBy(dx, dy);
    } else {
      orbit(dx, dy);
    }
    pointers[e.pointerId] = p;
    if (gesture) gesture.moved += Math.abs(dx) + Math.abs(dy);
    render();
  });
  function endPointer(e) {
    if (!pointers[e.pointerId]) return;
    delete pointers[e.pointerId];
    if (Object.keys(pointers).length === 0) {
      canvas.classList.remove("dragging");
      if (gesture && !gesture.many && gesture.moved < 6 && e.type === "pointerup") {
        var p = local(e);
        var hit = pick(p[0], p[1], gesture.touch ? 10 : 3);
        select(hit, "view");
        if (hit >= 0 && gesture.touch) showTip(strips[hit].id, p);
      }
      gesture = null;
    }
  }
  canvas.addEventListener("pointerup", endPointer);
  canvas.addEventListener("pointercancel", endPointer);
  canvas.addEventListener("pointerleave", function (e) { if (e.pointerType === "mouse" && !pointers[e.pointerId]) hideTip(); });
  canvas.addEventListener("contextmenu", function (e) { e.preventDefault(); });
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault();
    cam.dist *= Math.exp(Math.max(-1, Math.min(1, e.deltaY * (e.deltaMode === 1 ? 0.05 : 0.0015))));
    render();
  }, { passive: false });
  function orbit(dx, dy) {
    var a = dx * 0.008, b = dy * 0.008;
    var f = rotate(cam.fwd, cam.up, a), r = rotate(cam.right, cam.up, a);
    cam.fwd = norm(rotate(f, r, b));
    cam.up = norm(rotate(cam.up, r, b));
    cam.right = norm(cross(cam.fwd, cam.up));
    cam.up = cross(cam.right, cam.fwd);
  }
  function panBy(dx, dy) {
    var mmPerPx = 2 * cam.dist * Math.tan(FOV / 2) / cssSize()[1];
    cam.target = add(cam.target, add(mul(cam.right, -dx * mmPerPx), mul(cam.up, dy * mmPerPx)));
  }
  var tip = $("tip");
  function showTip(text, p) {
    tip.textContent = text;
    tip.hidden = false;
    tip.style.left = Math.min(p[0] + 12, canvas.clientWidth - tip.offsetWidth - 4) + "px";
    tip.style.top = Math.max(p[1] - 28, 2) + "px";
  }
  function hideTip() { tip.hidden = true; }
  var hoverAt = null;
  function hover(p) {
    if (hoverAt === null) requestAnimationFrame(function () {
      var q = hoverAt; hoverAt = null;
      var hit = pick(q[0], q[1], 2);
      if (hit >= 0) showTip(strips[hit].id + "  (" + typeName(strips[hit]) + ")", q); else hideTip();
    });
    hoverAt = p;
  }

  // ---- Steps -------------------------------------------------------------
  var stepInput = $("step");
  stepInput.max = String(NSTEPS);
  function idLink(i) {
    var a = document.createElement("a");
    a.className = "id";
    a.textContent = strips[i].id;
    a.href = "#" + strips[i].id;
    a.addEventListener("click", function (e) { e.preventDefault(); select(i, "text"); });
    return a;
  }
  function setStep(k) {
    k = Math.max(1, Math.min(NSTEPS, k | 0));
    state.step = k;
    stepInput.value = String(k);
    var st = D.steps[k - 1];
    $("step-head").textContent = "Step " + k + " of " + NSTEPS + " - " + st.title;
    var box = $("step-text");
    box.textContent = "";
    var p = document.createElement("p");
    p.textContent = D.say.pair;
    box.appendChild(p);
    var ul = document.createElement("ul");
    cellsOf[k - 1].forEach(function (c) {
      var li = document.createElement("li");
      li.appendChild(idLink(2 * c));
      li.appendChild(document.createTextNode(" + "));
      li.appendChild(idLink(2 * c + 1));
      ul.appendChild(li);
    });
    box.appendChild(ul);
    p = document.createElement("p");
    p.textContent = jointsOf[k - 1].length ? D.say.close : D.say.none;
    box.appendChild(p);
    if (jointsOf[k - 1].length) {
      ul = document.createElement("ul");
      jointsOf[k - 1].forEach(function (j) {
        var li = document.createElement("li");
        li.appendChild(document.createTextNode(j[1] + "  "));
        j[2].forEach(function (r, n) {
          if (n) li.appendChild(document.createTextNode(" / "));
          li.appendChild(idLink(r));
        });
        ul.appendChild(li);
      });
      box.appendChild(ul);
    }
    p = document.createElement("p");
    p.className = "eyelets";
    p.textContent = st.eyelets;
    box.appendChild(p);
    refresh();
  }
  stepInput.addEventListener("input", function () { setStep(+stepInput.value); });
  $("prev").addEventListener("click", function () { setStep(state.step - 1); });
  $("next").addEventListener("click", function () { setStep(state.step + 1); });
  document.addEventListener("keydown", function (e) {
    var t = e.target;
    if (t && (t.tagName === "INPUT" || t.tagName === "TEXTAREA")) return;
    if (e.key === "ArrowLeft") { setStep(state.step - 1); e.preventDefault(); }
    else if (e.key === "ArrowRight") { setStep(state.step + 1); e.preventDefault(); }
    else if (e.key === "Escape") { select(-1, "key"); }
  });

  // ---- Selection and the part finder ------------------------------------
  function typeName(s) {
    return "rod " + s.type + (s.part ? ", part " + s.part : "");
  }
  function select(i, from) {
    state.selected = i;
    var info = $("info");
    info.textContent = "";
    if (i >= 0) {
      var s = strips[i];
      var head = document.createElement("div");
      head.className = "sel";
      head.textContent = s.id;
      info.appendChild(head);
      var t = document.createElement("table");
      var h0 = M, h1 = M + s.legs[0], h2 = M + s.legs[0] + s.legs[1];
      var later = s.step < state.step ? "" : " (not built yet at this step)";
      [["Type", typeName(s) + (s.type === "A" ? ": upper left to lower right" : ": upper right to lower left")],
        ["Step", (s.step + 1) + " of " + NSTEPS + later],
        ["Length", fmt(s.length) + " mm tip to tip"],
        ["Hole pitches", fmt(s.legs[0]) + " + " + fmt(s.legs[1]) + " mm"],
        ["Holes at", fmt(h0) + ", " + fmt(h1) + ", " + fmt(h2) + " mm from the start tip"],
        ["Stacking layer", String(s.layer)],
        ["Sheet", s.sheet + " of " + D.sheets],
        ["Position", "x " + fmt(s.x, 0) + ", y " + fmt(s.y, 0) + " mm" + (s.rotated ? ", upright" : "")]
      ].forEach(function (r) {
        var tr = document.createElement("tr"), th = document.createElement("th"), td = document.createElement("td");
        th.textContent = r[0]; td.textContent = r[1];
        tr.appendChild(th); tr.appendChild(td); t.appendChild(tr);
      });
      info.appendChild(t);
      var go = document.createElement("button");
      go.type = "button";
      go.textContent = "Centre the view on it";
      go.addEventListener("click", function () { focusOn(i); });
      info.appendChild(go);
      state.sheet = s.sheet;
      if (from === "view" && info.scrollIntoView) info.scrollIntoView({ block: "nearest" });
    }
    refresh();
  }
  // Turn about and close in on a strip, keeping the direction of view.
  function focusOn(i) {
    cam.target = mul(add(linePoint(i, 0), linePoint(i, 2)), 0.5);
    var t = Math.tan(FOV / 2), size = Math.max(strips[i].length, 4 * W) * 2.5;
    cam.dist = Math.min(cam.dist, size / t);
    render();
  }
  function fmt(x, d) { return x.toFixed(d === undefined ? 1 : d); }
  var search = $("search");
  // A term that is a part type code finds that type (what a maker reads on
  // a strip engraved with its code); any other term, IDs containing it.
  var partCodes = {};
  strips.forEach(function (s) { if (s.part) partCodes[s.part.toUpperCase()] = true; });
  function find(q) {
    var terms = q.trim().toUpperCase().split(/[\s,;]+/).filter(function (t) { return t.length; });
    if (!terms.length) return null;
    var out = [];
    strips.forEach(function (s) {
      var id = s.id.toUpperCase();
      for (var k = 0; k < terms.length; k++) {
        var t = terms[k].replace(/^[<]/, "");
        var hit = partCodes[t] ? (s.part && s.part.toUpperCase() === t) : id.indexOf(t) >= 0;
        if (hit) { out.push(s.i); return; }
      }
    });
    return out;
  }
  function runSearch() {
    var found = find(search.value);
    var box = $("matches");
    box.textContent = "";
    if (found === null) { state.matches = []; state.matchSet = null; refresh(); return; }
    state.matches = found;
    state.matchSet = new Uint8Array(NS);
    found.forEach(function (i) { state.matchSet[i] = 1; });
    box.appendChild(document.createTextNode(found.length === 1 ? "1 strip matches: " : found.length + " strips match" + (found.length ? ": " : ".")));
    found.slice(0, 60).forEach(function (i) { box.appendChild(idLink(i)); box.appendChild(document.createTextNode(" ")); });
    if (found.length > 60) box.appendChild(document.createTextNode(" ..."));
    if (found.length) state.sheet = strips[found[0]].sheet;
    refresh();
  }
  search.addEventListener("input", runSearch);
  search.addEventListener("keydown", function (e) {
    if (e.key === "Enter" && state.matches.length) select(state.matches[0], "search");
    if (e.key === "Escape") { search.value = ""; runSearch(); }
  });

  // ---- Cut sheets ---------------------------------------------------------------
  var sheetCanvas = $("sheet-view");
  var sheetMarked = []; // strips highlighted on the sheet shown
  function sheetScale() {
    var w = Math.max(1, sheetCanvas.clientWidth);
    return w / D.fab.sheet_width;
  }
  function stripBox(s) {
    var l = s.cut, w = D.fab.part_width;
    return s.rotated ? [s.x, s.y, w, l] : [s.x, s.y, l, w];
  }
  function drawSheet() {
    var dpr = Math.min(window.devicePixelRatio || 1, 2);
    var k = sheetScale();
    var cw = Math.max(1, sheetCanvas.clientWidth), ch = Math.round(D.fab.sheet_height * k);
    sheetCanvas.style.height = ch + "px";
    sheetCanvas.width = Math.round(cw * dpr); sheetCanvas.height = Math.round(ch * dpr);
    var g = sheetCanvas.getContext("2d");
    g.setTransform(dpr * k, 0, 0, dpr * k, 0, 0);
    g.fillStyle = "#fffdf6";
    g.fillRect(0, 0, D.fab.sheet_width, D.fab.sheet_height);
    $("sheet-name").textContent = "Sheet " + state.sheet + " of " + D.sheets + " (" + D.fab.sheet + ")";
    var fontPx = 11 / k;
    g.font = fontPx + "px ui-monospace, Menlo, Consolas, monospace";
    g.textAlign = "center";
    g.textBaseline = "middle";
    sheetMarked = [];
    strips.forEach(function (s) {
      if (s.sheet !== state.sheet) return;
      var b = stripBox(s), r = D.fab.part_width / 2;
      var colour = "#d9d7d0", ink = "#6d6b64";
      if (s.i === state.selected) { colour = "rgb(" + SEL + ")"; ink = "#fff"; sheetMarked.push(s.i); }
      else if (state.matchSet !== null && state.matchSet[s.i]) { colour = "rgb(" + FOUND + ")"; ink = "#1d1d1b"; sheetMarked.push(s.i); }
      else if (s.step === state.step - 1) { colour = "#f0b4b4"; ink = "#8a1c1c"; }
      g.fillStyle = colour;
      g.beginPath();
      if (g.roundRect) g.roundRect(b[0], b[1], b[2], b[3], r); else g.rect(b[0], b[1], b[2], b[3]);
      g.fill();
      var long = s.rotated ? b[3] : b[2];
      if (g.measureText(s.id).width < long * 0.8 && fontPx <= D.fab.part_width * 1.2) {
        g.fillStyle = ink;
        g.save();
        g.translate(b[0] + b[2] / 2, b[1] + b[3] / 2);
        if (s.rotated) g.rotate(-Math.PI / 2);
        g.fillText(s.id, 0, 0);
        g.restore();
      }
    });
    g.strokeStyle = "#2b2b28";
    g.lineWidth = 1 / k;
    g.strokeRect(0, 0, D.fab.sheet_width, D.fab.sheet_height);
  }
  sheetCanvas.addEventListener("click", function (e) {
    var r = sheetCanvas.getBoundingClientRect(), k = sheetScale();
    var x = (e.clientX - r.left) / k, y = (e.clientY - r.top) / k, hit = -1;
    strips.forEach(function (s) {
      if (s.sheet !== state.sheet) return;
      var b = stripBox(s);
      if (x >= b[0] && x <= b[0] + b[2] && y >= b[1] && y <= b[1] + b[3]) hit = s.i;
    });
    select(hit, "sheet");
  });
  $("sheet-prev").addEventListener("click", function () { state.sheet = Math.max(1, state.sheet - 1); drawSheet(); });
  $("sheet-next").addEventListener("click", function () { state.sheet = Math.min(D.sheets, state.sheet + 1); drawSheet(); });

  // ---- Deployment: C(theta) placed cell by cell (planar true mechanisms) ----
  function fit2(pairs) { // least-squares rotation + translation, as the check does
    var n = Math.max(pairs.length, 1), cp = [0, 0], cq = [0, 0];
    pairs.forEach(function (p) { cp[0] += p[0][0]; cp[1] += p[0][1]; cq[0] += p[1][0]; cq[1] += p[1][1]; });
    cp = [cp[0] / n, cp[1] / n]; cq = [cq[0] / n, cq[1] / n];
    var s = 0, c = 0;
    pairs.forEach(function (p) {
      var a = [p[0][0] - cp[0], p[0][1] - cp[1]], b = [p[1][0] - cq[0], p[1][1] - cq[1]];
      c += a[0] * b[0] + a[1] * b[1]; s += a[0] * b[1] - a[1] * b[0];
    });
    var ang = pairs.length < 2 ? 0 : Math.atan2(s, c), co = Math.cos(ang), si = Math.sin(ang);
    return function (p) { var x = p[0] - cp[0], y = p[1] - cp[1]; return [cq[0] + co * x - si * y, cq[1] + si * x + co * y]; };
  }
  function cellLocal(c, theta) {
    var d = D.deploy.cells, o = 7 * c;
    var cphi = Math.max(-1, Math.min(1, d[o] + d[o + 1] * Math.cos(theta)));
    var phi = Math.acos(cphi), side = d[o + 6];
    var bx = Math.cos(phi), by = side * Math.sin(phi);
    return [[d[o + 2], 0], [bx * d[o + 5], by * d[o + 5]], [-bx * d[o + 3], -by * d[o + 3]], [-d[o + 4], 0]]; // UL UR LL LR
  }
  var deployMisfit = 0;
  function deployedShape(theta) {
    var out = new Float64Array(designed.length), placed = new Uint8Array(NV);
    var first = cellLocal(0, D.deploy.theta_design), pairs0 = [];
    for (var k = 0; k < 4; k++) {
      var v = cellOf(0, k);
      pairs0.push([first[k], [designed[3 * v], designed[3 * v + 1]]]);
    }
    var frame0 = fit2(pairs0);
    deployMisfit = 0;
    for (var c = 0; c < NC; c++) {
      var loc = cellLocal(c, theta), ids = [cellOf(c, 0), cellOf(c, 1), cellOf(c, 2), cellOf(c, 3)];
      var f = frame0;
      if (c > 0) {
        var pairs = [];
        ids.forEach(function (v, k) { if (placed[v]) pairs.push([loc[k], [out[3 * v], out[3 * v + 1]]]); });
        f = fit2(pairs);
      }
      ids.forEach(function (v, k) {
        var q = f(loc[k]);
        if (placed[v]) deployMisfit = Math.max(deployMisfit, Math.hypot(q[0] - out[3 * v], q[1] - out[3 * v + 1]));
        else { out[3 * v] = q[0]; out[3 * v + 1] = q[1]; placed[v] = 1; }
      });
      var pv = f([0, 0]);
      out[3 * (NV + c)] = pv[0]; out[3 * (NV + c) + 1] = pv[1];
    }
    return out;
  }
  var thetaInput = $("theta");
  function thetaText() {
    var d = D.deploy, deg = function (x) { return (x * 180 / Math.PI).toFixed(1) + "\u00b0"; };
    $("theta-out").textContent = deg(state.theta) + " (designed " + deg(d.theta_design) + ", 0 to " + deg(d.theta_max) + ")";
  }
  if (D.deploy) {
    $("deploy").hidden = false;
    thetaInput.value = String(Math.round(1000 * D.deploy.theta_design / D.deploy.theta_max));
    $("deploy-note").textContent = "A true mechanism: every cell opens by C(theta) of the check, strips straight. Slide to open or fold it.";
    thetaInput.addEventListener("input", function () {
      state.theta = D.deploy.theta_max * (+thetaInput.value) / 1000;
      P = deployedShape(state.theta);
      thetaText();
      rebuild();
    });
    thetaText();
  }
  $("verdict").textContent = "Deployment: " + D.verdict + "." +
    (D.extrinsic ? "" : " Rows grown on rebuilt fronts are drawn placed on the row above, shared vertices halfway where the strips bend.");
  if (D.simulated) {
    var simulatedShape = positions(D.simulated);
    $("shape-choice").hidden = false;
    document.querySelectorAll("input[name=shape]").forEach(function (r) {
      r.addEventListener("change", function () {
        if (!r.checked) return;
        state.shape = r.value;
        P = r.value === "simulated" ? simulatedShape : designed;
        rebuild();
      });
    });
  }

  // ---- Glue -------------------------------------------------------------------
  function refresh() { uploadColours(); drawSheet(); render(); }
  function rebuild() { buildGeometry(); uploadGeometry(); refresh(); }
  $("view-reset").addEventListener("click", resetView);
  document.querySelectorAll("#views button[data-axis]").forEach(function (b) {
    b.addEventListener("click", function () { axisView(b.getAttribute("data-axis")); });
  });
  $("panel-toggle").addEventListener("click", function () {
    var app = $("app"), hide = !app.classList.contains("nopanel");
    app.classList.toggle("nopanel", hide);
    $("panel-toggle").setAttribute("aria-expanded", String(!hide));
    render();
  });
  var eyeletCount = D.steps.length ? D.steps.reduce(function (n, s, k) { return n + cellsOf[k].length + jointsOf[k].length; }, 0) : 0;
  $("facts").textContent = NC + " cells \u00b7 " + NS + " strips \u00b7 " + eyeletCount + " eyelets \u00b7 " +
    D.sheets + (D.sheets === 1 ? " sheet" : " sheets") + " \u00b7 " + D.fab.material + " " + D.fab.thickness + " x " + D.fab.width + " mm";
  buildGeometry();
  uploadGeometry();
  if (window.ResizeObserver) new ResizeObserver(function () { render(); drawSheet(); }).observe(canvas);
  window.addEventListener("resize", function () { render(); drawSheet(); });
  resetView();
  setStep(NSTEPS);

  // ---- Read-only hook for tests and scripts ----------------------------------
  function ids(list) { return list.map(function (i) { return strips[i].id; }); }
  function stripIndex(id) { var s = byId[id]; if (!s) throw new Error("no strip " + id); return s.i; }
  var ready = false;
  requestAnimationFrame(function () { requestAnimationFrame(function () { ready = true; }); });
  window.karigami = Object.freeze({
    get ready() { return ready; },
    version: D.version,
    webgl: !!gl,
    steps: function () { return NSTEPS; },
    step: function () { return state.step; },
    visibleStrips: function () { return ids(strips.filter(shown).map(function (s) { return s.i; })); },
    stripsOfSteps: function (k) { return ids(strips.filter(function (s) { return s.step < k; }).map(function (s) { return s.i; })); },
    selected: function () { return state.selected >= 0 ? strips[state.selected].id : null; },
    highlighted: function () { return ids(state.matches); },
    sheet: function () { return state.sheet; },
    // Strips highlighted (selected or found) on the sheet shown.
    sheetHighlighted: function () { return ids(sheetMarked); },
    // Client (CSS) pixels of the middle of a strip's first leg, halfway
    // between its start eyelet and its scissor pivot, where no other strip crosses it.
    // Client pixels where a click selects the strip: the first point along
    // its centre line not covered by a nearer strip (else its first leg).
    pickPoint: function (id) {
      var i = stripIndex(id), mx = matrices(), r = canvas.getBoundingClientRect();
      var fallback = clientOf(project(mx, mul(add(linePoint(i, 3), linePoint(i, 1)), 0.5)));
      for (var k = 1; k < 20; k++) {
        var t = k / 20, a = linePoint(i, t < 0.5 ? 0 : 1), b = linePoint(i, t < 0.5 ? 1 : 2);
        var u = t < 0.5 ? 2 * t : 2 * t - 1;
        var c = clientOf(project(mx, add(mul(a, 1 - u), mul(b, u))));
        if (pick(c[0] - r.left, c[1] - r.top, 0) === i) return c;
      }
      return fallback;
    },
    // Client pixels of the projected centre of a strip (halfway along it).
    centre: function (id) {
      var i = stripIndex(id), mx = matrices();
      return clientOf(project(mx, mul(add(linePoint(i, 0), linePoint(i, 2)), 0.5)));
    },
    // The strip a click at client pixels (x, y) would select, or null.
    stripAt: function (x, y) {
      var r = canvas.getBoundingClientRect(), hit = pick(x - r.left, y - r.top, 3);
      return hit >= 0 ? strips[hit].id : null;
    },
    // The shape C(theta) places at an opening (degrees), without showing
    // it: its largest distance from the designed shape and its misfit (mm).
    shapeAt: function (deg) {
      if (!D.deploy) return null;
      var q = deployedShape(deg * Math.PI / 180), far = 0;
      for (var k = 0; k < q.length; k++) far = Math.max(far, Math.abs(q[k] - designed[k]));
      return { fromDesign: far, misfit: deployMisfit };
    },
    // How far the camera is from the point it turns about (mm).
    viewDistance: function () { return cam.dist; },
    // The direction the camera looks, in the lattice's coordinates.
    viewDirection: function () { return cam.fwd.slice(); },
    theta: function () { return state.theta === null ? null : state.theta * 180 / Math.PI; },
    // How well the drawn deployed state keeps the strips: the largest change
    // of a hole pitch and the largest misfit of a shared vertex (mm), and the
    // largest distance from the designed shape.
    deployCheck: function () {
      var legErr = 0, fromDesign = 0;
      strips.forEach(function (s) {
        var q = pt(NV + s.cell);
        legErr = Math.max(legErr, Math.abs(len(sub(pt(s.start), q)) - s.legs[0]), Math.abs(len(sub(pt(s.end), q)) - s.legs[1]));
      });
      for (var k = 0; k < P.length; k += 3) {
        fromDesign = Math.max(fromDesign, Math.hypot(P[k] - designed[k], P[k + 1] - designed[k + 1], P[k + 2] - designed[k + 2]));
      }
      return { pitchError: legErr, misfit: D.deploy ? deployMisfit : 0, fromDesign: fromDesign };
    }
  });
})();
