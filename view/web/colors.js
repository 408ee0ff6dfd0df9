// SPDX-License-Identifier: MIT
// graphslam view: colours of edge kinds, vertex types, chi2 (a sequential map on log10 chi2)
// and APE (jet, as evo draws it), and the legend's colour bar.
(function () {
  // Edge kinds: odometry, loop closure, landmark, prior, other.
  GV.KIND_COLORS = [
    [70, 110, 190],
    [235, 130, 20],
    [40, 160, 80],
    [150, 70, 190],
    [140, 110, 70],
  ];
  GV.REJECTED_COLOR = [230, 0, 200];
  GV.DOWNWEIGHTED_COLOR = [255, 120, 200];
  GV.INITIAL_COLOR = [170, 170, 170];
  GV.TRUTH_COLOR = [90, 90, 90];
  GV.SELECTED_COLOR = [255, 230, 0];
  const VERTEX_COLORS = [
    [80, 80, 90],
    [20, 140, 60],
    [200, 40, 40],
    [20, 120, 200],
    [200, 120, 0],
    [120, 60, 160],
  ];
  GV.vertexColor = function (d, i) {
    const kind = d.vkind[i];
    if (kind === 2) return [200, 40, 40]; // generic: red, said in the panel
    return VERTEX_COLORS[(d.vtag[i] * 2 + kind) % VERTEX_COLORS.length];
  };

  // A sequential map (dark blue, teal, yellow-green, orange, dark red): low to high chi2.
  const CHI2_STOPS = [
    [40, 60, 160],
    [30, 150, 170],
    [150, 200, 60],
    [250, 150, 30],
    [190, 20, 30],
  ];
  // Jet, as evo's APE colouring.
  const JET_STOPS = [
    [0, 0, 143],
    [0, 0, 255],
    [0, 255, 255],
    [255, 255, 0],
    [255, 0, 0],
    [128, 0, 0],
  ];
  function ramp(stops, t) {
    if (!(t >= 0)) t = 0;
    if (t > 1) t = 1;
    const x = t * (stops.length - 1);
    const i = Math.min(stops.length - 2, Math.floor(x));
    const f = x - i;
    const a = stops[i], b = stops[i + 1];
    return [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f];
  }
  /** Colour of chi2 `c` on the range [lo, hi] of log10 chi2. */
  GV.chi2Color = function (c, range) {
    if (!(c > 0)) return CHI2_STOPS[0];
    return ramp(CHI2_STOPS, (Math.log10(c) - range[0]) / (range[1] - range[0]));
  };
  GV.apeColor = function (e, range) {
    return ramp(JET_STOPS, (e - range[0]) / (range[1] - range[0]));
  };

  /** Draws the colour bar of `mode` ("chi2" or "ape") into canvas `cv`, labelled. */
  GV.drawLegend = function (cv, mode, range) {
    const g = cv.getContext("2d");
    const w = cv.width, h = cv.height;
    g.clearRect(0, 0, w, h);
    const stops = mode === "ape" ? JET_STOPS : CHI2_STOPS;
    for (let x = 0; x < w; x++) {
      const c = ramp(stops, x / (w - 1));
      g.fillStyle = "rgb(" + (c[0] | 0) + "," + (c[1] | 0) + "," + (c[2] | 0) + ")";
      g.fillRect(x, 0, 1, h);
    }
  };
})();
