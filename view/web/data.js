// SPDX-License-Identifier: MIT
// graphslam view: the page's data, decoded from the JSON element the library wrote.
(function () {
  const KIND_NAMES = ["odometry", "loop closure", "landmark", "prior", "other"];
  const VERTEX_KIND_NAMES = ["pose", "point", "generic"];
  GV.KIND_NAMES = KIND_NAMES;
  GV.VERTEX_KIND_NAMES = VERTEX_KIND_NAMES;
  GV.FLAG = { inactive: 1, downweighted: 2, robust: 4, removed: 8 };
  // The arrays of the data and their types (view/src/page_json.cpp writes them).
  const ARRAYS = {
    vid: Int32Array, vtag: Uint8Array, vfixed: Uint8Array, vline: Int32Array,
    ea: Uint32Array, eb: Uint32Array, ekind: Uint8Array, etag: Uint8Array, eflag: Uint8Array,
    eweight: Float32Array, eline: Int32Array, xedge: Uint32Array, xvertex: Uint32Array,
  };

  /** Bounding box (min, max, per axis) of positions `pos` (dim per vertex), NaN skipped. */
  function bounds(pos, dim) {
    const lo = [Infinity, Infinity, Infinity];
    const hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < pos.length; i += dim) {
      for (let c = 0; c < dim; c++) {
        const x = pos[i + c];
        if (x < lo[c]) lo[c] = x;
        if (x > hi[c]) hi[c] = x;
      }
    }
    for (let c = 0; c < 3; c++) {
      if (!isFinite(lo[c])) lo[c] = hi[c] = 0;
    }
    return { lo: lo, hi: hi };
  }
  GV.bounds = bounds;

  GV.loadData = function () {
    const raw = JSON.parse(document.getElementById("graph-data").textContent);
    const d = {
      dim: raw.dim,
      title: raw.title,
      source: raw.source,
      lodEdges: raw.lodEdges,
      vertexTags: raw.vertexTags,
      vertexTagKinds: raw.vertexTagKinds,
      edgeTags: raw.edgeTags,
      notes: raw.notes,
      summary: raw.summary || [],
      hasInitial: raw.hasInitial,
      covariances: raw.covariances || [],
    };
    for (const name in ARRAYS) d[name] = GV.decode(raw[name], ARRAYS[name]);
    if (raw.edim) {
      d.edim = GV.decode(raw.edim, Uint8Array);
      d.eerr = GV.decode(raw.eerr, Float32Array);
      d.eerrAt = new Uint32Array(d.edim.length + 1);
      for (let k = 0; k < d.edim.length; k++) d.eerrAt[k + 1] = d.eerrAt[k] + d.edim[k];
    }
    d.frames = raw.frames.map((f) => ({
      label: f.label,
      objective: f.objective,
      pos: GV.decode(f.pos, Float32Array),
      chi2: GV.decode(f.chi2, Float32Array),
    }));
    if (raw.truth) {
      d.truth = GV.decode(raw.truth, Float32Array);
      d.ape = GV.decode(raw.ape, Float32Array);
    }
    d.nv = d.vid.length;
    d.ne = d.ea.length;
    d.vkind = new Uint8Array(d.nv);
    for (let i = 0; i < d.nv; i++) d.vkind[i] = d.vertexTagKinds[d.vtag[i]];
    d.flagCount = { rejected: 0, downweighted: 0 };
    for (let k = 0; k < d.ne; k++) {
      if (d.eflag[k] & (GV.FLAG.inactive | GV.FLAG.removed)) d.flagCount.rejected++;
      if (d.eflag[k] & GV.FLAG.downweighted) d.flagCount.downweighted++;
    }
    const poses = [];
    for (let i = 0; i < d.nv; i++) if (d.vkind[i] === 0) poses.push(i);
    d.poses = Uint32Array.from(poses); // pose indices in id order: the trajectory
    d.final = d.frames.length - 1;
    d.box = bounds(d.frames[d.final].pos, d.dim);
    const lchi = new Float32Array(d.ne);
    const last = d.frames[d.final].chi2;
    for (let k = 0; k < d.ne; k++) {
      const gone = d.eflag[k] & (GV.FLAG.inactive | GV.FLAG.removed);
      lchi[k] = last[k] > 0 && !gone ? Math.log10(last[k]) : NaN;
    }
    const q = GV.quantiles(lchi, [0.02, 0.98]);
    d.chi2Range = [q[0], Math.max(q[1], q[0] + 1e-6)];
    if (d.ape) {
      const qa = GV.quantiles(d.ape, [0, 1]);
      d.apeRange = [qa[0], Math.max(qa[1], qa[0] + 1e-9)];
    }
    return d;
  };

  /** Counts and chi2 sums by edge kind and tag, and vertex counts by tag, for frame `f`. */
  GV.statistics = function (d, f) {
    const chi2 = d.frames[f].chi2;
    const byKind = KIND_NAMES.map((name) => ({ name: name, count: 0, chi2: 0 }));
    const byTag = d.edgeTags.map((name) => ({ name: name, count: 0, chi2: 0 }));
    let rejected = 0, downweighted = 0, total = 0;
    for (let k = 0; k < d.ne; k++) {
      const c = chi2[k];
      const removed = d.eflag[k] & (GV.FLAG.inactive | GV.FLAG.removed);
      byKind[d.ekind[k]].count++;
      byTag[d.etag[k]].count++;
      if (removed) rejected++;
      else {
        byKind[d.ekind[k]].chi2 += c;
        byTag[d.etag[k]].chi2 += c;
        total += c;
      }
      if (d.eflag[k] & GV.FLAG.downweighted) downweighted++;
    }
    const vertices = d.vertexTags.map((name) => ({ name: name, count: 0 }));
    for (let i = 0; i < d.nv; i++) vertices[d.vtag[i]].count++;
    return { byKind, byTag, vertices, rejected, downweighted, total };
  };
})();
