// SPDX-License-Identifier: MIT
// graphslam view: the WebGL renderer (WebGL 1, lines and points with per-vertex colours). A
// lines layer with more segments than the level-of-detail bound also gets a subsample
// (every k-th segment), drawn while the view moves.
(function () {
  const VS =
    "attribute vec3 p; attribute vec4 c; uniform mat4 m; uniform float s; varying vec4 v;" +
    "void main(){ gl_Position = m * vec4(p, 1.0); gl_PointSize = s; v = c; }";
  const FS = "precision mediump float; varying vec4 v; void main(){ gl_FragColor = v; }";

  function compile(gl, type, text) {
    const sh = gl.createShader(type);
    gl.shaderSource(sh, text);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    return sh;
  }

  /** The renderer on `canvas`, or null when WebGL is not available. */
  GV.GLRenderer = function (canvas) {
    const gl = canvas.getContext("webgl", { antialias: false, preserveDrawingBuffer: true });
    if (!gl) return null;
    const prog = gl.createProgram();
    gl.attachShader(prog, compile(gl, gl.VERTEX_SHADER, VS));
    gl.attachShader(prog, compile(gl, gl.FRAGMENT_SHADER, FS));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    this.gl = gl;
    this.prog = prog;
    this.loc = {
      p: gl.getAttribLocation(prog, "p"),
      c: gl.getAttribLocation(prog, "c"),
      m: gl.getUniformLocation(prog, "m"),
      s: gl.getUniformLocation(prog, "s"),
    };
    this.buffers = [];
    this.kind = "webgl";
  };

  function upload(gl, pos, col, count) {
    const pb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, pb);
    gl.bufferData(gl.ARRAY_BUFFER, pos.subarray(0, 3 * count), gl.STATIC_DRAW);
    const cb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, cb);
    gl.bufferData(gl.ARRAY_BUFFER, col.subarray(0, 4 * count), gl.STATIC_DRAW);
    return { pb: pb, cb: cb, count: count };
  }

  /** Every `stride`-th segment of a lines layer. */
  function subsample(layer, stride) {
    const segs = Math.ceil(layer.count / 2 / stride);
    const pos = new Float32Array(6 * segs), col = new Uint8Array(8 * segs);
    let n = 0;
    for (let s = 0; 2 * s < layer.count; s += stride, n++) {
      pos.set(layer.pos.subarray(6 * s, 6 * s + 6), 6 * n);
      col.set(layer.col.subarray(8 * s, 8 * s + 8), 8 * n);
    }
    return { pos: pos, col: col, count: 2 * n };
  }

  function release(gl, x) {
    if (!x) return;
    gl.deleteBuffer(x.pb);
    gl.deleteBuffer(x.cb);
  }

  GV.GLRenderer.prototype.setLayers = function (layers, lodEdges) {
    const gl = this.gl;
    for (const b of this.buffers) {
      release(gl, b.full);
      release(gl, b.lod);
    }
    this.layers = layers;
    this.buffers = layers.map((l) => ({ mode: l.mode, size: l.size, full: upload(gl, l.pos, l.col, l.count) }));
    this.setLod(lodEdges);
  };

  /** Subsamples of the lines layers with more than `lodEdges` segments, drawn while moving. */
  GV.GLRenderer.prototype.setLod = function (lodEdges) {
    const gl = this.gl;
    this.layers.forEach((l, i) => {
      const b = this.buffers[i];
      release(gl, b.lod);
      b.lod = null;
      if (l.mode === "lines" && l.count / 2 > lodEdges) {
        const s = subsample(l, Math.ceil(l.count / 2 / lodEdges));
        b.lod = upload(gl, s.pos, s.col, s.count);
      }
    });
  };

  /** Waits until the GPU has drawn everything asked so far (a one-pixel read-back): the
   * honest end of a frame for timing. */
  GV.GLRenderer.prototype.sync = function () {
    const px = new Uint8Array(4);
    this.gl.readPixels(0, 0, 1, 1, this.gl.RGBA, this.gl.UNSIGNED_BYTE, px);
  };

  /** Draws the layers under the world-to-clip matrix `m`; `moving` draws the subsamples.
   * Returns the number of segments and points drawn. */
  GV.GLRenderer.prototype.draw = function (m, w, h, moving) {
    const gl = this.gl;
    gl.viewport(0, 0, w, h);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(this.prog);
    gl.uniformMatrix4fv(this.loc.m, false, m);
    let drawn = 0;
    for (const b of this.buffers) {
      const x = moving && b.lod ? b.lod : b.full;
      if (!x.count) continue;
      gl.bindBuffer(gl.ARRAY_BUFFER, x.pb);
      gl.enableVertexAttribArray(this.loc.p);
      gl.vertexAttribPointer(this.loc.p, 3, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, x.cb);
      gl.enableVertexAttribArray(this.loc.c);
      gl.vertexAttribPointer(this.loc.c, 4, gl.UNSIGNED_BYTE, true, 0, 0);
      gl.uniform1f(this.loc.s, b.size * (window.devicePixelRatio || 1));
      gl.drawArrays(b.mode === "lines" ? gl.LINES : gl.POINTS, 0, x.count);
      drawn += b.mode === "lines" ? x.count / 2 : x.count;
    }
    return drawn;
  };
})();
