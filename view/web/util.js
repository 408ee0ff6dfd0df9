// SPDX-License-Identifier: MIT
// graphslam view: shared helpers. Every file of the page adds to the one namespace GV.
var GV = (window.GV = {});

/** The typed array of base64 text `s` (little-endian bytes, as the library writes them). */
GV.decode = function (s, Type) {
  const bin = atob(s);
  const n = bin.length;
  const bytes = new Uint8Array(n);
  for (let i = 0; i < n; i++) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer, 0, n / Type.BYTES_PER_ELEMENT);
};

/** A new element `tag` with properties `props`, appended to `parent` when given. */
GV.el = function (tag, props, parent) {
  const e = document.createElement(tag);
  if (props) {
    for (const k in props) {
      if (k === "text") e.textContent = props[k];
      else if (k === "cls") e.className = props[k];
      else e.setAttribute(k, props[k]);
    }
  }
  if (parent) parent.appendChild(e);
  return e;
};

/** Short text of a number: 4 significant digits, exponent form when large or small. */
GV.fmt = function (x) {
  if (x === null || x === undefined || !isFinite(x)) return "n/a";
  const a = Math.abs(x);
  if (a !== 0 && (a >= 1e5 || a < 1e-3)) return x.toExponential(3);
  return String(Number(x.toPrecision(4)));
};

GV.now = function () {
  return performance.now();
};

/** The `q` quantile (0..1) of the finite values of `values` (a sample of at most 20000). */
GV.quantiles = function (values, qs) {
  const n = values.length;
  const step = Math.max(1, Math.floor(n / 20000));
  const sample = [];
  for (let i = 0; i < n; i += step) if (isFinite(values[i])) sample.push(values[i]);
  sample.sort((a, b) => a - b);
  return qs.map((q) =>
    sample.length ? sample[Math.min(sample.length - 1, Math.floor(q * sample.length))] : 0
  );
};
