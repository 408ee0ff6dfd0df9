// SPDX-License-Identifier: MIT
// graphslam view: what is drawn, as layers of lines and points (positions xyz, colours
// rgba) built from the data and the user's choices; the renderers only draw layers.
(function () {
  /** A growing layer: `mode` "lines" or "points". */
  function Layer(mode, capacity, size) {
    this.mode = mode;
    this.pos = new Float32Array(3 * Math.max(capacity, 1));
    this.col = new Uint8Array(4 * Math.max(capacity, 1));
    this.count = 0;
    this.size = size || 1;
  }
  Layer.prototype.add = function (p, i, dim, c) {
    const n = this.count++;
    this.pos[3 * n] = p[i * dim];
    this.pos[3 * n + 1] = p[i * dim + 1];
    this.pos[3 * n + 2] = dim === 3 ? p[i * dim + 2] : 0;
    this.col[4 * n] = c[0];
    this.col[4 * n + 1] = c[1];
    this.col[4 * n + 2] = c[2];
    this.col[4 * n + 3] = 255;
  };
  Layer.prototype.addXYZ = function (x, y, z, c) {
    const n = this.count++;
    this.pos[3 * n] = x;
    this.pos[3 * n + 1] = y;
    this.pos[3 * n + 2] = z;
    this.col.set([c[0], c[1], c[2], 255], 4 * n);
  };
  GV.Layer = Layer;

  function isRejected(d, k) {
    return (d.eflag[k] & (GV.FLAG.inactive | GV.FLAG.removed)) !== 0;
  }

  /** Whether edge k is drawn under the user's choices `st`. */
  GV.edgeVisible = function (d, st, k) {
    if (isRejected(d, k)) return st.layers.rejected;
    return st.layers["kind" + d.ekind[k]];
  };

  function edgeColor(d, st, chi2, k) {
    if (isRejected(d, k)) return GV.REJECTED_COLOR;
    if (d.eflag[k] & GV.FLAG.downweighted) return GV.DOWNWEIGHTED_COLOR;
    if (st.colorBy === "kind") return GV.KIND_COLORS[d.ekind[k]];
    return GV.chi2Color(chi2[k], d.chi2Range);
  }

  /** The edges of frame f as line segments (rejected ones last, on top). */
  function edgeLayer(d, st, f, color) {
    const pos = d.frames[f].pos, chi2 = d.frames[f].chi2;
    const layer = new Layer("lines", 2 * (d.ne + d.xedge.length));
    for (let pass = 0; pass < 2; pass++) {
      for (let k = 0; k < d.ne; k++) {
        if ((pass === 1) !== isRejected(d, k) || !GV.edgeVisible(d, st, k)) continue;
        const c = color || edgeColor(d, st, chi2, k);
        layer.add(pos, d.ea[k], d.dim, c);
        layer.add(pos, d.eb[k], d.dim, c);
      }
    }
    for (let j = 0; j < d.xedge.length; j++) {
      const k = d.xedge[j];
      if (!GV.edgeVisible(d, st, k)) continue;
      const c = color || edgeColor(d, st, chi2, k);
      layer.add(pos, d.ea[k], d.dim, c);
      layer.add(pos, d.xvertex[j], d.dim, c);
    }
    return layer;
  }

  function vertexLayer(d, st, f) {
    const pos = d.frames[f].pos;
    const size = d.nv > 100000 ? 1 : d.nv > 1000 ? 2 : 3;
    const layer = new Layer("points", d.nv, size);
    const byApe = st.vertexColorBy === "ape" && d.ape;
    for (let i = 0; i < d.nv; i++) {
      if (byApe && isFinite(d.ape[i])) layer.add(pos, i, d.dim, GV.apeColor(d.ape[i], d.apeRange));
      else layer.add(pos, i, d.dim, GV.vertexColor(d, i));
    }
    return layer;
  }

  /** The ground truth: a line through consecutive poses that have one, and its points. */
  function truthLayer(d) {
    const layer = new Layer("lines", 2 * d.poses.length);
    for (let j = 0; j + 1 < d.poses.length; j++) {
      const i = d.poses[j], n = d.poses[j + 1];
      if (!isFinite(d.truth[i * d.dim]) || !isFinite(d.truth[n * d.dim])) continue;
      layer.add(d.truth, i, d.dim, GV.TRUTH_COLOR);
      layer.add(d.truth, n, d.dim, GV.TRUTH_COLOR);
    }
    return layer;
  }

  /** The estimated trajectory coloured by its APE (evo's picture): a line through
   * consecutive poses that have an error. */
  function apePathLayer(d, f) {
    const pos = d.frames[f].pos;
    const layer = new Layer("lines", 2 * d.poses.length);
    for (let j = 0; j + 1 < d.poses.length; j++) {
      const i = d.poses[j], n = d.poses[j + 1];
      if (!isFinite(d.ape[i]) || !isFinite(d.ape[n])) continue;
      const c = GV.apeColor(0.5 * (d.ape[i] + d.ape[n]), d.apeRange);
      layer.add(pos, i, d.dim, c);
      layer.add(pos, n, d.dim, c);
    }
    return layer;
  }

  /** 3-sigma ellipses (3D: one per pair of principal axes) of the chosen vertices. */
  function covarianceLayer(d, f) {
    const pos = d.frames[f].pos, steps = 48, dim = d.dim;
    const planes = dim === 2 ? [[0, 1]] : [[0, 1], [0, 2], [1, 2]];
    const layer = new Layer("lines", d.covariances.length * planes.length * steps * 2);
    const color = [200, 0, 60];
    for (const cv of d.covariances) {
      const o = [0, 1, 2].map((c) => (c < dim ? pos[cv.v * dim + c] : 0));
      const axis = (k) => [0, 1, 2].map((c) => (c < dim ? 3 * cv.axes[k * dim + c] : 0));
      for (const [a, b] of planes) {
        const u = axis(a), w = axis(b);
        let prev = null;
        for (let s = 0; s <= steps; s++) {
          const t = (2 * Math.PI * s) / steps, ct = Math.cos(t), st = Math.sin(t);
          const p = [0, 1, 2].map((c) => o[c] + ct * u[c] + st * w[c]);
          if (prev) {
            layer.addXYZ(prev[0], prev[1], prev[2], color);
            layer.addXYZ(p[0], p[1], p[2], color);
          }
          prev = p;
        }
      }
    }
    return layer;
  }

  function selectionLayers(d, st, f) {
    const pos = d.frames[f].pos, sel = st.selected;
    if (!sel) return [];
    const points = new Layer("points", 4, 9);
    const lines = new Layer("lines", 2 * (d.xedge.length + 1));
    if (sel.type === "vertex") {
      points.add(pos, sel.index, d.dim, GV.SELECTED_COLOR);
    } else {
      const k = sel.index;
      lines.add(pos, d.ea[k], d.dim, GV.SELECTED_COLOR);
      lines.add(pos, d.eb[k], d.dim, GV.SELECTED_COLOR);
      points.add(pos, d.ea[k], d.dim, GV.SELECTED_COLOR);
      points.add(pos, d.eb[k], d.dim, GV.SELECTED_COLOR);
    }
    return [lines, points];
  }

  /** Every layer of the picture, back to front. */
  GV.compose = function (d, st) {
    const f = st.frame;
    const layers = [];
    if (st.layers.initial && d.hasInitial && f !== 0) {
      layers.push(edgeLayer(d, st, 0, GV.INITIAL_COLOR));
    }
    if (st.layers.truth && d.truth) layers.push(truthLayer(d));
    layers.push(edgeLayer(d, st, f, null));
    if (d.ape && st.vertexColorBy === "ape") layers.push(apePathLayer(d, f));
    if (st.layers.covariance && d.covariances.length) layers.push(covarianceLayer(d, f));
    if (st.layers.vertices) layers.push(vertexLayer(d, st, f));
    for (const l of selectionLayers(d, st, f)) layers.push(l);
    return layers;
  };
})();
