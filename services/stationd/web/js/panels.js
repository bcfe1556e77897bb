/*
 * panels.js — the side panel and the page's messages: the connection and
 * simulation time, the access note, the UAV selector, the status panel,
 * the flight inputs and the intercept selects as the server reports them,
 * the sensor image (the latest picture, or the live video video.js plays,
 * with the line that says which), and the result line (a command sent,
 * accepted or refused with the reason).
 */
import { cgs } from './hooks.js';
import { $, num, setText } from './util.js';

const EDIT_HOLD_MS = 3000;           // a select the operator just changed is not overwritten for this long, at most

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

// ---------------------------------------------------------------------------
// Elements and state

export const ui = {
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
  video: $('sensor-video'),
  videoStatus: $('video-status'),
  imageEmpty: $('image-empty'),
  imageCaption: $('image-caption'),
  sensorMti: $('sensor-mti'),
  sensorBcis: $('sensor-bcis'),
  showRoute: $('show-route'),
  showTracks: $('show-tracks'),
  truth: $('truth'),
};
const OPERATOR_CONTROLS = [ui.cancel, ui.altInput, ui.altSet, ui.speedInput, ui.speedSet, ui.fpScale, ui.method];

let operator = false;       // this page may command (the hello says)
let selectedUav = null;     // uav_id commands go to
let uavSelect = null;       // the #uav <select>, only with several UAVs
let prefilledFor = null;    // UAV whose commanded values filled the inputs
let imageFrame = null;
let videoShown = false;     // the live video plays in place of the picture
// A select the operator just changed keeps its value until the server
// reports it, the command is refused, or EDIT_HOLD_MS pass.
const holdScale = { sel: ui.fpScale, until: 0, want: null };
const holdMethod = { sel: ui.method, until: 0, want: null };
const holds = new Map([['footprint_scale', holdScale], ['intercept_mode', holdMethod]]);

export function showResult(text, kind) {
  ui.result.textContent = text;
  ui.result.className = 'result ' + (kind || 'info');
}

// The reply to a command `op`: a refused select edit is no longer held.
export function showReply(m, op) {
  const hold = holds.get(op);
  if (!m.ok && hold) hold.until = 0;
  if (m.ok) showResult(op + ': ' + (m.detail || 'ok'), 'ok');
  else showResult('refused: ' + (m.error || 'no reason given'), 'err');
}

// The operator changed the select of command `op`: it keeps that value for
// a while (see holdScale).
export function holdEdit(op) {
  const hold = holds.get(op);
  hold.until = performance.now() + EDIT_HOLD_MS;
  hold.want = hold.sel.value;
}

export const canCommand = () => operator;
export const selectedUavId = () => selectedUav;

export function setConnection(text, kind) {
  setText(ui.connection, text);
  ui.connection.className = 'conn conn-' + kind;
  document.body.classList.toggle('offline', kind !== 'up');
}

// ---------------------------------------------------------------------------
// Panels

export function setOperator(isOperator) {
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

export function updatePanels(st) {
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

// Which of the video, the picture and the "no image yet" box shows.
function showSensor() {
  ui.video.hidden = !videoShown;
  ui.image.hidden = videoShown || imageFrame === null;
  ui.imageEmpty.hidden = videoShown || imageFrame !== null;
}

// The live video plays (live true) or the picture shows; text says which,
// and why (kind: 'live' or 'still').
export function setVideoShown(live, text, kind) {
  if (videoShown !== live) {
    videoShown = live;
    showSensor();
  }
  setText(ui.videoStatus, text);
  ui.videoStatus.className = 'video-' + kind;
}

// The latest imaging-sensor frame: a new src only for a new frame.
export function updateImage(img) {
  if (!img || !img.url) {
    if (imageFrame !== null) {
      imageFrame = null;
      ui.image.removeAttribute('src');
      showSensor();
      setText(ui.imageCaption, '—');
      ui.imageCaption.className = '';
    }
    return;
  }
  if (img.frame !== imageFrame) {
    // The picture keeps loading behind the video, ready for a fallback.
    imageFrame = img.frame;
    ui.image.src = img.url;
    showSensor();
  }
  const cap = 'frame ' + img.frame + ' · ' + (img.mode || '—') + ' · uav ' + img.uav_id +
    (img.target_in_view ? ' · target in view' : '');
  setText(ui.imageCaption, cap);
  ui.imageCaption.className = img.target_in_view ? 'in-view' : '';
}

