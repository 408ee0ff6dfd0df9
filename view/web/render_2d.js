// SPDX-License-Identifier: MIT
// graphslam view: the canvas 2D renderer, used when WebGL is not available (or with #canvas
// in the page's address). It draws at most the level-of-detail bound of segments per layer.
(function () {
  GV.CanvasRenderer = function (canvas) {
    this.g = canvas.getContext("2d");
    this.layers = [];
    this.lodEdges = 200000;
    this.kind = "canvas";
    this.screen = null;
  };

  GV.CanvasRenderer.prototype.setLayers = function (layers, lodEdges) {
    this.layers = layers;
    this.lodEdges = Math.min(lodEdges, 200000);
  };

  GV.CanvasRenderer.prototype.sync = function () {};

  GV.CanvasRenderer.prototype.setLod = function (lodEdges) {
    this.lodEdges = Math.min(lodEdges, 200000);
  };

  GV.CanvasRenderer.prototype.draw = function (m, w, h, moving) {
    const g = this.g;
    const dpr = window.devicePixelRatio || 1;
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.fillStyle = "#fff";
    g.fillRect(0, 0, w, h);
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    const cam = { width: w / dpr, height: h / dpr };
    let drawn = 0;
    for (const l of this.layers) {
      const xy = GV.Camera.prototype.projectAll.call(cam, l.pos.subarray(0, 3 * l.count), 3, m);
      if (l.mode === "lines") {
        const segs = l.count / 2;
        const stride = moving || segs > this.lodEdges ? Math.max(1, Math.ceil(segs / this.lodEdges)) : 1;
        g.lineWidth = 1;
        let style = "";
        for (let s = 0; s < segs; s += stride) {
          const a = 2 * s, b = a + 1;
          const c = "rgb(" + l.col[4 * a] + "," + l.col[4 * a + 1] + "," + l.col[4 * a + 2] + ")";
          if (c !== style) {
            if (style) g.stroke();
            g.strokeStyle = style = c;
            g.beginPath();
          }
          if (!isFinite(xy[2 * a]) || !isFinite(xy[2 * b])) continue;
          g.moveTo(xy[2 * a], xy[2 * a + 1]);
          g.lineTo(xy[2 * b], xy[2 * b + 1]);
          drawn++;
        }
        if (style) g.stroke();
      } else {
        const r = l.size;
        for (let i = 0; i < l.count; i++) {
          if (!isFinite(xy[2 * i])) continue;
          g.fillStyle = "rgb(" + l.col[4 * i] + "," + l.col[4 * i + 1] + "," + l.col[4 * i + 2] + ")";
          g.fillRect(xy[2 * i] - r / 2, xy[2 * i + 1] - r / 2, r, r);
          drawn++;
        }
      }
    }
    return drawn;
  };
})();
