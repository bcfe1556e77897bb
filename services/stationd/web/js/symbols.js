/*
 * symbols.js — how things look on the map: the shared OpenLayers styles
 * (hits, BCIS replies, footprint, route, waypoints, target ring, the
 * camera's stare point, leaders, loiter circle) and the MIL-STD-2525 symbols of tracks, UAVs and ground
 * truth (milsymbol, global `ms`), composed with their labels into shared
 * sprite sheets. Styles are one object per look, never one per feature or
 * update.
 */
import { clamp } from './util.js';

export const SIDC_TRACK_UNKNOWN = 'SUGPE----------';
export const SIDC_TRACK_FRIEND = 'SFGPE----------';
export const SIDC_UAV = 'SFAPMFQ--------';

const C_PURPLE = '#a020f0';
const C_BCIS = '#1e64ff';
const C_CURRENT = '#ffd700';

// ---------------------------------------------------------------------------
// Shared styles

export const S = {};

// Hits: thousands of points, so each scan (a MultiPoint) is drawn by one
// custom renderer as two filled paths (a dark rim, then the colour)
// instead of one styled image per point.
function hitStyle(radius, fill, rim, rimWidth) {
  function disks(ctx, pts, r, w, h) {
    ctx.beginPath();
    for (let i = 0; i < pts.length; i++) {
      const x = pts[i][0];
      const y = pts[i][1];
      if (x < -r || y < -r || x > w + r || y > h + r) continue;
      ctx.moveTo(x + r, y);
      ctx.arc(x, y, r, 0, 2 * Math.PI);
    }
  }
  return new ol.style.Style({
    renderer: function (coords, state) {
      const ctx = state.context;
      const ratio = state.pixelRatio;
      const pts = typeof coords[0] === 'number' ? [coords] : coords;
      const w = ctx.canvas.width;
      const h = ctx.canvas.height;
      ctx.save();
      disks(ctx, pts, (radius + rimWidth) * ratio, w, h);
      ctx.fillStyle = rim;
      ctx.fill();
      disks(ctx, pts, radius * ratio, w, h);
      ctx.fillStyle = fill;
      ctx.fill();
      ctx.restore();
    },
  });
}

S.hitOld = hitStyle(3.5, 'rgb(155,155,155)', 'rgba(0,0,0,0.75)', 1);
S.hitCurrent = hitStyle(5, C_CURRENT, '#1a1a1a', 1.5);

// BCIS replies: a blue circle with the marking; the text is set per feature.
S.bcis = new ol.style.Style({
  image: new ol.style.Circle({
    radius: 7,
    fill: new ol.style.Fill({ color: C_BCIS }),
    stroke: new ol.style.Stroke({ color: '#ffffff', width: 1.5 }),
  }),
  text: new ol.style.Text({
    font: 'bold 11px sans-serif',
    textAlign: 'right',   // left of the circle: track labels are on the right
    offsetX: -11,
    fill: new ol.style.Fill({ color: '#cfe0ff' }),
    stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.67)', width: 3 }),
  }),
});

S.footprint = new ol.style.Style({
  fill: new ol.style.Fill({ color: 'rgba(0,220,255,0.12)' }),
  stroke: new ol.style.Stroke({ color: 'rgba(0,220,255,0.9)', width: 1.5 }),
});
S.footprintHit = new ol.style.Style({
  fill: new ol.style.Fill({ color: 'rgba(70,255,110,0.14)' }),
  stroke: new ol.style.Stroke({ color: 'rgba(70,255,110,0.95)', width: 2 }),
});

// The imaging sensor's footprint from its `image` messages (thin white)
// and from the video's KLV (dashed orange, over it): drawn one on the other,
// a user sees them agree.
S.imageFootprint = new ol.style.Style({
  stroke: new ol.style.Stroke({ color: 'rgba(255,255,255,0.85)', width: 1 }),
});
S.klvFootprint = new ol.style.Style({
  stroke: new ol.style.Stroke({ color: '#ff9f1a', width: 2, lineDash: [8, 6] }),
});

S.route = [
  new ol.style.Style({ stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.45)', width: 5 }) }),
  new ol.style.Style({ stroke: new ol.style.Stroke({ color: C_PURPLE, width: 3 }) }),
];
// The label above a route point (waypoint, secondary point).
function routeLabel(text) {
  return new ol.style.Text({
    text: text, font: 'bold 10px sans-serif', offsetY: -12,
    fill: new ol.style.Fill({ color: '#e6c8ff' }),
    stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.67)', width: 3 }),
  });
}
S.waypoint = new ol.style.Style({
  image: new ol.style.Circle({
    radius: 5,
    fill: new ol.style.Fill({ color: C_PURPLE }),
    stroke: new ol.style.Stroke({ color: '#ffffff', width: 1.5 }),
  }),
  text: routeLabel('WP'),
});
S.secondary = new ol.style.Style({
  image: new ol.style.RegularShape({
    points: 4, radius: 5, angle: Math.PI / 4,
    fill: new ol.style.Fill({ color: '#ffffff' }),
    stroke: new ol.style.Stroke({ color: C_PURPLE, width: 2 }),
  }),
  text: routeLabel('P2'),
});

// Ring around the designated track.
S.target = new ol.style.Style({
  image: new ol.style.Circle({
    radius: 17,
    stroke: new ol.style.Stroke({ color: C_PURPLE, width: 3 }),
  }),
});

// Where the imaging sensor stares (a point, or the target's estimate): a
// white cross in a ring, red while the gimbal holds it at its limit.
function stareStyle(color) {
  return [
    new ol.style.Style({
      image: new ol.style.Circle({ radius: 9, stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.6)', width: 4 }) }),
    }),
    new ol.style.Style({
      image: new ol.style.Circle({ radius: 9, stroke: new ol.style.Stroke({ color: color, width: 2 }) }),
    }),
    new ol.style.Style({
      image: new ol.style.RegularShape({
        points: 4, radius: 6, radius2: 0, angle: 0,
        stroke: new ol.style.Stroke({ color: color, width: 2 }),
      }),
    }),
  ];
}
S.stare = stareStyle('#ffffff');
S.stareLimit = stareStyle('#ff5a52');

// Leaders (tracks, UAVs) are drawn from a LineString kept on the feature.
function leaderGeometry(f) {
  return f.cgsLeader;
}

// Track leaders by identity, full and faint (tentative).
function leaderStyle(color) {
  return new ol.style.Style({ geometry: leaderGeometry, stroke: new ol.style.Stroke({ color: color, width: 2 }) });
}
S.leader = {
  unknown: leaderStyle('rgba(255,215,0,0.95)'),
  unknownFaint: leaderStyle('rgba(255,215,0,0.4)'),
  friendly: leaderStyle('rgba(90,160,255,0.95)'),
  friendlyFaint: leaderStyle('rgba(90,160,255,0.4)'),
};
S.uavLeader = [
  new ol.style.Style({ geometry: leaderGeometry, stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.5)', width: 4.5 }) }),
  new ol.style.Style({ geometry: leaderGeometry, stroke: new ol.style.Stroke({ color: '#80c0ff', width: 2.5 }) }),
];
S.loiter = new ol.style.Style({
  stroke: new ol.style.Stroke({ color: 'rgba(128,192,255,0.7)', width: 1.5, lineDash: [6, 6] }),
});

// Simple truth marker when a symbol cannot be drawn.
export const FORCE_COLORS = { friendly: '#4f9dff', opposing: '#ff4040', neutral: '#40d040', other: '#ffd700' };

// ---------------------------------------------------------------------------
// MIL-STD-2525 symbols. milsymbol draws each SIDC/size once; each labelled
// variant (symbol + label, e.g. a track id) is composed once into a cell of
// a shared sprite sheet and shown with an ol.style.Icon cut from it. A
// thousand labelled tracks are thus a few canvases, drawn in a few ms.
// Cells belong to an owner (a track, UAV or truth record) and are recycled
// when it goes.

const PIXEL_RATIO = clamp(Math.ceil(window.devicePixelRatio || 1), 1, 3);
const SHEET_PX = 1024;          // sprite sheet side, CSS pixels
const LABEL_PX = 11;            // label font size, CSS pixels
const baseSymbols = new Map();  // sidc|size -> {canvas, ax, ay}
const families = new Map();     // sidc|size|colour|room -> cell layout and sheets
const measureCtx = document.createElement('canvas').getContext('2d');

function baseSymbol(sidc, size) {
  const key = sidc + '|' + size;
  let b = baseSymbols.get(key);
  if (!b) {
    // Track frames are partly transparent so the hits under them still show.
    const opts = { size: size };
    if (sidc === SIDC_TRACK_UNKNOWN || sidc === SIDC_TRACK_FRIEND) opts.fillOpacity = 0.7;
    const sym = new ms.Symbol(sidc, opts);
    const canvas = sym.asCanvas(PIXEL_RATIO);
    const a = sym.getAnchor();
    b = { canvas: canvas, ax: a.x * PIXEL_RATIO, ay: a.y * PIXEL_RATIO };
    baseSymbols.set(key, b);
  }
  return b;
}

const LABEL_FONT = 'bold ' + LABEL_PX * PIXEL_RATIO + 'px sans-serif';
measureCtx.font = LABEL_FONT;

function textWidth(text) {
  return text ? Math.ceil(measureCtx.measureText(text).width) : 0;
}

// Cell layout for a symbol with a label up to `room` wide.
function cellLayout(b, labelWidth) {
  const r = PIXEL_RATIO;
  const gap = 3 * r;
  const halo = 3 * r;
  const w = b.canvas.width + gap + labelWidth + halo;
  const h = Math.max(b.canvas.height, (LABEL_PX + 4) * r + halo);
  const y0 = Math.round((h - b.canvas.height) / 2);
  return { w: w, h: h, y0: y0, tx: b.canvas.width + gap, ty: y0 + b.ay, halo: halo };
}

export function family(sidc, size, color, room) {
  const key = sidc + '|' + size + '|' + color + '|' + room;
  let fam = families.get(key);
  if (!fam) {
    const b = baseSymbol(sidc, size);
    fam = cellLayout(b, textWidth(room));
    fam.b = b;
    fam.color = color;
    fam.roomPx = textWidth(room);
    const side = SHEET_PX * PIXEL_RATIO;
    fam.perRow = Math.max(1, Math.floor(side / fam.w));
    fam.perSheet = fam.perRow * Math.max(1, Math.floor(side / fam.h));
    fam.sheet = null;
    fam.free = [];
    families.set(key, fam);
  }
  return fam;
}

function allocCell(fam) {
  if (fam.free.length) return fam.free.pop();
  let sh = fam.sheet;
  if (!sh || sh.used >= fam.perSheet) {
    const c = document.createElement('canvas');
    c.width = fam.perRow * fam.w;
    c.height = Math.ceil(fam.perSheet / fam.perRow) * fam.h;
    sh = fam.sheet = { canvas: c, ctx: c.getContext('2d'), used: 0 };
  }
  const i = sh.used++;
  return { fam: fam, canvas: sh.canvas, ctx: sh.ctx, x: (i % fam.perRow) * fam.w, y: Math.floor(i / fam.perRow) * fam.h };
}

// Symbol plus label (white or `color` on a dark halo) into a cell.
function drawCell(cell, lay, b, label, color) {
  const ctx = cell.ctx;
  ctx.save();
  ctx.clearRect(cell.x, cell.y, lay.w, lay.h);
  ctx.beginPath();
  ctx.rect(cell.x, cell.y, lay.w, lay.h);
  ctx.clip();
  ctx.drawImage(b.canvas, cell.x, cell.y + lay.y0);
  ctx.font = LABEL_FONT;
  ctx.textBaseline = 'middle';
  ctx.lineJoin = 'round';
  ctx.lineWidth = lay.halo;
  ctx.strokeStyle = 'rgba(0,0,0,0.75)';
  ctx.strokeText(label, cell.x + lay.tx, cell.y + lay.ty);
  ctx.fillStyle = color;
  ctx.fillText(label, cell.x + lay.tx, cell.y + lay.ty);
  ctx.restore();
}

// The Icon of `sidc` labelled `label` for `owner`, made once per owner,
// symbol, label and opacity. `room` is the label width a shared sheet
// leaves; longer labels get a canvas of their own.
export function symbolIcon(owner, sidc, size, label, opacity, color, room) {
  if (!owner.cells) owner.cells = new Map();
  const key = sidc + '|' + size + '|' + label + '|' + color;
  let entry = owner.cells.get(key);
  if (!entry) {
    const fam = family(sidc, size, color, room);
    let cell;
    let lay;
    if (textWidth(label) <= fam.roomPx) {
      cell = allocCell(fam);
      lay = fam;
    } else {
      lay = cellLayout(fam.b, textWidth(label));
      const c = document.createElement('canvas');
      c.width = lay.w;
      c.height = lay.h;
      cell = { fam: null, canvas: c, ctx: c.getContext('2d'), x: 0, y: 0 };
    }
    drawCell(cell, lay, fam.b, label, color);
    entry = { cell: cell, lay: lay, b: fam.b, icons: {} };
    owner.cells.set(key, entry);
  }
  let icon = entry.icons[opacity];
  if (!icon) {
    const c = entry.cell;
    icon = new ol.style.Icon({
      img: c.canvas,
      offset: [c.x, c.y],
      size: [entry.lay.w, entry.lay.h],
      anchor: [entry.b.ax, entry.lay.y0 + entry.b.ay],
      anchorXUnits: 'pixels',
      anchorYUnits: 'pixels',
      scale: 1 / PIXEL_RATIO,
      opacity: opacity,
    });
    entry.icons[opacity] = icon;
  }
  return icon;
}

// Give an owner's sheet cells back for reuse.
export function releaseSymbols(owner) {
  if (!owner.cells) return;
  owner.cells.forEach((entry) => {
    if (entry.cell.fam) entry.cell.fam.free.push(entry.cell);
  });
  owner.cells.clear();
}

export const ROOM_TRACK = '0000000';         // track ids
export const ROOM_NAME = 'WWWWWW 000 (ext)'; // markings (11 characters in DIS) and UAV names

// SIDC of a ground-truth entity by force and kind.
const TRUTH_AFFIL = { friendly: 'F', opposing: 'H', neutral: 'N', other: 'U' };
const TRUTH_KIND = {
  tracked: ['G', 'EVAT-'],   // armoured tracked vehicle
  wheeled: ['G', 'EVU--'],   // utility (wheeled) vehicle
  air: ['A', 'MF---'],       // fixed-wing aircraft
  person: ['G', 'UCI--'],    // dismounted person
  other: ['G', 'E----'],     // equipment
};
export function truthSidc(force, kind) {
  const a = TRUTH_AFFIL[force] || 'U';
  const k = TRUTH_KIND[kind] || TRUTH_KIND.other;
  return 'S' + a + k[0] + 'P' + k[1] + '-----';
}
