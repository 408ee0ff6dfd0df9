// SPDX-License-Identifier: MIT
// graphslam view: the side panel: summary (counts, chi2 by edge kind and tag, status, notes),
// layer switches, colouring, the iteration slider, the legend and the picked element.
(function () {
  function section(panel, title) {
    const s = GV.el("section", null, panel);
    GV.el("h2", { text: title }, s);
    return s;
  }

  function checkbox(parent, id, label, checked, swatch, onChange) {
    const row = GV.el("label", { cls: "row" }, parent);
    const box = GV.el("input", { type: "checkbox", id: "layer-" + id }, row);
    box.checked = checked;
    if (swatch) {
      const sw = GV.el("span", { cls: "swatch" }, row);
      sw.style.background = "rgb(" + swatch.join(",") + ")";
    }
    GV.el("span", { text: label }, row);
    box.addEventListener("change", () => onChange(id, box.checked));
    return box;
  }

  function select(parent, id, label, options, value, onChange) {
    const row = GV.el("label", { cls: "row" }, parent);
    GV.el("span", { text: label + " " }, row);
    const s = GV.el("select", { id: id }, row);
    for (const [v, text] of options) {
      const o = GV.el("option", { value: v, text: text }, s);
      if (v === value) o.selected = true;
    }
    s.addEventListener("change", () => onChange(s.value));
    return s;
  }

  /** The summary table of frame `f`. */
  GV.fillSummary = function (d, f, box) {
    box.textContent = "";
    const s = GV.statistics(d, f);
    const t = GV.el("table", null, box);
    const row = (a, b, c) => {
      const r = GV.el("tr", null, t);
      GV.el("td", { text: a }, r);
      GV.el("td", { text: b, cls: "num" }, r);
      GV.el("td", { text: c === undefined ? "" : c, cls: "num" }, r);
    };
    row("vertices", String(d.nv));
    for (const v of s.vertices) row("  " + v.name, String(v.count));
    row("edges", String(d.ne), "chi2");
    for (const k of s.byKind) if (k.count) row("  " + k.name, String(k.count), GV.fmt(k.chi2));
    for (const k of s.byTag) if (k.count) row("  " + k.name, String(k.count), GV.fmt(k.chi2));
    row("total chi2", "", GV.fmt(s.total));
    if (s.rejected) row("rejected", String(s.rejected));
    if (s.downweighted) row("down-weighted", String(s.downweighted));
    return s;
  };

  /** Builds the panel; `app` has the data `d`, the state `st` and `changed(what)`. */
  GV.buildPanel = function (app) {
    const d = app.d, st = app.st;
    const panel = GV.el("div", { id: "panel" }, document.body);
    GV.el("h1", { text: d.title }, panel);
    if (d.source) GV.el("div", { cls: "source", text: d.source }, panel);
    const status = section(panel, "Summary");
    for (const [k, v] of d.summary) GV.el("div", { cls: "kv", text: k + ": " + v }, status);
    app.summaryBox = GV.el("div", { id: "summary" }, status);
    for (const n of d.notes) GV.el("div", { cls: "note", text: n }, status);

    const layers = section(panel, "Layers");
    const set = (id, on) => {
      st.layers[id] = on;
      app.changed("layers");
    };
    for (let k = 0; k < GV.KIND_NAMES.length; k++) {
      let n = 0;
      for (let e = 0; e < d.ne; e++) if (d.ekind[e] === k) n++;
      if (n) checkbox(layers, "kind" + k, GV.KIND_NAMES[k] + " (" + n + ")", st.layers["kind" + k], GV.KIND_COLORS[k], set);
    }
    checkbox(layers, "vertices", "vertices", st.layers.vertices, null, set);
    if (d.flagCount.rejected) checkbox(layers, "rejected", "rejected edges (" + d.flagCount.rejected + ")", st.layers.rejected, GV.REJECTED_COLOR, set);
    if (d.flagCount.downweighted) {
      const r = GV.el("div", { cls: "row" }, layers);
      const sw = GV.el("span", { cls: "swatch" }, r);
      sw.style.background = "rgb(" + GV.DOWNWEIGHTED_COLOR.join(",") + ")";
      GV.el("span", { text: "down-weighted by a robust kernel (" + d.flagCount.downweighted + ")" }, r);
    }
    if (d.hasInitial) checkbox(layers, "initial", "initial estimate (grey)", st.layers.initial, GV.INITIAL_COLOR, set);
    if (d.truth) checkbox(layers, "truth", "ground truth", st.layers.truth, GV.TRUTH_COLOR, set);
    if (d.covariances.length) checkbox(layers, "covariance", "3-sigma covariance (" + d.covariances.length + ")", st.layers.covariance, [200, 0, 60], set);

    const colours = section(panel, "Colours");
    if (d.ne > 0) {
      select(colours, "color-by", "edges by", [["chi2", "chi2 contribution"], ["kind", "kind"]], st.colorBy, (v) => {
        st.colorBy = v;
        app.changed("colors");
      });
    }
    if (d.ape) {
      select(colours, "vertex-color-by", "vertices by", [["ape", "APE (evo's jet)"], ["type", "type"]], st.vertexColorBy, (v) => {
        st.vertexColorBy = v;
        app.changed("colors");
      });
    }
    app.legend = GV.el("canvas", { id: "legend", width: "220", height: "12" }, colours);
    app.legendText = GV.el("div", { cls: "legend-text" }, colours);

    if (d.frames.length > 1) {
      const it = section(panel, "Iterations");
      const slider = GV.el("input", { type: "range", id: "frame", min: "0", max: String(d.frames.length - 1), step: "1" }, it);
      slider.value = String(st.frame);
      app.frameLabel = GV.el("div", { id: "frame-label" }, it);
      slider.addEventListener("input", () => {
        st.frame = Number(slider.value);
        app.changed("frame");
      });
    }
    const sel = section(panel, "Selected");
    app.infoBox = GV.el("pre", { id: "info", text: "hover or click a vertex or an edge" }, sel);
    app.perfBox = GV.el("div", { id: "perf" }, panel);
  };

  /** Updates the legend, the frame label and the summary after a change. */
  GV.updatePanel = function (app) {
    const d = app.d, st = app.st;
    const ape = st.vertexColorBy === "ape" && d.ape;
    if (st.colorBy === "chi2" && d.ne > 0) {
      GV.drawLegend(app.legend, "chi2", d.chi2Range);
      app.legendText.textContent =
        "edge chi2 (log scale): " + GV.fmt(Math.pow(10, d.chi2Range[0])) + " ... " + GV.fmt(Math.pow(10, d.chi2Range[1]));
    } else if (ape) {
      GV.drawLegend(app.legend, "ape", d.apeRange);
      app.legendText.textContent = "APE: " + GV.fmt(d.apeRange[0]) + " ... " + GV.fmt(d.apeRange[1]);
    } else {
      app.legend.getContext("2d").clearRect(0, 0, app.legend.width, app.legend.height);
      app.legendText.textContent = "edges coloured by kind (swatches above)";
    }
    if (ape && st.colorBy === "chi2" && d.ne > 0) app.legendText.textContent += "; vertices by APE " + GV.fmt(d.apeRange[0]) + " ... " + GV.fmt(d.apeRange[1]);
    if (app.frameLabel) {
      const fr = d.frames[st.frame];
      app.frameLabel.textContent = fr.label + (fr.objective !== null && isFinite(fr.objective) ? "  chi2 " + GV.fmt(fr.objective) : "");
    }
    GV.fillSummary(d, st.frame, app.summaryBox);
  };
})();
