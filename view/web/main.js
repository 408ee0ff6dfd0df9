// SPDX-License-Identifier: MIT
// graphslam view: start-up, input (drag, wheel, hover, click, keys) and the draw loop. The
// page announces itself ready in window.graphslamView.ready (and body's data-ready); the
// same object holds its timings and a small API for scripted use (the browser tests).
(function () {
  const api = (window.graphslamView = { ready: false, errors: [] });

  function initialState(d) {
    const layers = { vertices: d.nv <= 200000, rejected: true, initial: false, truth: true, covariance: true };
    for (let k = 0; k < GV.KIND_NAMES.length; k++) layers["kind" + k] = true;
    return {
      frame: d.final,
      colorBy: "chi2",
      vertexColorBy: d.ape ? "ape" : "type",
      layers: layers,
      selected: null,
    };
  }

  function start() {
    const t0 = GV.now();
    const d = GV.loadData();
    const tDecoded = GV.now();
    const canvas = GV.el("canvas", { id: "view" }, document.body);
    const forceCanvas = location.hash.indexOf("canvas") >= 0;
    let renderer = forceCanvas ? null : new GV.GLRenderer(canvas);
    if (!renderer || !renderer.gl) renderer = new GV.CanvasRenderer(canvas);
    const cam = new GV.Camera(d.dim, d.box);
    const app = { d: d, st: initialState(d), cam: cam, renderer: renderer };
    let dirtyLayers = true, pending = false, moving = false, idleTimer = 0, xy = null;
    // Level of detail: at most this many segments per layer while the view moves, halved
    // (down to 20000) whenever a moving frame takes longer than 40 ms.
    let lodBudget = d.lodEdges;
    const frameTimes = [];

    function draw() {
      pending = false;
      const t = GV.now();
      const dpr = window.devicePixelRatio || 1;
      const w = canvas.clientWidth, h = canvas.clientHeight;
      if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
        canvas.width = Math.round(w * dpr);
        canvas.height = Math.round(h * dpr);
      }
      cam.resize(w, h);
      if (dirtyLayers) {
        renderer.setLayers(GV.compose(d, app.st), lodBudget);
        dirtyLayers = false;
      }
      const m = cam.matrix();
      api.drawn = renderer.draw(m, canvas.width, canvas.height, moving);
      renderer.sync(); // the frame time includes the GPU's work
      api.draws = (api.draws || 0) + 1;
      xy = null;
      const dt = GV.now() - t;
      if (moving && dt > 40 && lodBudget > 20000 && d.ne > 20000) {
        lodBudget = Math.max(20000, lodBudget >> 1);
        renderer.setLod(lodBudget);
      }
      frameTimes.push(dt);
      if (frameTimes.length > 60) frameTimes.shift();
      const sorted = frameTimes.slice().sort((a, b) => a - b);
      api.frameTimeMs = sorted[Math.floor(sorted.length / 2)];
      app.perfBox.textContent =
        renderer.kind + ", frame " + api.frameTimeMs.toFixed(1) + " ms (median of " + frameTimes.length + ")" +
        (moving && d.ne > lodBudget ? ", level of detail (" + lodBudget + " edges)" : "");
    }
    function redraw() {
      if (!pending) {
        pending = true;
        requestAnimationFrame(draw);
      }
    }
    app.changed = function (what) {
      dirtyLayers = true;
      GV.updatePanel(app);
      redraw();
    };
    function interacting() {
      moving = true;
      clearTimeout(idleTimer);
      idleTimer = setTimeout(() => {
        moving = false;
        redraw();
      }, 150);
      redraw();
    }
    function screen() {
      if (!xy) xy = cam.projectAll(d.frames[app.st.frame].pos, d.dim, cam.matrix(), xy);
      return xy;
    }
    function show(sel) {
      app.infoBox.textContent = sel ? GV.describe(d, sel, app.st.frame).join("\n") : "nothing here";
    }
    GV.buildPanel(app);
    GV.updatePanel(app);
    bindInput(canvas, app, { interacting, redraw, screen, show, dirty: () => (dirtyLayers = true) });
    window.addEventListener("resize", redraw);
    // A graph beyond the level-of-detail bound shows its subsample first, every edge next.
    moving = d.ne > lodBudget;
    draw();
    if (moving) {
      moving = false;
      setTimeout(redraw, 0);
    }

    api.data = d;
    api.state = app.st;
    api.renderer = renderer.kind;
    api.decodeMs = tDecoded - t0;
    api.readyMs = GV.now() - t0;
    api.sinceNavigationMs = GV.now();
    api.redraw = draw;
    api.orbit = function (dx, dy) {
      cam.drag(dx, dy, false);
      moving = true;
      draw();
      moving = false;
    };
    api.select = function (type, index) {
      app.st.selected = { type: type, index: index };
      show(app.st.selected);
      app.changed("selection");
    };
    api.screenOf = function (i) {
      const p = screen();
      return [p[2 * i], p[2 * i + 1]];
    };
    api.info = () => app.infoBox.textContent;
    api.ready = true;
    document.body.setAttribute("data-ready", "1");
  }

  function bindInput(canvas, app, h) {
    const cam = app.cam;
    let down = null, dragged = false;
    canvas.addEventListener("mousedown", (e) => {
      down = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button !== 0 };
      dragged = false;
    });
    window.addEventListener("mouseup", (e) => {
      if (down && !dragged) {
        const r = canvas.getBoundingClientRect();
        const p = h.screen();
        app.st.selected = GV.pick(app.d, app.st, p, e.clientX - r.left, e.clientY - r.top);
        h.show(app.st.selected);
        app.changed("selection");
      }
      down = null;
    });
    canvas.addEventListener("contextmenu", (e) => e.preventDefault());
    canvas.addEventListener("mousemove", (e) => {
      if (down) {
        const dx = e.clientX - down.x, dy = e.clientY - down.y;
        if (Math.abs(dx) + Math.abs(dy) > 2) dragged = true;
        if (!dragged) return;
        cam.drag(dx, dy, down.pan);
        down.x = e.clientX;
        down.y = e.clientY;
        h.interacting();
        return;
      }
      if (app.st.selected || app.d.ne > app.d.lodEdges) return; // click to pick on huge graphs
      const r = canvas.getBoundingClientRect();
      const sel = GV.pick(app.d, app.st, h.screen(), e.clientX - r.left, e.clientY - r.top);
      if (sel) h.show(sel);
    });
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      const r = canvas.getBoundingClientRect();
      cam.zoomAt(Math.exp(-e.deltaY * 0.0015), e.clientX - r.left, e.clientY - r.top);
      h.interacting();
    }, { passive: false });
    window.addEventListener("keydown", (e) => {
      if (e.key === "f") {
        cam.fit(app.d.box);
        h.redraw();
      } else if (e.key === "Escape") {
        app.st.selected = null;
        h.show(null);
        app.changed("selection");
      }
    });
  }

  window.addEventListener("error", (e) => api.errors.push(String(e.message)));
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
