/* util.js — small helpers shared by the page's modules. */

export const $ = (id) => document.getElementById(id);

// Set an element's text only when it changes (no needless layout work).
export function setText(el, s) {
  if (el.textContent !== s) el.textContent = s;
}

export function num(x, d) {
  return typeof x === 'number' && isFinite(x) ? x : d;
}

export function clamp(x, lo, hi) {
  return x < lo ? lo : x > hi ? hi : x;
}

// Two flat number arrays hold the same values.
export function sameArray(a, b) {
  if (a === b) return true;
  if (!a || !b || a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

// Flat [x0,y0,x1,y1,...] to [[x0,y0],[x1,y1],...].
export function pairs(flat) {
  const out = [];
  for (let i = 0; i + 1 < flat.length; i += 2) out.push([flat[i], flat[i + 1]]);
  return out;
}

export function evenFlat(xy) {
  if (!Array.isArray(xy)) return [];
  return xy.length % 2 ? xy.slice(0, xy.length - 1) : xy;
}
