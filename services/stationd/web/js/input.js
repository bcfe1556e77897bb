/*
 * input.js — what the operator does: clicks on the map (designation by a
 * current hit's id, or, after "At point…", the point the camera is to stare
 * at), the cursor's MGRS read-out, the command buttons, inputs and selects,
 * the imaging sensor's mode and camera controls, and the Sensors and Map
 * Features check boxes.
 */
import { applyTruth } from './features.js';
import { cgs } from './hooks.js';
import { L, map, showLayer, showMti } from './layers.js';
import { isConnected, nextReq, request, send } from './net.js';
import { canCommand, holdEdit, selectedUavId, showResult, ui } from './panels.js';
import { setText } from './util.js';

const PICK_PX = 10;                  // designation: click tolerance, pixels
const MGRS_INTERVAL_MS = 100;        // at most 10 cursor look-ups a second
// The camera's values the page sends (the server refuses what is outside
// the scenario's limits, with the reason).
const DEPRESSION_MIN_DEG = 0;
const DEPRESSION_MAX_DEG = 90;
const FOV_MIN_DEG = 0.1;
const FOV_MAX_DEG = 90;

// An operator command to the selected UAV; its reply lands in #result.
function command(op, extra) {
  if (!canCommand()) {
    showResult('view only: open the page with ?token=… to command', 'err');
    return;
  }
  if (!isConnected()) {
    showResult(op + ': not connected', 'err');
    return;
  }
  if (selectedUavId() === null) {
    showResult(op + ': no UAV yet', 'err');
    return;
  }
  request(op, Object.assign({ uav_id: selectedUavId() }, extra || {}));
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
  if (!isConnected()) {
    setText(ui.cursor, enText(mgrsWanted));
    return;
  }
  if (mgrsTimer) return;
  const wait = mgrsLastSent + MGRS_INTERVAL_MS - performance.now();
  if (wait <= 0) sendMgrs();
  else mgrsTimer = setTimeout(() => { mgrsTimer = 0; sendMgrs(); }, wait);
}

function sendMgrs() {
  if (!mgrsWanted || !isConnected()) return;
  const p = mgrsWanted;
  mgrsWanted = null;
  const req = nextReq();
  if (!send({ op: 'mgrs', req: req, e: p[0], n: p[1] })) return;
  mgrsLastSent = performance.now();
  mgrsLatestReq = req;
  mgrsPos.set(req, p);
  if (mgrsPos.size > 50) mgrsPos.delete(mgrsPos.keys().next().value);
}

// The answer to a look-up: shown only for the newest.
export function onMgrs(m) {
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

// ---------------------------------------------------------------------------
// Controls

// A value from an input: a positive number, or the reason it is not.
function setValue(op, input) {
  const v = Number(input.value);
  if (input.value === '' || !isFinite(v) || v <= 0) {
    showResult(op + ': enter a positive number', 'err');
    return;
  }
  command(op, { value: v });
}

// A camera setting from an input: a number within [lo, hi] degrees, or the
// reason it is not (nothing sent).
function setCamera(field, what, input, lo, hi) {
  const v = Number(input.value);
  if (input.value === '' || !isFinite(v) || v < lo || v > hi) {
    showResult('camera: the ' + what + ' must be a number of degrees from ' + lo + ' to ' + hi, 'err');
    return;
  }
  command('camera', { [field]: v });
}

// "At point…": the next click on the map is where the camera stares.
let stareArmed = false;

function armStare(on) {
  stareArmed = on;
  ui.starePoint.setAttribute('aria-pressed', on ? 'true' : 'false');
  map.getTargetElement().classList.toggle('picking', on);
  map.getTargetElement().style.cursor = on ? 'crosshair' : '';
}

// A check box that shows or hides with apply(checked), applied at once.
function bindToggle(box, apply) {
  const onChange = () => apply(box.checked);
  box.addEventListener('change', onChange);
  onChange();
}

// Every handler of the map and the panel's controls.
export function bindInput() {
  map.on('singleclick', (ev) => {
    if (stareArmed) {
      armStare(false);
      const e = Math.round(ev.coordinate[0] * 10) / 10;
      const n = Math.round(ev.coordinate[1] * 10) / 10;
      command('camera', { stare: { e: e, n: n } });
      return;
    }
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
    const over = stareArmed || !!nearestCurrentHit(ev.coordinate);
    map.getTargetElement().style.cursor = over ? 'crosshair' : '';
  });

  ui.cancel.addEventListener('click', () => command('cancel'));
  ui.altSet.addEventListener('click', () => setValue('altitude', ui.altInput));
  ui.speedSet.addEventListener('click', () => setValue('speed', ui.speedInput));
  ui.altInput.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setValue('altitude', ui.altInput); });
  ui.speedInput.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setValue('speed', ui.speedInput); });

  ui.fpScale.addEventListener('change', () => {
    holdEdit('footprint_scale');
    command('footprint_scale', { value: Number(ui.fpScale.value) });
  });
  ui.method.addEventListener('change', () => {
    holdEdit('intercept_mode');
    command('intercept_mode', { value: ui.method.value });
  });

  // The imaging sensor's mode: the radio clicked is held until a frame in
  // that mode comes (the status says which is live).
  ui.sensorModes.forEach((r) => r.addEventListener('change', () => {
    if (!r.checked) return;
    holdEdit('sensor_mode');
    command('sensor_mode', { mode: r.value });
  }));

  // The camera.
  const setDepression = () => setCamera('depression', 'depression', ui.camDepression, DEPRESSION_MIN_DEG, DEPRESSION_MAX_DEG);
  const setFov = () => setCamera('fov', 'field of view', ui.camFov, FOV_MIN_DEG, FOV_MAX_DEG);
  ui.camDepressionSet.addEventListener('click', setDepression);
  ui.camFovSet.addEventListener('click', setFov);
  ui.camDepression.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setDepression(); });
  ui.camFov.addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setFov(); });
  ui.camStabilized.addEventListener('change', () => {
    holdEdit('camera');
    command('camera', { stabilized: ui.camStabilized.checked });
  });
  ui.stareOff.addEventListener('click', () => {
    armStare(false);
    command('camera', { stare: 'off' });
  });
  ui.stareTarget.addEventListener('click', () => {
    armStare(false);
    command('camera', { stare: 'target' });
  });
  ui.starePoint.addEventListener('click', () => {
    if (stareArmed) {
      armStare(false);
      showResult('stare: no point chosen', 'info');
      return;
    }
    armStare(true);
    showResult('stare: click the map where the camera is to look (Esc cancels)', 'info');
  });
  document.addEventListener('keydown', (ev) => {
    if (ev.key === 'Escape' && stareArmed) {
      armStare(false);
      showResult('stare: no point chosen', 'info');
    }
  });

  const applyMti = () => showMti(ui.sensorMti.checked, ui.showTracks.checked);
  ui.sensorMti.addEventListener('change', applyMti);
  ui.showTracks.addEventListener('change', applyMti);
  applyMti();
  bindToggle(ui.sensorBcis, (on) => showLayer('bcis', on));
  bindToggle(ui.showRoute, (on) => showLayer('route', on));
  bindToggle(ui.truth, (on) => {
    showLayer('truth', on);
    if (cgs.state) {
      applyTruth(cgs.state.truth);
      map.render();
    }
  });
}
