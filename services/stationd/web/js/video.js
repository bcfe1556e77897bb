/*
 * video.js — the imaging sensor's live video in the side panel, and the
 * sensor's footprints on the map.
 *
 * stationd relays imagerd's MPEG transport stream (H.264 and MISB ST 0601
 * KLV) over the WebSocket /video; mpegts.js (global `mpegts`) plays it
 * through Media Source Extensions, muted, at the exercise's time scale (at
 * 10x, ten seconds of video a wall second), chasing the live edge when it
 * falls behind. Where the browser cannot (no MSE live
 * playback), or the player fails, the latest.png picture shows instead, and
 * the status line under the panel says which is live and why. A failed
 * player is tried again later, a stream that started over at once.
 *
 * Each KLV packet is read (klv.js; a bad checksum refuses it, counted) and
 * its footprint drawn on the map (dashed orange, at most KLV_DRAW_MS apart)
 * over the footprint of the `image` messages (thin white), so a user sees
 * the two agree. window.cgs.video holds what the browser tests read.
 */
import { localFrame } from './geo.js';
import { cgs } from './hooks.js';
import { decodePackets, footprintOf } from './klv.js';
import { src } from './layers.js';
import { setVideoShown } from './panels.js';
import { S } from './symbols.js';
import { clamp, evenFlat, pairs, sameArray } from './util.js';

const KLV_DRAW_MS = 250;             // the KLV footprint is redrawn at most 4 times a second
const RETRY_MIN_MS = 2000;           // a failed player is tried again after this,
const RETRY_MAX_MS = 60000;          // doubling up to this
const RESTART_MS = 300;              // a stream that started over: a new player after this
const START_TIMEOUT_MS = 15000;      // frames come but no picture this long: failed
const STALL_MS = 8000;               // the picture stops this long while frames come: failed
const LATENCY_MAX_S = 0.5;           // wall seconds behind the newest frame before it seeks ahead,
const LATENCY_KEEP_S = 0.15;         // to this much before it; but in frames (mpegts.js hands
const KEEP_FRAMES = 3;               // the video on two frames at a time, a frame late) at least
const MAX_FRAMES = 6;                // this many
const PERIOD_CHANGE = 2;             // a frame period this many times longer or shorter: a new player
const RATE_MIN = 0.0625;             // the playback rates Chromium allows
const RATE_MAX = 16;
const ERRORS_KEEP = 20;

const videoEl = document.getElementById('sensor-video');

// What the tests read (window.cgs.video).
const v = {
  supported: false,          // MSE live playback (mpegts.getFeatureList().mseLivePlayback)
  status: 'still',           // 'live' (the video shows) or 'still' (the picture does)
  reason: '',                // why the picture shows
  uavId: null,               // the UAV whose video plays
  starts: 0,                 // players started
  remade: [],                // why players were made again (time scale, frame rate, UAV)
  errors: [],                // the players' errors, newest last
  klv: {
    packets: 0,              // packets read
    bad: 0,                  // packets refused (checksum, length)
    lastError: '',
    last: null,              // the newest packet's values
    form: '',                // its corners' form: 'offset' or 'full'
    footprint: null,         // the footprint drawn, [e, n] × 4 flat, local metres
    drawn: 0,                // times it was drawn
    drawnAt: 0,              // performance.now() of the last drawing
  },
  imageFootprint: null,      // the `image` messages' footprint drawn, [e, n] × 4
};
cgs.video = v;

let player = null;
let playerScale = 1;         // the time scale the player was made for,
let playerPeriod = 0;        // and the frame period (simulation seconds)
let playerKeep = 0;          // media seconds it keeps behind the newest frame
let startedAt = 0;           // performance.now() when it was made
let framesAtStart = 0;       // the state's video frame count then
let lastProgress = { t: 0, media: -1, frames: 0 };
let live = false;
let retryAt = 0;
let retryMs = RETRY_MIN_MS;
let frames = 0;              // the state's video frame count, newest
let local = null;            // the exercise's local frame (from the hello's origin)
let localKey = { key: '', h: 0 };  // the origin it is about, and its height
let klvPending = null;
let klvTimer = null;

const imageFp = new ol.Feature();
imageFp.cgsStyle = S.imageFootprint;
const klvFp = new ol.Feature();
klvFp.cgsStyle = S.klvFootprint;
src.sensorFootprint.addFeatures([imageFp, klvFp]);

function mpegtsFeatures() {
  try {
    return window.mpegts ? window.mpegts.getFeatureList() : null;
  } catch (err) {
    return null;
  }
}
const features = mpegtsFeatures();
v.supported = !!(features && features.mseLivePlayback);

// ---------------------------------------------------------------------------
// Which shows

function showLive() {
  if (v.status !== 'live') {
    v.status = 'live';
    v.reason = '';
  }
  retryMs = RETRY_MIN_MS;
  const size = videoEl.videoWidth ? ' · ' + videoEl.videoWidth + '×' + videoEl.videoHeight : '';
  const track = v.klv.last && v.klv.last.target_id ? ' · KLV track ' + v.klv.last.target_id : '';
  setVideoShown(true, 'live video · uav ' + v.uavId + size + track, 'live');
}

function showStill(reason) {
  v.status = 'still';
  v.reason = reason;
  setVideoShown(false, 'still picture (latest.png): ' + reason, 'still');
}

// ---------------------------------------------------------------------------
// The player

// mpegts.js's WebSocket loader, but one that lets go of its socket when
// aborted. mpegts.js 1.8.2's own keeps the socket's handlers: a socket
// closed while it connects (a player given up early) fails afterwards, and
// its handler, its player destroyed, throws an uncaught exception.
let SocketLoader = null;
function socketLoader() {
  if (SocketLoader) return SocketLoader;
  const { BaseLoader, LoaderStatus, LoaderErrors } = mpegts;
  SocketLoader = class extends BaseLoader {
    static isSupported() {
      return typeof WebSocket !== 'undefined';
    }

    constructor() {
      super('cgs-websocket-loader');
      this.TAG = 'CgsSocketLoader';
      this._needStash = true;
      this._ws = null;
      this._received = 0;
    }

    destroy() {
      this.abort();
      super.destroy();
    }

    open(dataSource) {
      const ws = new WebSocket(dataSource.url);
      this._ws = ws;
      ws.binaryType = 'arraybuffer';
      ws.onopen = () => { this._status = LoaderStatus.kBuffering; };
      ws.onmessage = (ev) => {
        if (!(ev.data instanceof ArrayBuffer)) return;   // stationd sends binary frames only
        const start = this._received;
        this._received += ev.data.byteLength;
        if (this._onDataArrival) this._onDataArrival(ev.data, start, this._received);
      };
      ws.onclose = () => {
        this._ws = null;
        this._status = LoaderStatus.kComplete;
        if (this._onComplete) this._onComplete(0, this._received - 1);
      };
      ws.onerror = () => {
        this._status = LoaderStatus.kError;
        if (this._onError) this._onError(LoaderErrors.EXCEPTION, { code: -1, msg: 'the WebSocket ' + dataSource.url + ' failed' });
      };
      this._status = LoaderStatus.kConnecting;
    }

    abort() {
      const ws = this._ws;
      this._ws = null;
      if (ws) {
        ws.onopen = ws.onmessage = ws.onclose = ws.onerror = null;
        if (ws.readyState === WebSocket.CONNECTING || ws.readyState === WebSocket.OPEN) ws.close();
      }
      this._status = LoaderStatus.kComplete;
    }
  };
  return SocketLoader;
}

function stopPlayer() {
  if (!player) return;
  const p = player;
  player = null;
  live = false;
  try {
    p.pause();
    p.unload();
    p.detachMediaElement();
    p.destroy();
  } catch (err) {
    // It is being thrown away: nothing more to do with it.
  }
  klvFp.setGeometry(null);
  klvFp.cgsKey = null;
  v.klv.footprint = null;
}

function fail(why) {
  v.errors.push(why);
  if (v.errors.length > ERRORS_KEEP) v.errors.shift();
  stopPlayer();
  showStill('live video failed (' + why + '); retrying');
  retryAt = performance.now() + retryMs;
  retryMs = Math.min(RETRY_MAX_MS, retryMs * 2);
}

function rateOf(scale) {
  return clamp(scale > 0 ? scale : 1, RATE_MIN, RATE_MAX);
}

// The frames' spacing in simulation seconds, once stationd has measured it
// (two frames in); 0 before.
function periodOf(video) {
  return typeof video.frame_period_s === 'number' && video.frame_period_s > 0 ? video.frame_period_s : 0;
}

function startPlayer(video, scale) {
  const url = (location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + (video.url || '/video');
  const rate = rateOf(scale);
  const period = periodOf(video);
  // Latency in media (simulation) seconds: the wall seconds times the rate,
  // but never less than a few frames, or it runs dry between them.
  const keep = Math.max(LATENCY_KEEP_S * rate, KEEP_FRAMES * period);
  const max = Math.max(LATENCY_MAX_S * rate, keep + MAX_FRAMES * period - KEEP_FRAMES * period);
  const p = mpegts.createPlayer({ type: 'mpegts', isLive: true, url: url }, {
    customLoader: socketLoader(),
    enableWorker: false,
    enableStashBuffer: false,
    lazyLoad: false,
    liveBufferLatencyChasing: true,
    liveBufferLatencyMaxLatency: max,
    liveBufferLatencyMinRemain: keep,
    autoCleanupSourceBuffer: true,
    autoCleanupMaxBackwardDuration: 60 * rate,
    autoCleanupMinBackwardDuration: 30 * rate,
  });
  const E = mpegts.Events;
  p.on(E.ERROR, (type, detail, info) => {
    if (player !== p) return;
    fail(type + ': ' + detail + (info && info.msg ? ' (' + info.msg + ')' : ''));
  });
  p.on(E.LOADING_COMPLETE, () => {
    // stationd closed the stream: it started over (another UAV, a
    // restarted imagerd), or stationd stopped.
    if (player !== p) return;
    stopPlayer();
    showStill('the video stream ended; reconnecting');
    retryAt = performance.now() + RESTART_MS;
  });
  p.on(E.ASYNCHRONOUS_KLV_METADATA_ARRIVED, (m) => { if (player === p && m && m.data) takeKlv(m.data); });
  p.on(E.SYNCHRONOUS_KLV_METADATA_ARRIVED, (m) => {
    if (player !== p || !m || !Array.isArray(m.access_units)) return;
    m.access_units.forEach((au) => takeKlv(au.data));
  });
  p.attachMediaElement(videoEl);
  player = p;
  playerScale = scale;
  playerPeriod = period;
  playerKeep = keep;
  startedAt = performance.now();
  framesAtStart = frames;
  lastProgress = { t: startedAt, media: -1, frames: frames };
  v.starts += 1;
  v.uavId = video.uav_id;
  videoEl.muted = true;
  p.load();
  videoEl.playbackRate = rate;
  videoEl.defaultPlaybackRate = rate;
  const played = p.play();
  if (played && played.catch) played.catch(() => { /* autoplay waits for the first frame */ });
}

// The video's time moved on: it is live.
videoEl.addEventListener('timeupdate', () => {
  if (!player) return;
  const t = videoEl.currentTime;
  if (t !== lastProgress.media) {
    lastProgress = { t: performance.now(), media: t, frames: frames };
    if (!live && videoEl.videoWidth > 0 && videoEl.readyState >= 2) {
      live = true;
      showLive();
      // It starts where the stream did: up to the live edge at once (then
      // mpegts.js keeps it there), not as far behind as it started.
      const b = videoEl.buffered;
      const edge = b.length ? b.end(b.length - 1) - playerKeep : t;
      if (edge > t + playerPeriod) videoEl.currentTime = edge;
    }
  }
});
videoEl.addEventListener('error', () => {
  if (player) fail('the video element: ' + (videoEl.error ? videoEl.error.message || 'code ' + videoEl.error.code : 'error'));
});

// ---------------------------------------------------------------------------
// KLV

function takeKlv(bytes) {
  const data = bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes);
  for (const r of decodePackets(data)) {
    if (!r.ok) {
      v.klv.bad += 1;
      v.klv.lastError = r.error;
      continue;
    }
    v.klv.packets += 1;
    v.klv.last = r.values;
    const fp = footprintOf(r.values);
    if (fp) klvPending = { fp, values: r.values };
  }
  if (klvPending && !klvTimer) {
    const wait = Math.max(0, v.klv.drawnAt + KLV_DRAW_MS - performance.now());
    klvTimer = setTimeout(drawKlv, wait);
  }
}

function drawKlv() {
  klvTimer = null;
  const pending = klvPending;
  klvPending = null;
  if (!pending || !local || !player) return;
  const h = typeof pending.values.frame_center_elev_m === 'number' ? pending.values.frame_center_elev_m : localKey.h;
  const flat = [];
  for (const [lat, lon] of pending.fp.corners) {
    const enu = local.toEnu(lat, lon, h);
    flat.push(enu[0], enu[1]);
  }
  const ring = pairs(flat);
  ring.push(ring[0]);
  klvFp.setGeometry(new ol.geom.Polygon([ring]));
  v.klv.footprint = flat;
  v.klv.form = pending.fp.form;
  v.klv.drawn += 1;
  v.klv.drawnAt = performance.now();
  if (live) showLive();
}

// ---------------------------------------------------------------------------
// Each state

// The exercise's origin, from the hello: the frame the KLV's corners are
// taken into.
export function setOrigin(origin) {
  if (!origin || typeof origin.lat_deg !== 'number' || typeof origin.lon_deg !== 'number') return;
  const h = typeof origin.height_m === 'number' ? origin.height_m : 0;
  const key = origin.lat_deg + ',' + origin.lon_deg + ',' + h;
  if (key === localKey.key) return;
  local = localFrame(origin.lat_deg, origin.lon_deg, h);
  localKey = { key, h };
}

// The footprint of the `image` messages, [e, n] × 4 flat, or none.
function applyImageFootprint(img) {
  const flat = img && Array.isArray(img.footprint) && img.footprint.length === 8 ? evenFlat(img.footprint) : null;
  if (sameArray(imageFp.cgsKey, flat)) return;
  imageFp.cgsKey = flat;
  v.imageFootprint = flat;
  if (!flat) {
    imageFp.setGeometry(null);
    return;
  }
  const ring = pairs(flat);
  ring.push(ring[0]);
  imageFp.setGeometry(new ol.geom.Polygon([ring]));
}

// A state: start, keep or stop the player, and check it plays.
export function updateVideo(st) {
  applyImageFootprint(st.image);
  const video = st.video && typeof st.video === 'object' ? st.video : null;
  frames = video && typeof video.frames === 'number' ? video.frames : 0;
  const scale = typeof st.time_scale === 'number' && st.time_scale > 0 ? st.time_scale : 1;
  if (!v.supported) {
    showStill('this browser cannot play the live video (no Media Source Extensions live playback)');
    return;
  }
  if (!video) {
    stopPlayer();
    showStill('no live video from imagerd');
    return;
  }
  const now = performance.now();
  // A player made for another time scale, frame rate or UAV is made again.
  const period = periodOf(video);
  if (player) {
    const why = rateOf(scale) !== rateOf(playerScale) ? 'time scale ' + scale
      : video.uav_id !== v.uavId ? 'uav ' + video.uav_id
        : period && (period > PERIOD_CHANGE * playerPeriod || period * PERIOD_CHANGE < playerPeriod) ? 'frame period ' + period + ' s' : null;
    if (why) {
      v.remade.push(why);
      if (v.remade.length > ERRORS_KEEP) v.remade.shift();
      stopPlayer();
    }
  }
  if (!player) {
    if (now < retryAt || !period) return;   // the frame rate is known two frames in
    if (v.status !== 'still' || !v.reason) showStill('starting the live video');
    startPlayer(video, scale);
    return;
  }
  if (live) {
    showLive();
    // Frames come but the picture stands still: the decoder is stuck.
    if (!st.paused && now - lastProgress.t > STALL_MS && frames - lastProgress.frames > 5) fail('the picture stopped while frames came');
  } else if (now - startedAt > START_TIMEOUT_MS && frames - framesAtStart > 5) {
    fail('no picture ' + Math.round(START_TIMEOUT_MS / 1000) + ' s after it started');
  }
}
