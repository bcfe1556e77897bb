/*
 * panels.js — the side panel and the page's messages: the connection and
 * simulation time, the access note, the UAV selector, the status panel
 * (with the imaging sensor's live mode, as its frames say), the flight
 * inputs, the intercept selects, the sensor mode and the camera's settings
 * as the server reports them, the sensor image (the latest picture, or the
 * live video video.js plays, with the line that says which), and the result
 * line (a command sent, accepted or refused with the reason).
 */
import { cgs } from './hooks.js';
import { $, num, setText } from './util.js';

const EDIT_HOLD_MS = 3000;           // a select the operator just changed is not overwritten for this long, at most
const MODE_HOLD_MS = 10000;          // the sensor mode clicked, until a frame in it comes (at most)

// The imaging sensor's modes as the page names them.
export const MODE_LABELS = { visible: 'Visible (EO)', infrared: 'FLIR (infrared)', sar: 'SAR' };

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
  statusSensor: $('status-sensor'),
  sensorModes: [$('sensor-eo'), $('sensor-flir'), $('sensor-sar')],
  camDepression: $('cam-depression'),
  camDepressionSet: $('cam-depression-set'),
  camFov: $('cam-fov'),
  camFovSet: $('cam-fov-set'),
  camStabilized: $('cam-stabilized'),
  stareOff: $('stare-off'),
  stareTarget: $('stare-target'),
  starePoint: $('stare-point'),
  cameraState: $('camera-state'),
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
const OPERATOR_CONTROLS = [ui.cancel, ui.altInput, ui.altSet, ui.speedInput, ui.speedSet, ui.fpScale, ui.method,
  ...ui.sensorModes, ui.camDepression, ui.camDepressionSet, ui.camFov, ui.camFovSet, ui.camStabilized,
  ui.stareOff, ui.stareTarget, ui.starePoint];

let operator = false;       // this page may command (the hello says)
let selectedUav = null;     // uav_id commands go to
let uavSelect = null;       // the #uav <select>, only with several UAVs
let prefilledFor = null;    // UAV whose commanded values filled the inputs
let cameraFilledFor = null; // UAV whose camera settings filled the camera inputs
let imageFrame = null;
let videoShown = false;     // the live video plays in place of the picture

// The checked one of the sensor mode's radio buttons ('' none).
function checkedMode() {
  const r = ui.sensorModes.find((x) => x.checked);
  return r ? r.value : '';
}

// A control the operator just changed keeps its value until the server
// reports it, the command is refused, or ms pass: el, its value as a string
// (read) and set (write); a select is also left alone while it has the
// focus (focus).
function makeHold(el, read, write, ms, focus) {
  return { el: el, read: read, write: write, ms: ms, focus: focus, until: 0, want: null };
}
function setSelect(sel, v) {
  if (sel.value !== v && Array.prototype.some.call(sel.options, (o) => o.value === v)) sel.value = v;
}
const holdScale = makeHold(ui.fpScale, () => ui.fpScale.value, (v) => setSelect(ui.fpScale, v), EDIT_HOLD_MS, true);
const holdMethod = makeHold(ui.method, () => ui.method.value, (v) => setSelect(ui.method, v), EDIT_HOLD_MS, true);
const holdMode = makeHold(null, checkedMode, (v) => {
  ui.sensorModes.forEach((r) => { r.checked = r.value === v; });
}, MODE_HOLD_MS, false);
const holdStabilized = makeHold(ui.camStabilized, () => String(ui.camStabilized.checked), (v) => {
  ui.camStabilized.checked = v === 'true';
}, EDIT_HOLD_MS, false);
const holds = new Map([['footprint_scale', holdScale], ['intercept_mode', holdMethod], ['sensor_mode', holdMode],
  ['camera', holdStabilized]]);

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

// The operator changed the control of command `op`: it keeps that value
// for a while (see makeHold).
export function holdEdit(op) {
  const hold = holds.get(op);
  hold.until = performance.now() + hold.ms;
  hold.want = hold.read();
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

// replay: the page shows a replay (`mscgs replay`): the operator's controls
// are off (they would reach nothing), only the timeline commands.
export function setOperator(isOperator, replay) {
  operator = isOperator;
  OPERATOR_CONTROLS.forEach((el) => { el.disabled = !isOperator || replay === true; });
  if (replay === true) {
    ui.access.hidden = false;
    ui.access.textContent = 'replay: the timeline drives it; operator commands reach nothing';
  } else if (isOperator) {
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
      cameraFilledFor = null;
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

// A control follows the server unless the operator has just changed it
// (or, a select, is on it): see makeHold.
function syncHeld(hold, value) {
  if (value === undefined || value === null) return;
  const v = String(value);
  if (v === hold.want) hold.until = 0;
  if ((hold.focus && document.activeElement === hold.el) || performance.now() < hold.until) return;
  hold.want = null;
  hold.write(v);
}

function fmtDeg(x, digits) {
  return typeof x === 'number' && isFinite(x) ? String(Math.round(x * 10 ** digits) / 10 ** digits) + '°' : '—';
}

function fmtPoint(p) {
  return Array.isArray(p) && p.length >= 2 ? 'E ' + Math.round(num(p[0], 0)) + ' N ' + Math.round(num(p[1], 0)) : 'no point';
}

// The imaging sensor: its live mode (its latest frame's; a mode clicked
// and not yet live is shown pending), the mode's radio buttons, and how the
// camera is set.
function updateSensor(u) {
  const live = u && u.sensor_mode ? u.sensor_mode : null;
  syncHeld(holdMode, live);
  const pending = holdMode.want && holdMode.want !== live && performance.now() < holdMode.until ? holdMode.want : null;
  let text = live ? MODE_LABELS[live] || live : '—';
  if (pending) text += ' · switching to ' + (MODE_LABELS[pending] || pending) + '…';
  setText(ui.statusSensor, text);
  ui.statusSensor.className = pending ? 'pending' : '';

  const c = u ? u.camera : null;
  if (!c) {
    setText(ui.cameraState, '—');
    ui.cameraState.className = 'hint';
    [ui.stareOff, ui.stareTarget, ui.starePoint].forEach((b) => b.classList.remove('on'));
    return;
  }
  if (cameraFilledFor !== u.id) {
    cameraFilledFor = u.id;
    if (typeof c.depression_deg === 'number') ui.camDepression.value = String(Math.round(c.depression_deg * 10) / 10);
    if (typeof c.hfov_deg === 'number') ui.camFov.value = String(Math.round(c.hfov_deg * 10) / 10);
  }
  syncHeld(holdStabilized, c.stabilized === true);
  ui.stareOff.classList.toggle('on', c.stare === 'off');
  ui.stareTarget.classList.toggle('on', c.stare === 'target');
  ui.starePoint.classList.toggle('on', c.stare === 'point');
  let stare = 'stare off';
  if (c.stare === 'point') stare = (c.staring ? 'staring at ' : 'to stare at ') + fmtPoint(c.stare_point);
  else if (c.stare === 'target') stare = c.staring ? 'staring at the target (' + fmtPoint(c.stare_point) + ')' : 'to stare at the target: none designated';
  const parts = [fmtDeg(c.depression_deg, 1) + ' down', 'FOV ' + fmtDeg(c.hfov_deg, 2) + ' × ' + fmtDeg(c.vfov_deg, 2),
    c.stabilized ? 'stabilized' : 'not stabilized', stare];
  if (c.at_gimbal_limit) parts.push('held at the gimbal\'s limit');
  setText(ui.cameraState, parts.join(' · '));
  ui.cameraState.className = 'hint' + (c.at_gimbal_limit ? ' limit' : '');
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
    syncHeld(holdScale, icpt.scale);
    syncHeld(holdMethod, icpt.method);
  }
  updateSensor(u);
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

