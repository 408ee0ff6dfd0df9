// SPDX-License-Identifier: MIT
// graphslam view: what is under the pointer: the nearest drawn vertex within a few pixels,
// else the nearest drawn edge.
(function () {
  function segmentDistance2(px, py, ax, ay, bx, by) {
    const dx = bx - ax, dy = by - ay;
    const len = dx * dx + dy * dy;
    let t = len > 0 ? ((px - ax) * dx + (py - ay) * dy) / len : 0;
    t = Math.max(0, Math.min(1, t));
    const x = ax + t * dx - px, y = ay + t * dy - py;
    return x * x + y * y;
  }

  /** {type: "vertex"|"edge", index} under canvas point (px, py), or null. `xy` holds the
   * screen positions of the vertices of the shown frame (Camera.projectAll). */
  GV.pick = function (d, st, xy, px, py) {
    const r = 7;
    let best = -1, bestD = r * r;
    if (st.layers.vertices) {
      for (let i = 0; i < d.nv; i++) {
        const dx = xy[2 * i] - px, dy = xy[2 * i + 1] - py;
        const dd = dx * dx + dy * dy;
        if (dd < bestD) {
          bestD = dd;
          best = i;
        }
      }
      if (best >= 0) return { type: "vertex", index: best };
    }
    bestD = 5 * 5;
    for (let k = 0; k < d.ne; k++) {
      if (!GV.edgeVisible(d, st, k)) continue;
      const a = d.ea[k], b = d.eb[k];
      const ax = xy[2 * a], ay = xy[2 * a + 1], bx = xy[2 * b], by = xy[2 * b + 1];
      if (!(isFinite(ax) && isFinite(bx))) continue;
      if (Math.min(ax, bx) > px + 5 || Math.max(ax, bx) < px - 5) continue;
      if (Math.min(ay, by) > py + 5 || Math.max(ay, by) < py - 5) continue;
      const dd = segmentDistance2(px, py, ax, ay, bx, by);
      if (dd < bestD) {
        bestD = dd;
        best = k;
      }
    }
    return best >= 0 ? { type: "edge", index: best } : null;
  };

  /** Lines of text describing the picked element in frame `f`. */
  GV.describe = function (d, sel, f) {
    const lines = [];
    const pos = d.frames[f].pos;
    const where = (line) => (line > 0 ? (d.source || "input") + ":" + line : "no file line");
    if (sel.type === "vertex") {
      const i = sel.index;
      const p = [];
      for (let c = 0; c < d.dim; c++) p.push(GV.fmt(pos[i * d.dim + c]));
      lines.push("vertex " + d.vid[i] + "  " + d.vertexTags[d.vtag[i]]);
      lines.push(GV.VERTEX_KIND_NAMES[d.vkind[i]] + (d.vfixed[i] ? ", fixed" : "") + "  at (" + p.join(", ") + ")");
      lines.push("line: " + where(d.vline[i]));
      if (d.ape && isFinite(d.ape[i])) lines.push("APE: " + GV.fmt(d.ape[i]));
      return lines;
    }
    const k = sel.index;
    const ids = [d.vid[d.ea[k]]];
    if (d.eb[k] !== d.ea[k]) ids.push(d.vid[d.eb[k]]);
    for (let j = 0; j < d.xedge.length; j++) if (d.xedge[j] === k) ids.push(d.vid[d.xvertex[j]]);
    lines.push("edge " + d.edgeTags[d.etag[k]] + "  " + ids.join(" - "));
    lines.push(GV.KIND_NAMES[d.ekind[k]] + "  (edge " + k + ")");
    lines.push("chi2: " + GV.fmt(d.frames[f].chi2[k]));
    if (d.eerr && k < d.edim.length && f === d.final) {
      const e = Array.from(d.eerr.subarray(d.eerrAt[k], d.eerrAt[k + 1]), GV.fmt);
      lines.push("error: (" + e.join(", ") + ")");
    }
    const flags = d.eflag[k];
    if (flags & GV.FLAG.removed) lines.push("rejected as an outlier (removed)");
    else if (flags & GV.FLAG.inactive) lines.push("inactive (left out of the optimisation)");
    if (flags & GV.FLAG.robust) lines.push("robust weight: " + GV.fmt(d.eweight[k]));
    if (flags & GV.FLAG.downweighted) lines.push("down-weighted by its robust kernel");
    lines.push("line: " + where(d.eline[k]));
    return lines;
  };
})();
