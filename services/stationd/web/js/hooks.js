/*
 * hooks.js — the page's state as the browser tests and the benchmark read
 * it: window.cgs (the last hello and state, whether a state was drawn, apply
 * times and replies, the live video's state, the map, and pixelOf, the page
 * pixel of a map point).
 * The only global the page sets.
 */

export const cgs = {
  hello: null,
  state: null,
  ready: false,
  stats: { updates: 0, applyMs: [], replies: [] },
  video: null,             // the live video and the KLV footprint (video.js)
  map: null,
  pixelOf: function (e, n) {
    const p = cgs.map.getPixelFromCoordinate([e, n]);
    if (!p) return null;
    const r = cgs.map.getTargetElement().getBoundingClientRect();
    return [p[0] + r.left, p[1] + r.top];
  },
};
window.cgs = cgs;
