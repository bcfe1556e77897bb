/*
 * app.js — the browser front end of the mscgs ground station (served by
 * stationd): a tactical map of the exercise in its local east/north metre
 * frame, the operator's intercept and flight controls, the intercept status
 * and the imaging sensor's latest frame.
 *
 * It speaks JSON over one WebSocket (/ws): the server sends `hello` once per
 * connection and the whole picture (`state`) at about 5 Hz; the page sends
 * operator commands and cursor MGRS look-ups, each with a `req` number.
 *
 * Drawing uses OpenLayers (global `ol`, full build) and milsymbol (global
 * `ms`). Features are kept by key and updated in place, styles are shared,
 * symbol images are built once and hits are drawn in bulk, so a full state
 * of thousands of hits and tracks is applied well within one 5 Hz update.
 *
 * Plain ES2017, classic script, no modules.
 */
(function () {
  'use strict';

  // ---------------------------------------------------------------------------
  // Constants

  const PICK_PX = 10;                  // designation: click tolerance, pixels
  const LEADER_S = 60;                 // track leader: metres per (m/s)
  const LEADER_MIN_M = 150;
  const LEADER_MAX_M = 2000;
  const UAV_LEADER_S = 30;             // UAV leader: 30 s of flight
  const UAV_LEADER_MIN_M = 300;
  const UAV_LEADER_MAX_M = 2500;
  const MGRS_INTERVAL_MS = 100;        // at most 10 cursor look-ups a second
  const RECONNECT_MIN_MS = 1000;
  const RECONNECT_MAX_MS = 5000;
  const FALLBACK_HALF_M = 500000;      // map extent without relief: ±500 km
  const EDIT_HOLD_MS = 3000;           // a select the operator just changed is not overwritten for this long, at most
  const APPLY_KEEP = 1000;             // apply times kept for the benchmark
  const REPLIES_KEEP = 1000;

  const SIDC_TRACK_UNKNOWN = 'SUGPE----------';
  const SIDC_TRACK_FRIEND = 'SFGPE----------';
  const SIDC_UAV = 'SFAPMFQ--------';

  const C_PURPLE = '#a020f0';
  const C_BCIS = '#1e64ff';
  const C_CURRENT = '#ffd700';

  // Intercept phases in which the UAV is working on a target.
  const ACTIVE_PHASES = new Set(['TO_SECONDARY', 'TO_WAYPOINT', 'APPROACH', 'PRECISION', 'OVERFLIGHT']);

  // ---------------------------------------------------------------------------
  // Test and benchmark hooks

  const cgs = {
    hello: null,
    state: null,
    ready: false,
    stats: { updates: 0, applyMs: [], replies: [] },
    map: null,
    pixelOf: function (e, n) {
      const p = cgs.map.getPixelFromCoordinate([e, n]);
      if (!p) return null;
      const r = cgs.map.getTargetElement().getBoundingClientRect();
      return [p[0] + r.left, p[1] + r.top];
    },
  };
  window.cgs = cgs;

  // ---------------------------------------------------------------------------
  // Small helpers

  const $ = (id) => document.getElementById(id);

  // Set an element's text only when it changes (no needless layout work).
  function setText(el, s) {
    if (el.textContent !== s) el.textContent = s;
  }

  function num(x, d) {
    return typeof x === 'number' && isFinite(x) ? x : d;
  }

  function clamp(x, lo, hi) {
    return x < lo ? lo : x > hi ? hi : x;
  }

  // Two flat number arrays hold the same values.
  function sameArray(a, b) {
    if (a === b) return true;
    if (!a || !b || a.length !== b.length) return false;
    for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
    return true;
  }

  // Flat [x0,y0,x1,y1,...] to [[x0,y0],[x1,y1],...].
  function pairs(flat) {
    const out = [];
    for (let i = 0; i + 1 < flat.length; i += 2) out.push([flat[i], flat[i + 1]]);
    return out;
  }

  function evenFlat(xy) {
    if (!Array.isArray(xy)) return [];
    return xy.length % 2 ? xy.slice(0, xy.length - 1) : xy;
  }

  function fmtRange(m) {
    if (typeof m !== 'number' || !isFinite(m) || m < 0) return '—';
    if (m >= 1000) return (m / 1000).toFixed(1) + ' km';
    return Math.round(m) + ' m';
  }

  function fmtTtg(s) {
    if (typeof s !== 'number' || !isFinite(s) || s < 0) return '—';
    const t = Math.round(s);
    if (t < 60) return t + ' s';
    const m = Math.floor(t / 60);
    const r = t % 60;
    return m + ' min ' + (r < 10 ? '0' : '') + r + ' s';
  }

  function fmtSimTime(s) {
    if (typeof s !== 'number' || !isFinite(s)) return '—';
    const neg = s < 0;
    let t = Math.abs(s);
    const h = Math.floor(t / 3600);
    t -= h * 3600;
    const m = Math.floor(t / 60);
    t -= m * 60;
    const p2 = (v) => (v < 10 ? '0' : '') + v;
    return (neg ? '-' : '') + 'T ' + p2(h) + ':' + p2(m) + ':' + (t < 10 ? '0' : '') + t.toFixed(1);
  }

  // End of a leader from (e, n) along a compass heading (clockwise from north).
  function leaderEnd(e, n, headingDeg, len) {
    const a = headingDeg * Math.PI / 180;
    return [e + Math.sin(a) * len, n + Math.cos(a) * len];
  }

  // ---------------------------------------------------------------------------
  // Shared styles (one object per look, never one per feature or update)

  const S = {};

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

  S.route = [
    new ol.style.Style({ stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.45)', width: 5 }) }),
    new ol.style.Style({ stroke: new ol.style.Stroke({ color: C_PURPLE, width: 3 }) }),
  ];
  S.waypoint = new ol.style.Style({
    image: new ol.style.Circle({
      radius: 5,
      fill: new ol.style.Fill({ color: C_PURPLE }),
      stroke: new ol.style.Stroke({ color: '#ffffff', width: 1.5 }),
    }),
    text: new ol.style.Text({
      text: 'WP', font: 'bold 10px sans-serif', offsetY: -12,
      fill: new ol.style.Fill({ color: '#e6c8ff' }),
      stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.67)', width: 3 }),
    }),
  });
  S.secondary = new ol.style.Style({
    image: new ol.style.RegularShape({
      points: 4, radius: 5, angle: Math.PI / 4,
      fill: new ol.style.Fill({ color: '#ffffff' }),
      stroke: new ol.style.Stroke({ color: C_PURPLE, width: 2 }),
    }),
    text: new ol.style.Text({
      text: 'P2', font: 'bold 10px sans-serif', offsetY: -12,
      fill: new ol.style.Fill({ color: '#e6c8ff' }),
      stroke: new ol.style.Stroke({ color: 'rgba(0,0,0,0.67)', width: 3 }),
    }),
  });

  // Ring around the designated track.
  S.target = new ol.style.Style({
    image: new ol.style.Circle({
      radius: 17,
      stroke: new ol.style.Stroke({ color: C_PURPLE, width: 3 }),
    }),
  });

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
  const FORCE_COLORS = { friendly: '#4f9dff', opposing: '#ff4040', neutral: '#40d040', other: '#ffd700' };

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

  function family(sidc, size, color, room) {
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
  function symbolIcon(owner, sidc, size, label, opacity, color, room) {
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
  function releaseSymbols(owner) {
    if (!owner.cells) return;
    owner.cells.forEach((entry) => {
      if (entry.cell.fam) entry.cell.fam.free.push(entry.cell);
    });
    owner.cells.clear();
  }

  const ROOM_TRACK = '0000000';         // track ids
  const ROOM_NAME = 'WWWWWW 000 (ext)'; // markings (11 characters in DIS) and UAV names

  // SIDC of a ground-truth entity by force and kind.
  const TRUTH_AFFIL = { friendly: 'F', opposing: 'H', neutral: 'N', other: 'U' };
  const TRUTH_KIND = {
    tracked: ['G', 'EVAT-'],   // armoured tracked vehicle
    wheeled: ['G', 'EVU--'],   // utility (wheeled) vehicle
    air: ['A', 'MF---'],       // fixed-wing aircraft
    person: ['G', 'UCI--'],    // dismounted person
    other: ['G', 'E----'],     // equipment
  };
  function truthSidc(force, kind) {
    const a = TRUTH_AFFIL[force] || 'U';
    const k = TRUTH_KIND[kind] || TRUTH_KIND.other;
    return 'S' + a + k[0] + 'P' + k[1] + '-----';
  }

  // ---------------------------------------------------------------------------
  // Map and layers (bottom to top)

  // All vector layers draw into the map's one canvas. (A layer rendered to
  // an image of its own, ol.layer.VectorImage, costs more to compose each
  // time its content changes than plainly drawing the hits every update.)
  function vectorLayer(name, style, extra, LayerClass) {
    // Features that move at every update skip the spatial index: rebalancing
    // it costs more than drawing the few thousand features outright.
    const opts = { source: new ol.source.Vector({ wrapX: false, useSpatialIndex: false }), style: style };
    if (extra) Object.assign(opts, extra);
    const layer = new (LayerClass || ol.layer.Vector)(opts);
    layer.set('name', name);
    return layer;
  }

  const L = {
    relief: new ol.layer.Image({ source: null }),
    truth: vectorLayer('truth', null, { visible: false }),
    footprint: vectorLayer('footprint', null),
    route: vectorLayer('route', null),
    hitsOld: vectorLayer('hits-old', S.hitOld),
    bcis: vectorLayer('bcis', function (f) {
      S.bcis.getText().setText(f.cgsLabel || '');
      return S.bcis;
    }),
    hitsCurrent: vectorLayer('hits-current', S.hitCurrent),
    target: vectorLayer('target', S.target),
    tracks: vectorLayer('tracks', null),
    uav: vectorLayer('uav', null),
  };
  L.relief.set('name', 'relief');

  // Per-feature styles stored on the feature (`cgsStyle`), shared objects.
  const featureStyle = (f) => f.cgsStyle;
  L.truth.setStyle(featureStyle);
  L.footprint.setStyle(featureStyle);
  L.route.setStyle(featureStyle);
  L.tracks.setStyle(featureStyle);
  L.uav.setStyle(featureStyle);

  const src = {};
  Object.keys(L).forEach((k) => { if (k !== 'relief') src[k] = L[k].getSource(); });

  function makeView(extent) {
    const proj = new ol.proj.Projection({ code: 'CGS-LOCAL', units: 'm', extent: extent });
    const w = Math.max(ol.extent.getWidth(extent), ol.extent.getHeight(extent));
    return new ol.View({
      projection: proj,
      center: ol.extent.getCenter(extent),
      resolution: w / 1000,
      maxResolution: Math.max(w / 256, 50),
      minResolution: 0.05,
    });
  }

  const map = new ol.Map({
    target: 'map',
    layers: [L.relief, L.truth, L.footprint, L.route, L.hitsOld, L.bcis, L.hitsCurrent,
      L.target, L.tracks, L.uav],
    controls: [new ol.control.Zoom(), new ol.control.ScaleLine({ units: 'metric' })],
    view: makeView([-FALLBACK_HALF_M, -FALLBACK_HALF_M, FALLBACK_HALF_M, FALLBACK_HALF_M]),
  });
  map.getView().setResolution(50);
  cgs.map = map;

  let reliefKey = null;      // url + extent of the relief shown
  let viewFitted = false;    // the view was fitted once (first hello or first state)

  // Relief and view from a hello: fit only the first time (or when the
  // exercise's terrain changed), so the operator's pan and zoom survive a
  // reconnect.
  function applyRelief(relief) {
    const ok = relief && typeof relief.url === 'string' && Array.isArray(relief.extent) &&
      relief.extent.length === 4 && relief.extent[2] > relief.extent[0] && relief.extent[3] > relief.extent[1];
    if (!ok) {
      if (reliefKey !== null) {
        L.relief.setSource(null);
        reliefKey = null;
      }
      return;
    }
    const key = relief.url + '|' + relief.extent.join(',');
    if (key === reliefKey) return;
    const extent = relief.extent.slice();
    const view = makeView(extent);
    map.setView(view);
    L.relief.setSource(new ol.source.ImageStatic({
      url: relief.url,
      imageExtent: extent,
      projection: view.getProjection(),
      interpolate: true,
    }));
    view.fit(extent, { size: map.getSize(), padding: [10, 10, 10, 10] });
    reliefKey = key;
    viewFitted = true;
  }

  // ---------------------------------------------------------------------------
  // Page state

  const ui = {
    connection: $('connection'),
    simTime: $('sim-time'),
    access: $('access'),
    uavRow: $('uav-row'),
    phase: $('status-phase'),
    target: $('status-target'),
    range: $('status-range'),
    ttg: $('status-ttg'),
    reason: $('status-reason'),
    uav: $('status-uav'),
    result: $('result'),
    cursor: $('cursor-mgrs'),
    cancel: $('cancel'),
    altInput: $('alt-input'),
    altSet: $('alt-set'),
    speedInput: $('speed-input'),
    speedSet: $('speed-set'),
    fpScale: $('fp-scale'),
    method: $('method'),
    image: $('sensor-image'),
    imageEmpty: $('image-empty'),
    imageCaption: $('image-caption'),
    sensorMti: $('sensor-mti'),
    sensorBcis: $('sensor-bcis'),
    showRoute: $('show-route'),
    showTracks: $('show-tracks'),
    truth: $('truth'),
  };
  const OPERATOR_CONTROLS = [ui.cancel, ui.altInput, ui.altSet, ui.speedInput, ui.speedSet, ui.fpScale, ui.method];

  let ws = null;
  let connected = false;
  let reconnectDelay = RECONNECT_MIN_MS;
  let reconnectTimer = 0;
  let reqSeq = 0;
  let operator = false;
  let selectedUav = null;     // uav_id commands go to
  let uavSelect = null;       // the #uav <select>, only with several UAVs
  let prefilledFor = null;    // UAV whose commanded values filled the inputs
  let imageFrame = null;
  // A select the operator just changed keeps its value until the server
  // reports it, the command is refused, or EDIT_HOLD_MS pass.
  const holdScale = { until: 0, want: null };
  const holdMethod = { until: 0, want: null };
  const pendingOps = new Map();   // req -> op of commands awaiting a reply

  function nextReq() {
    reqSeq += 1;
    return reqSeq;
  }

  function showResult(text, kind) {
    ui.result.textContent = text;
    ui.result.className = 'result ' + (kind || 'info');
  }

  // ---------------------------------------------------------------------------
  // Applying a state: keyed features, updated in place

  // Hit scans: one MultiPoint feature per uav_id:scan, in the current
  // (yellow) or the old (grey) source.
  const hitRecs = new Map();
  let hitGen = 0;

  function applyHits(hits) {
    hitGen += 1;
    for (let i = 0; i < hits.length; i++) {
      const h = hits[i];
      const key = h.uav_id + ':' + h.scan;
      const xy = evenFlat(h.xy);
      const current = h.current === true;
      let rec = hitRecs.get(key);
      if (!rec) {
        const f = new ol.Feature(xy.length ? new ol.geom.MultiPoint(xy, 'XY') : null);
        rec = { f: f, xy: xy, current: current, gen: hitGen };
        hitRecs.set(key, rec);
        (current ? src.hitsCurrent : src.hitsOld).addFeature(f);
        continue;
      }
      rec.gen = hitGen;
      if (!sameArray(rec.xy, xy)) {
        rec.f.setGeometry(xy.length ? new ol.geom.MultiPoint(xy, 'XY') : null);
        rec.xy = xy;
      }
      if (rec.current !== current) {
        (rec.current ? src.hitsCurrent : src.hitsOld).removeFeature(rec.f);
        (current ? src.hitsCurrent : src.hitsOld).addFeature(rec.f);
        rec.current = current;
      }
    }
    hitRecs.forEach((rec, key) => {
      if (rec.gen !== hitGen) {
        (rec.current ? src.hitsCurrent : src.hitsOld).removeFeature(rec.f);
        hitRecs.delete(key);
      }
    });
  }

  // Generic keyed sync: create(item) -> record, update(record, item), and
  // remove(record) for keys that vanished.
  function syncKeyed(recs, items, keyOf, create, update, remove) {
    const seen = new Set();
    for (let i = 0; i < items.length; i++) {
      const it = items[i];
      const key = keyOf(it);
      if (seen.has(key)) continue;
      seen.add(key);
      const rec = recs.get(key);
      if (rec) update(rec, it);
      else recs.set(key, create(it));
    }
    recs.forEach((rec, key) => {
      if (!seen.has(key)) {
        remove(rec);
        recs.delete(key);
      }
    });
  }

  // Move a point feature; true when it moved.
  function setPoint(f, e, n) {
    const g = f.getGeometry();
    const c = g.getCoordinates();
    if (c[0] === e && c[1] === n) return false;
    g.setCoordinates([e, n]);
    return true;
  }

  // A leader is a two-point LineString kept on its feature (`cgsLeader`) and
  // drawn by a style whose geometry it is, so a moving track is a single
  // feature change. True when the leader changed.
  function setLeader(f, e, n, end) {
    const g = f.cgsLeader;
    const c = g.getFlatCoordinates();
    if (c[0] === e && c[1] === n && c[2] === end[0] && c[3] === end[1]) return false;
    g.setCoordinates([[e, n], end]);
    return true;
  }

  function setStyle(f, style) {
    if (f.cgsStyle !== style) {
      f.cgsStyle = style;
      f.changed();
    }
  }

  // Tracks: a labelled 2525 symbol and a leader line per track id, styles
  // made once per track and look (identity, tentative or not).
  const trackRecs = new Map();

  function trackLook(t) {
    const friendly = t.identity === 'friendly';
    const faint = t.status === 'tentative';
    return (friendly ? 'F' : 'U') + (faint ? 't' : '');
  }

  // New labels composed per update: a first picture of a thousand tracks
  // shows them all at once, and their labels follow over the next updates.
  const LABELS_PER_UPDATE = 200;
  let labelBudget = 0;
  const plainTrackStyles = {};   // look -> unlabelled style, shared
  const plainOwner = {};

  function trackStyleParts(look) {
    const friendly = look[0] === 'F';
    const faint = look.length > 1;
    return {
      sidc: friendly ? SIDC_TRACK_FRIEND : SIDC_TRACK_UNKNOWN,
      opacity: faint ? 0.45 : 1,
      leader: S.leader[(friendly ? 'friendly' : 'unknown') + (faint ? 'Faint' : '')],
    };
  }

  // The track's style for a look; sets rec.unlabelled while it has to make
  // do with the shared unlabelled one.
  function trackStyle(rec, look) {
    let st = rec.styles[look];
    if (st) {
      rec.unlabelled = false;
      return st;
    }
    const p = trackStyleParts(look);
    if (labelBudget > 0) {
      labelBudget -= 1;
      st = [p.leader, new ol.style.Style({ image: symbolIcon(rec, p.sidc, 20, String(rec.id), p.opacity, '#ffffff', ROOM_TRACK) })];
      rec.styles[look] = st;
      rec.unlabelled = false;
      return st;
    }
    rec.unlabelled = true;
    st = plainTrackStyles[look];
    if (!st) {
      st = [p.leader, new ol.style.Style({ image: symbolIcon(plainOwner, p.sidc, 20, '', p.opacity, '#ffffff', ROOM_TRACK) })];
      plainTrackStyles[look] = st;
    }
    return st;
  }

  function trackLeaderEnd(t, e, n) {
    const len = clamp(num(t.speed_mps, 0) * LEADER_S, LEADER_MIN_M, LEADER_MAX_M);
    return leaderEnd(e, n, num(t.heading_deg, 0), len);
  }

  let newTracks = [];

  function createTrack(t) {
    const e = num(t.e, 0);
    const n = num(t.n, 0);
    const look = trackLook(t);
    const rec = { id: t.id, styles: {}, look: look };
    rec.f = new ol.Feature(new ol.geom.Point([e, n]));
    rec.f.cgsLeader = new ol.geom.LineString([[e, n], trackLeaderEnd(t, e, n)]);
    rec.f.cgsStyle = trackStyle(rec, look);
    newTracks.push(rec.f);
    return rec;
  }

  function updateTrack(rec, t) {
    const e = num(t.e, 0);
    const n = num(t.n, 0);
    const look = trackLook(t);
    let restyled = false;
    if (look !== rec.look || (rec.unlabelled && labelBudget > 0)) {
      rec.look = look;
      rec.f.cgsStyle = trackStyle(rec, look);
      restyled = true;
    }
    const turned = setLeader(rec.f, e, n, trackLeaderEnd(t, e, n));
    const moved = setPoint(rec.f, e, n);
    if (!moved && (turned || restyled)) rec.f.changed();
  }

  function removeTrack(rec) {
    src.tracks.removeFeature(rec.f);
    releaseSymbols(rec);
  }

  function applyTracks(tracks) {
    newTracks = [];
    labelBudget = LABELS_PER_UPDATE;
    syncKeyed(trackRecs, tracks, (t) => t.id, createTrack, updateTrack, removeTrack);
    // New features in one go.
    if (newTracks.length) src.tracks.addFeatures(newTracks);
  }

  // UAVs: symbol with name, leader along heading, loiter circle.
  const uavRecs = new Map();

  function uavLeaderEnd(u, e, n) {
    const v = num(u.ground_speed_mps, num(u.airspeed_mps, 0));
    const len = clamp(v * UAV_LEADER_S, UAV_LEADER_MIN_M, UAV_LEADER_MAX_M);
    return leaderEnd(e, n, num(u.heading_deg, 0), len);
  }

  function uavLoiterGeom(u) {
    const lo = u.loiter;
    if (u.mode !== 'loiter' || !lo || !(num(lo.radius_m, 0) > 0)) return null;
    return new ol.geom.Circle([num(lo.e, 0), num(lo.n, 0)], lo.radius_m);
  }

  function uavStyle(rec, name) {
    return S.uavLeader.concat([new ol.style.Style({ image: symbolIcon(rec, SIDC_UAV, 28, name, 1, '#cfe6ff', ROOM_NAME) })]);
  }

  function loiterKey(u) {
    const lo = u.loiter;
    return u.mode === 'loiter' && lo ? lo.e + ',' + lo.n + ',' + lo.radius_m : '';
  }

  function createUav(u) {
    const e = num(u.e, 0);
    const n = num(u.n, 0);
    const rec = { name: String(u.name || 'uav' + u.id) };
    rec.f = new ol.Feature(new ol.geom.Point([e, n]));
    rec.f.cgsLeader = new ol.geom.LineString([[e, n], uavLeaderEnd(u, e, n)]);
    rec.f.cgsStyle = uavStyle(rec, rec.name);
    rec.loiter = new ol.Feature(uavLoiterGeom(u));
    rec.loiter.cgsStyle = S.loiter;
    rec.loiterKey = loiterKey(u);
    src.uav.addFeatures([rec.loiter, rec.f]);
    return rec;
  }

  function updateUav(rec, u) {
    const e = num(u.e, 0);
    const n = num(u.n, 0);
    const name = String(u.name || 'uav' + u.id);
    if (name !== rec.name) {
      rec.name = name;
      setStyle(rec.f, uavStyle(rec, name));
    }
    const turned = setLeader(rec.f, e, n, uavLeaderEnd(u, e, n));
    if (!setPoint(rec.f, e, n) && turned) rec.f.changed();
    const lk = loiterKey(u);
    if (lk !== rec.loiterKey) {
      rec.loiterKey = lk;
      rec.loiter.setGeometry(uavLoiterGeom(u));
    }
  }

  function removeUav(rec) {
    src.uav.removeFeature(rec.f);
    src.uav.removeFeature(rec.loiter);
    releaseSymbols(rec);
  }

  // BCIS replies younger than the hello's timeout.
  const bcisRecs = new Map();

  function applyBcis(bcis) {
    const timeout = num(cgs.hello && cgs.hello.bcis_timeout_s, 5);
    const fresh = bcis.filter((b) => !(num(b.age_s, 0) >= timeout));
    syncKeyed(bcisRecs, fresh, (b) => b.uav_id + ':' + b.id, (b) => {
      const f = new ol.Feature(new ol.geom.Point([num(b.e, 0), num(b.n, 0)]));
      f.cgsLabel = b.marking || '';
      src.bcis.addFeature(f);
      return { f: f };
    }, (rec, b) => {
      setPoint(rec.f, num(b.e, 0), num(b.n, 0));
      const label = b.marking || '';
      if (rec.f.cgsLabel !== label) {
        rec.f.cgsLabel = label;
        rec.f.changed();
      }
    }, (rec) => src.bcis.removeFeature(rec.f));
  }

  // Ground truth (instructor view): only kept up to date while shown.
  const truthRecs = new Map();

  function truthLabel(t) {
    return String(t.marking || t.id) + (t.external ? ' (ext)' : '');
  }

  function truthStyle(rec, t) {
    const sidc = truthSidc(t.force, t.kind);
    let img;
    try {
      img = symbolIcon(rec, sidc, 16, truthLabel(t), 0.9, '#ffffff', ROOM_NAME);
    } catch (err) {
      img = new ol.style.Circle({ radius: 5, fill: new ol.style.Fill({ color: FORCE_COLORS[t.force] || '#fff' }) });
    }
    return new ol.style.Style({ image: img });
  }

  function truthKey(t) {
    return t.force + '|' + t.kind + '|' + truthLabel(t);
  }

  function applyTruth(truth) {
    const items = L.truth.getVisible() ? truth : [];
    syncKeyed(truthRecs, items, (t) => t.id, (t) => {
      const rec = { f: new ol.Feature(new ol.geom.Point([num(t.e, 0), num(t.n, 0)])), key: truthKey(t) };
      rec.f.cgsStyle = truthStyle(rec, t);
      src.truth.addFeature(rec.f);
      return rec;
    }, (rec, t) => {
      setPoint(rec.f, num(t.e, 0), num(t.n, 0));
      const k = truthKey(t);
      if (k !== rec.key) {
        rec.key = k;
        releaseSymbols(rec);
        setStyle(rec.f, truthStyle(rec, t));
      }
    }, (rec) => {
      src.truth.removeFeature(rec.f);
      releaseSymbols(rec);
    });
  }

  // Intercepts: footprint, route, waypoint, secondary waypoint and the
  // target ring, per UAV.
  const icptRecs = new Map();

  // Set a feature's geometry from a flat array (null: none), only on change.
  function setOptionalGeom(f, flat, make) {
    if (sameArray(f.cgsKey, flat)) return;
    f.cgsKey = flat;
    f.setGeometry(flat ? make(flat) : null);
  }

  function polygonOf(flat) {
    const ring = pairs(flat);
    ring.push(ring[0]);
    return new ol.geom.Polygon([ring]);
  }

  function applyIntercepts(intercepts) {
    syncKeyed(icptRecs, intercepts, (i) => i.uav_id, (i) => {
      const rec = {
        fp: new ol.Feature(), route: new ol.Feature(), wp: new ol.Feature(), sec: new ol.Feature(),
        ring: new ol.Feature(),
      };
      rec.fp.cgsStyle = S.footprint;
      rec.route.cgsStyle = S.route;
      rec.wp.cgsStyle = S.waypoint;
      rec.sec.cgsStyle = S.secondary;
      src.footprint.addFeature(rec.fp);
      src.route.addFeatures([rec.route, rec.sec, rec.wp]);
      src.target.addFeature(rec.ring);
      updateIntercept(rec, i);
      return rec;
    }, updateIntercept, (rec) => {
      src.footprint.removeFeature(rec.fp);
      src.route.removeFeature(rec.route);
      src.route.removeFeature(rec.sec);
      src.route.removeFeature(rec.wp);
      src.target.removeFeature(rec.ring);
    });
  }

  function validFlat(a, minLen) {
    return Array.isArray(a) && a.length >= minLen ? evenFlat(a) : null;
  }

  function updateIntercept(rec, i) {
    setOptionalGeom(rec.fp, validFlat(i.footprint_display, 6), polygonOf);
    setStyle(rec.fp, i.target_in_footprint ? S.footprintHit : S.footprint);
    setOptionalGeom(rec.route, validFlat(i.route, 4), (f) => new ol.geom.LineString(f, 'XY'));
    setOptionalGeom(rec.wp, validFlat(i.waypoint, 2), (f) => new ol.geom.Point([f[0], f[1]]));
    setOptionalGeom(rec.sec, validFlat(i.secondary, 2), (f) => new ol.geom.Point([f[0], f[1]]));
    // Ring on the designated track while the intercept is under way.
    const tr = ACTIVE_PHASES.has(i.state) ? trackRecs.get(i.track_id) : null;
    const at = tr ? tr.f.getGeometry().getCoordinates() : null;
    setOptionalGeom(rec.ring, at, (f) => new ol.geom.Point([f[0], f[1]]));
  }

  // ---------------------------------------------------------------------------
  // Panels

  function setOperator(isOperator) {
    operator = isOperator;
    OPERATOR_CONTROLS.forEach((el) => { el.disabled = !isOperator; });
    if (isOperator) {
      ui.access.hidden = true;
      ui.access.textContent = '';
    } else {
      ui.access.hidden = false;
      ui.access.textContent = 'view only: open the page with ?token=… to command';
    }
  }

  // The #uav selector exists only while there are several UAVs.
  function updateUavSelector(uavs) {
    if (uavs.length <= 1) {
      if (uavSelect) {
        uavSelect.remove();
        uavSelect = null;
        ui.uavRow.hidden = true;
      }
      return;
    }
    if (!uavSelect) {
      uavSelect = document.createElement('select');
      uavSelect.id = 'uav';
      uavSelect.addEventListener('change', () => {
        selectedUav = Number(uavSelect.value);
        prefilledFor = null;
        if (cgs.state) updatePanels(cgs.state);
      });
      ui.uavRow.appendChild(uavSelect);
      ui.uavRow.hidden = false;
    }
    const ids = uavs.map((u) => u.id + ':' + (u.name || '')).join(',');
    if (uavSelect.cgsIds !== ids) {
      uavSelect.cgsIds = ids;
      uavSelect.textContent = '';
      uavs.forEach((u) => {
        const o = document.createElement('option');
        o.value = String(u.id);
        o.textContent = u.name ? u.name + ' (' + u.id + ')' : 'UAV ' + u.id;
        uavSelect.appendChild(o);
      });
    }
    if (String(selectedUav) !== uavSelect.value) uavSelect.value = String(selectedUav);
  }

  function findBy(arr, field, value) {
    for (let i = 0; i < arr.length; i++) if (arr[i][field] === value) return arr[i];
    return null;
  }

  // A select follows the server unless the operator is on it or has just
  // changed it (see holdScale).
  function syncSelect(sel, value, hold) {
    if (value === undefined || value === null) return;
    const v = String(value);
    if (v === hold.want) hold.until = 0;
    if (document.activeElement === sel || performance.now() < hold.until) return;
    hold.want = null;
    if (sel.value !== v && Array.prototype.some.call(sel.options, (o) => o.value === v)) sel.value = v;
  }

  function updatePanels(st) {
    const uavs = st.uavs;
    if (selectedUav === null || !findBy(uavs, 'id', selectedUav)) selectedUav = uavs.length ? uavs[0].id : null;
    updateUavSelector(uavs);

    setText(ui.simTime, fmtSimTime(st.sim_time_s));

    const u = selectedUav === null ? null : findBy(uavs, 'id', selectedUav);
    const icpt = selectedUav === null ? null : findBy(st.intercepts, 'uav_id', selectedUav);

    // Pre-fill the flight inputs once per UAV from its commanded values.
    if (u && prefilledFor !== u.id) {
      prefilledFor = u.id;
      if (typeof u.cmd_alt_agl_m === 'number') ui.altInput.value = String(Math.round(u.cmd_alt_agl_m));
      if (typeof u.cmd_airspeed_mps === 'number') ui.speedInput.value = String(Math.round(u.cmd_airspeed_mps * 10) / 10);
    }

    // An intercept under way shows its target; one that ended (or none) does not.
    const ENDED = { IDLE: 1, DONE: 1, CANCELLED: 1, LOST: 1 };
    const busy = !!(icpt && icpt.state && !ENDED[icpt.state]);
    let phase = '—';
    if (icpt && icpt.state && icpt.state !== 'IDLE') phase = icpt.state;
    else if (u) phase = String(u.mode || 'loiter').toUpperCase();
    setText(ui.phase, phase);
    setText(ui.target, busy && icpt.track_id ? 'track ' + icpt.track_id : '—');
    setText(ui.range, icpt && busy ? fmtRange(icpt.range_m) : '—');
    setText(ui.ttg, icpt && busy ? fmtTtg(icpt.time_to_go_s) : '—');
    let reason = icpt && icpt.reason ? icpt.reason : '—';
    if (icpt && busy && icpt.replans) reason += ' (re-plans: ' + icpt.replans + ')';
    setText(ui.reason, reason);
    if (u) {
      const alt = Math.round(num(u.alt_agl_m, 0)) + ' m AGL';
      const spd = Math.round(num(u.airspeed_mps, 0)) + ' m/s';
      setText(ui.uav, (u.name || 'uav' + u.id) + ' · ' + alt + ' · ' + spd + ' · ' + (u.mode || '—'));
      ui.uav.title = 'commanded ' + Math.round(num(u.cmd_alt_agl_m, 0)) + ' m AGL, ' +
        Math.round(num(u.cmd_airspeed_mps, 0)) + ' m/s; heading ' + Math.round(num(u.heading_deg, 0)) + '°';
    } else {
      setText(ui.uav, '—');
    }

    if (icpt) {
      syncSelect(ui.fpScale, icpt.scale, holdScale);
      syncSelect(ui.method, icpt.method, holdMethod);
    }
  }

  // The latest imaging-sensor frame: a new src only for a new frame.
  function updateImage(img) {
    if (!img || !img.url) {
      if (imageFrame !== null) {
        imageFrame = null;
        ui.image.hidden = true;
        ui.image.removeAttribute('src');
        ui.imageEmpty.hidden = false;
        setText(ui.imageCaption, '—');
        ui.imageCaption.className = '';
      }
      return;
    }
    if (img.frame !== imageFrame) {
      imageFrame = img.frame;
      ui.image.src = img.url;
      ui.image.hidden = false;
      ui.imageEmpty.hidden = true;
    }
    const cap = 'frame ' + img.frame + ' · ' + (img.mode || '—') + ' · uav ' + img.uav_id +
      (img.target_in_view ? ' · target in view' : '');
    setText(ui.imageCaption, cap);
    ui.imageCaption.className = img.target_in_view ? 'in-view' : '';
  }

  // ---------------------------------------------------------------------------
  // Messages

  function arr(x) {
    return Array.isArray(x) ? x : [];
  }

  function applyState(st) {
    st.uavs = arr(st.uavs);
    st.hits = arr(st.hits);
    st.bcis = arr(st.bcis);
    st.tracks = arr(st.tracks);
    st.intercepts = arr(st.intercepts);
    st.truth = arr(st.truth);
    cgs.state = st;

    applyHits(st.hits);
    applyBcis(st.bcis);
    applyTracks(st.tracks);
    applyUavs(st.uavs);
    applyIntercepts(st.intercepts);
    applyTruth(st.truth);

    // Without relief, centre on the first UAV once.
    if (!viewFitted && st.uavs.length) {
      map.getView().setCenter([num(st.uavs[0].e, 0), num(st.uavs[0].n, 0)]);
      viewFitted = true;
    }

    updatePanels(st);
    updateImage(st.image);
  }

  function applyUavs(uavs) {
    syncKeyed(uavRecs, uavs, (u) => u.id, createUav, updateUav, removeUav);
  }

  function onHello(h) {
    cgs.hello = h;
    applyRelief(h.relief);
    setOperator(h.operator === true);
  }

  function onReply(m) {
    cgs.stats.replies.push(m);
    if (cgs.stats.replies.length > REPLIES_KEEP) cgs.stats.replies.shift();
    const op = m.op || pendingOps.get(m.req) || 'command';
    pendingOps.delete(m.req);
    if (!m.ok && op === 'footprint_scale') holdScale.until = 0;
    if (!m.ok && op === 'intercept_mode') holdMethod.until = 0;
    if (m.ok) showResult(op + ': ' + (m.detail || 'ok'), 'ok');
    else showResult('refused: ' + (m.error || 'no reason given'), 'err');
  }

  function onMessage(ev) {
    const t0 = performance.now();
    lastMessageAt = t0;
    let m;
    try {
      m = JSON.parse(ev.data);
    } catch (err) {
      console.warn('bad message from the server', err);
      return;
    }
    if (!m || typeof m !== 'object') return;
    switch (m.type) {
      case 'state':
        try {
          applyState(m);
        } catch (err) {
          // A picture the page cannot use must not stop the next ones.
          console.error('state ' + m.seq + ' not fully applied:', err);
        }
        map.renderSync();
        cgs.stats.updates += 1;
        cgs.stats.applyMs.push(performance.now() - t0);
        if (cgs.stats.applyMs.length > APPLY_KEEP) cgs.stats.applyMs.shift();
        cgs.ready = true;
        break;
      case 'hello':
        onHello(m);
        break;
      case 'reply':
        onReply(m);
        break;
      case 'mgrs':
        onMgrs(m);
        break;
      case 'error':
        showResult('error: ' + (m.error || 'protocol error'), 'err');
        break;
      default:
        break;
    }
  }

  // ---------------------------------------------------------------------------
  // Connection

  function wsUrl() {
    const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
    let url = proto + '//' + location.host + '/ws';
    const token = new URLSearchParams(location.search).get('token');
    if (token) url += '?token=' + encodeURIComponent(token);
    return url;
  }

  function setConnection(text, kind) {
    setText(ui.connection, text);
    ui.connection.className = 'conn conn-' + kind;
    document.body.classList.toggle('offline', kind !== 'up');
  }

  function connect() {
    reconnectTimer = 0;
    setConnection('connecting…', 'wait');
    let sock;
    try {
      sock = new WebSocket(wsUrl());
    } catch (err) {
      scheduleReconnect();
      return;
    }
    ws = sock;
    sock.onopen = () => {
      connected = true;
      lastMessageAt = performance.now();
      reconnectDelay = RECONNECT_MIN_MS;
      setConnection('connected', 'up');
    };
    sock.onmessage = onMessage;
    sock.onerror = () => { /* followed by close */ };
    sock.onclose = () => {
      if (ws !== sock) return;
      ws = null;
      connected = false;
      pendingOps.clear();
      scheduleReconnect();
    };
  }

  // A link that went quiet (the server gave up on this page, or the network
  // dropped it without a close) is closed and opened again: pictures come at
  // push_hz, so several missed in a row mean the picture is frozen.
  let lastMessageAt = 0;
  setInterval(() => {
    const hz = cgs.hello && cgs.hello.push_hz > 0 ? cgs.hello.push_hz : 5;
    const quiet = Math.max(3000, 6000 / hz);
    if (ws && connected && performance.now() - lastMessageAt > quiet) {
      setConnection('no pictures for ' + Math.round(quiet / 1000) + ' s · reconnecting', 'wait');
      ws.close();
    }
  }, 1000);

  function scheduleReconnect() {
    if (reconnectTimer) return;
    const delay = reconnectDelay;
    reconnectDelay = Math.min(RECONNECT_MAX_MS, reconnectDelay * 2);
    setConnection('disconnected · retry in ' + Math.round(delay / 1000) + ' s', 'down');
    reconnectTimer = setTimeout(connect, delay);
  }

  function send(obj) {
    if (!ws || !connected || ws.readyState !== WebSocket.OPEN) return false;
    ws.send(JSON.stringify(obj));
    return true;
  }

  // An operator command to the selected UAV; its reply lands in #result.
  function command(op, extra) {
    if (!operator) {
      showResult('view only: open the page with ?token=… to command', 'err');
      return;
    }
    if (!connected) {
      showResult(op + ': not connected', 'err');
      return;
    }
    if (selectedUav === null) {
      showResult(op + ': no UAV yet', 'err');
      return;
    }
    const req = nextReq();
    const msg = Object.assign({ op: op, req: req, uav_id: selectedUav }, extra || {});
    pendingOps.set(req, op);
    send(msg);
    showResult(op + ': sent…', 'pending');
  }

  // ---------------------------------------------------------------------------
  // Cursor MGRS: at most one look-up per 100 ms, always for the latest
  // position; only the answer to the newest look-up is shown.

  let mgrsWanted = null;     // [e, n] not yet sent
  let mgrsLastSent = -Infinity;
  let mgrsTimer = 0;
  let mgrsLatestReq = 0;
  const mgrsPos = new Map(); // req -> [e, n]

  function enText(p) {
    return 'E ' + Math.round(p[0]) + ' N ' + Math.round(p[1]);
  }

  function onPointerMove(coord) {
    mgrsWanted = [Math.round(coord[0] * 10) / 10, Math.round(coord[1] * 10) / 10];
    if (!connected) {
      setText(ui.cursor, enText(mgrsWanted));
      return;
    }
    if (mgrsTimer) return;
    const wait = mgrsLastSent + MGRS_INTERVAL_MS - performance.now();
    if (wait <= 0) sendMgrs();
    else mgrsTimer = setTimeout(() => { mgrsTimer = 0; sendMgrs(); }, wait);
  }

  function sendMgrs() {
    if (!mgrsWanted || !connected) return;
    const p = mgrsWanted;
    mgrsWanted = null;
    const req = nextReq();
    if (!send({ op: 'mgrs', req: req, e: p[0], n: p[1] })) return;
    mgrsLastSent = performance.now();
    mgrsLatestReq = req;
    mgrsPos.set(req, p);
    if (mgrsPos.size > 50) mgrsPos.delete(mgrsPos.keys().next().value);
  }

  function onMgrs(m) {
    const p = mgrsPos.get(m.req);
    mgrsPos.delete(m.req);
    if (m.req !== mgrsLatestReq || !p) return;
    setText(ui.cursor, enText(p) + ' · ' + (m.error ? 'MGRS: ' + m.error : m.mgrs));
  }

  // ---------------------------------------------------------------------------
  // Designation: the nearest current (yellow) hit within PICK_PX of the
  // click, sent by its id: guidanced designates the track that took it, or
  // says why not (a false alarm, a tentative or friendly track, a stale hit).

  function nearestCurrentHit(coord) {
    const st = cgs.state;
    if (!st || !L.hitsCurrent.getVisible()) return null;
    const res = map.getView().getResolution();
    const tol = PICK_PX * res;
    let best = tol * tol;
    let hit = null;
    for (let i = 0; i < st.hits.length; i++) {
      const h = st.hits[i];
      if (h.current !== true) continue;
      const xy = h.xy;
      if (!Array.isArray(xy)) continue;
      const ids = Array.isArray(h.ids) ? h.ids : [];
      for (let k = 0; k + 1 < xy.length; k += 2) {
        const dx = xy[k] - coord[0];
        const dy = xy[k + 1] - coord[1];
        const d2 = dx * dx + dy * dy;
        if (d2 <= best) {
          best = d2;
          hit = { xy: [xy[k], xy[k + 1]], id: ids[k / 2], radar: h.uav_id };
        }
      }
    }
    return hit;
  }

  map.on('singleclick', (ev) => {
    const hit = nearestCurrentHit(ev.coordinate);
    if (!hit) {
      showResult('click a yellow MTI hit (the current scan\'s) to designate its track', 'info');
      return;
    }
    // Never a point instead: that would designate whatever track is nearest.
    if (!Number.isInteger(hit.id) || hit.id <= 0) {
      showResult('this hit has no id to designate by (stationd sent none)', 'err');
      return;
    }
    command('designate', { hit: hit.id, radar: hit.radar });
  });

  map.on('pointermove', (ev) => {
    if (ev.dragging) return;
    onPointerMove(ev.coordinate);
    const over = !!nearestCurrentHit(ev.coordinate);
    map.getTargetElement().style.cursor = over ? 'crosshair' : '';
  });

  // ---------------------------------------------------------------------------
  // Controls

  ui.cancel.addEventListener('click', () => command('cancel'));

  function setValue(op, input) {
    const v = Number(input.value);
    if (input.value === '' || !isFinite(v) || v <= 0) {
      showResult(op + ': enter a positive number', 'err');
      return;
    }
    command(op, { value: v });
  }
  ui.altSet.addEventListener('click', () => setValue('altitude', ui.altInput));
  ui.speedSet.addEventListener('click', () => setValue('speed', ui.speedInput));
  ui.altInput.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setValue('altitude', ui.altInput); });
  ui.speedInput.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setValue('speed', ui.speedInput); });

  ui.fpScale.addEventListener('change', () => {
    holdScale.until = performance.now() + EDIT_HOLD_MS;
    holdScale.want = ui.fpScale.value;
    command('footprint_scale', { value: Number(ui.fpScale.value) });
  });
  ui.method.addEventListener('change', () => {
    holdMethod.until = performance.now() + EDIT_HOLD_MS;
    holdMethod.want = ui.method.value;
    command('intercept_mode', { value: ui.method.value });
  });

  function bindLayerToggle(box, layers, after) {
    const apply = () => {
      layers.forEach((l) => l.setVisible(box.checked));
      if (after) after();
    };
    box.addEventListener('change', apply);
    apply();
  }
  // MTI in the Sensors menu hides every symbol the radar's hits give: the
  // hits, the tracks and the designated target's marker; Show Tracks hides
  // the tracks and the marker alone.
  const applyMtiLayers = () => {
    const mti = ui.sensorMti.checked;
    L.hitsOld.setVisible(mti);
    L.hitsCurrent.setVisible(mti);
    L.tracks.setVisible(mti && ui.showTracks.checked);
    L.target.setVisible(mti && ui.showTracks.checked);
  };
  ui.sensorMti.addEventListener('change', applyMtiLayers);
  ui.showTracks.addEventListener('change', applyMtiLayers);
  applyMtiLayers();
  bindLayerToggle(ui.sensorBcis, [L.bcis]);
  bindLayerToggle(ui.showRoute, [L.route]);
  bindLayerToggle(ui.truth, [L.truth], () => {
    if (cgs.state) {
      applyTruth(cgs.state.truth);
      map.render();
    }
  });

  // ---------------------------------------------------------------------------
  // Start

  // Draw the common symbols before the first picture arrives.
  [SIDC_TRACK_UNKNOWN, SIDC_TRACK_FRIEND].forEach((sidc) => {
    symbolIcon(plainOwner, sidc, 20, '', 1, '#ffffff', ROOM_TRACK);
    family(sidc, 20, '#ffffff', ROOM_TRACK);
  });
  family(SIDC_UAV, 28, '#cfe6ff', ROOM_NAME);

  setOperator(false);
  ui.access.hidden = true;   // until the hello says otherwise
  connect();
})();
