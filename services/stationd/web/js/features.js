/*
 * features.js — a state applied to the map's layers: hit scans, tracks,
 * UAVs, BCIS replies, ground truth and intercepts (footprint, route,
 * waypoints, target ring), each kept by key and updated in place, so a full
 * state of thousands of hits and tracks is applied well within one 5 Hz
 * update.
 */
import { cgs } from './hooks.js';
import { L, src } from './layers.js';
import {
  FORCE_COLORS, ROOM_NAME, ROOM_TRACK, S, SIDC_TRACK_FRIEND, SIDC_TRACK_UNKNOWN, SIDC_UAV, family, releaseSymbols,
  symbolIcon, truthSidc,
} from './symbols.js';
import { clamp, evenFlat, num, pairs, sameArray } from './util.js';

const LEADER_S = 60;                 // track leader: metres per (m/s)
const LEADER_MIN_M = 150;
const LEADER_MAX_M = 2000;
const UAV_LEADER_S = 30;             // UAV leader: 30 s of flight
const UAV_LEADER_MIN_M = 300;
const UAV_LEADER_MAX_M = 2500;

// Intercept phases in which the UAV is working on a target.
const ACTIVE_PHASES = new Set(['TO_SECONDARY', 'TO_WAYPOINT', 'APPROACH', 'PRECISION', 'OVERFLIGHT']);

// End of a leader from (e, n) along a compass heading (clockwise from north).
function leaderEnd(e, n, headingDeg, len) {
  const a = headingDeg * Math.PI / 180;
  return [e + Math.sin(a) * len, n + Math.cos(a) * len];
}

// Hit scans: one MultiPoint feature per uav_id:scan, in the current
// (yellow) or the old (grey) source.
const hitRecs = new Map();
let hitGen = 0;

export function applyHits(hits) {
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

export function applyTracks(tracks) {
  newTracks = [];
  labelBudget = LABELS_PER_UPDATE;
  syncKeyed(trackRecs, tracks, (t) => t.id, createTrack, updateTrack, removeTrack);
  // New features in one go.
  if (newTracks.length) src.tracks.addFeatures(newTracks);
}

// UAVs: symbol with name, leader along heading, loiter circle, and where
// the camera stares (staring at a point or at the target).
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

// The stare point shown: [e, n, atLimit] or null.
function stareOf(u) {
  const c = u.camera;
  if (!c || c.stare === 'off' || !Array.isArray(c.stare_point) || c.stare_point.length < 2) return null;
  return [num(c.stare_point[0], 0), num(c.stare_point[1], 0), c.at_gimbal_limit === true ? 1 : 0];
}

function updateStare(rec, u) {
  const p = stareOf(u);
  setOptionalGeom(rec.stare, p, (f) => new ol.geom.Point([f[0], f[1]]));
  setStyle(rec.stare, p && p[2] ? S.stareLimit : S.stare);
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
  rec.stare = new ol.Feature();
  rec.stare.cgsStyle = S.stare;
  updateStare(rec, u);
  src.uav.addFeatures([rec.loiter, rec.stare, rec.f]);
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
  updateStare(rec, u);
}

function removeUav(rec) {
  src.uav.removeFeature(rec.f);
  src.uav.removeFeature(rec.loiter);
  src.uav.removeFeature(rec.stare);
  releaseSymbols(rec);
}

export function applyUavs(uavs) {
  syncKeyed(uavRecs, uavs, (u) => u.id, createUav, updateUav, removeUav);
}

// BCIS replies younger than the hello's timeout.
const bcisRecs = new Map();

export function applyBcis(bcis) {
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

export function applyTruth(truth) {
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

export function applyIntercepts(intercepts) {
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

// Draw the common symbols before the first picture arrives.
export function preloadSymbols() {
  [SIDC_TRACK_UNKNOWN, SIDC_TRACK_FRIEND].forEach((sidc) => {
    symbolIcon(plainOwner, sidc, 20, '', 1, '#ffffff', ROOM_TRACK);
    family(sidc, 20, '#ffffff', ROOM_TRACK);
  });
  family(SIDC_UAV, 28, '#cfe6ff', ROOM_NAME);
}
