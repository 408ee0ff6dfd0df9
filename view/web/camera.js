// SPDX-License-Identifier: MIT
// graphslam view: the camera. 2D graphs pan and zoom (orthographic); 3D graphs orbit around
// a target (perspective). matrix() maps world to clip space (column-major, WebGL's layout);
// project() maps world to canvas pixels (for picking and the canvas fallback).
(function () {
  function multiply(a, b) {
    const r = new Float32Array(16);
    for (let c = 0; c < 4; c++) {
      for (let rr = 0; rr < 4; rr++) {
        let s = 0;
        for (let k = 0; k < 4; k++) s += a[k * 4 + rr] * b[c * 4 + k];
        r[c * 4 + rr] = s;
      }
    }
    return r;
  }

  GV.Camera = function (dim, box) {
    this.dim = dim;
    this.width = 1;
    this.height = 1;
    this.fit(box);
  };

  GV.Camera.prototype.fit = function (box) {
    const c = [0, 1, 2].map((k) => 0.5 * (box.lo[k] + box.hi[k]));
    const ext = [0, 1, 2].map((k) => box.hi[k] - box.lo[k]);
    this.target = c;
    this.extent = Math.max(ext[0], ext[1], ext[2], 1e-6);
    this.zoom = 1; // 2D: the extent fills the shorter side at zoom 1
    this.yaw = -0.6;
    this.pitch = 0.5;
    this.distance = 1.6 * this.extent;
  };

  GV.Camera.prototype.resize = function (w, h) {
    this.width = Math.max(1, w);
    this.height = Math.max(1, h);
  };

  /** Pixels per world unit (2D). */
  GV.Camera.prototype.scale = function () {
    return (0.9 * Math.min(this.width, this.height) * this.zoom) / this.extent;
  };

  GV.Camera.prototype.matrix = function () {
    const w = this.width, h = this.height, t = this.target;
    if (this.dim === 2) {
      const s = this.scale();
      const sx = (2 * s) / w, sy = (2 * s) / h;
      return new Float32Array([sx, 0, 0, 0, 0, sy, 0, 0, 0, 0, 1, 0, -t[0] * sx, -t[1] * sy, 0, 1]);
    }
    const cy = Math.cos(this.yaw), sy = Math.sin(this.yaw);
    const cp = Math.cos(this.pitch), sp = Math.sin(this.pitch);
    // View: rotate the world about the target (z up), then move back by the distance.
    const fwd = [cp * cy, cp * sy, sp]; // from the target to the eye
    const right = [-sy, cy, 0];
    const up = [-sp * cy, -sp * sy, cp];
    const e = [t[0] + fwd[0] * this.distance, t[1] + fwd[1] * this.distance, t[2] + fwd[2] * this.distance];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const view = new Float32Array([
      right[0], up[0], fwd[0], 0,
      right[1], up[1], fwd[1], 0,
      right[2], up[2], fwd[2], 0,
      -dot(right, e), -dot(up, e), -dot(fwd, e), 1,
    ]);
    const near = this.distance * 0.01, far = this.distance * 4 + this.extent * 4;
    const f = 1 / Math.tan(0.5 * 0.8);
    const aspect = w / h;
    const proj = new Float32Array([
      f / aspect, 0, 0, 0,
      0, f, 0, 0,
      0, 0, (far + near) / (near - far), -1,
      0, 0, (2 * far * near) / (near - far), 0,
    ]);
    return multiply(proj, view);
  };

  /** Screen coordinates of every vertex of `pos` (dim per vertex) under `m`: x, y per vertex
   * (NaN behind the camera or for a NaN position). */
  GV.Camera.prototype.projectAll = function (pos, dim, m, out) {
    const n = pos.length / dim;
    const w = this.width, h = this.height;
    const r = out && out.length === 2 * n ? out : new Float32Array(2 * n);
    for (let i = 0; i < n; i++) {
      const x = pos[i * dim], y = pos[i * dim + 1], z = dim === 3 ? pos[i * dim + 2] : 0;
      const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
      if (!(cw > 0)) {
        r[2 * i] = r[2 * i + 1] = NaN;
        continue;
      }
      const cx = (m[0] * x + m[4] * y + m[8] * z + m[12]) / cw;
      const cyy = (m[1] * x + m[5] * y + m[9] * z + m[13]) / cw;
      r[2 * i] = (cx + 1) * 0.5 * w;
      r[2 * i + 1] = (1 - cyy) * 0.5 * h;
    }
    return r;
  };

  /** Zoom by `factor` about the canvas point (px, py). */
  GV.Camera.prototype.zoomAt = function (factor, px, py) {
    if (this.dim === 3) {
      this.distance = Math.min(Math.max(this.distance / factor, this.extent * 1e-3), this.extent * 50);
      return;
    }
    const s0 = this.scale();
    const wx = this.target[0] + (px - this.width / 2) / s0;
    const wy = this.target[1] - (py - this.height / 2) / s0;
    this.zoom = Math.min(Math.max(this.zoom * factor, 1e-3), 1e6);
    const s1 = this.scale();
    this.target[0] = wx - (px - this.width / 2) / s1;
    this.target[1] = wy + (py - this.height / 2) / s1;
  };

  /** A drag by (dx, dy) pixels: pan (2D, or 3D with `pan`), orbit (3D). */
  GV.Camera.prototype.drag = function (dx, dy, pan) {
    if (this.dim === 2) {
      const s = this.scale();
      this.target[0] -= dx / s;
      this.target[1] += dy / s;
      return;
    }
    if (pan) {
      const k = (this.distance * 0.8) / this.height;
      const cy = Math.cos(this.yaw), sy = Math.sin(this.yaw);
      const cp = Math.cos(this.pitch), sp = Math.sin(this.pitch);
      const right = [-sy, cy, 0], up = [-sp * cy, -sp * sy, cp];
      for (let c = 0; c < 3; c++) this.target[c] += (-dx * right[c] + dy * up[c]) * k;
      return;
    }
    this.yaw -= dx * 0.008;
    this.pitch = Math.min(Math.max(this.pitch + dy * 0.008, -1.55), 1.55);
  };
})();
