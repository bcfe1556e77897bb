/*
 * main.js — the browser front end of the mscgs ground station (served by
 * stationd): a tactical map of the exercise in its local east/north metre
 * frame, the operator's intercept, flight, sensor-mode and camera controls,
 * the intercept status and the imaging sensor's live video (or its latest
 * frame). This module
 * wires the others:
 *
 *   hooks.js     window.cgs, the state the browser tests and benchmark read
 *   util.js      small helpers
 *   symbols.js   shared styles and the MIL-STD-2525 symbol sheets
 *   layers.js    the map, its layers, view, relief and layer visibility
 *   features.js  a state applied to the layers' features, kept by key
 *   panels.js    the side panel, the status and the result messages
 *   net.js       the WebSocket to stationd and its protocol
 *   input.js     clicks, the cursor's MGRS, the controls and check boxes
 *   video.js     the live video (mpegts.js) and the sensor's footprints
 *   klv.js       the video's MISB ST 0601 KLV packets read
 *   geo.js       latitude and longitude to the local east/north frame
 *   timeline.js  a replay's timeline: play, pause, speed, seek, marks
 *
 * OpenLayers (global `ol`, full build), milsymbol (global `ms`) and
 * mpegts.js (global `mpegts`) are classic scripts loaded before it. ES
 * modules, no bundler.
 */
import {
  applyBcis, applyHits, applyIntercepts, applyTracks, applyTruth, applyUavs, preloadSymbols,
} from './features.js';
import { cgs } from './hooks.js';
import { bindInput, onMgrs } from './input.js';
import { applyRelief, centreOnce, map } from './layers.js';
import { connect } from './net.js';
import { setConnection, setOperator, showReply, showResult, ui, updateImage, updatePanels } from './panels.js';
import { num } from './util.js';
import { bindTimeline, updateTimeline } from './timeline.js';
import { setOrigin, updateVideo } from './video.js';

const APPLY_KEEP = 1000;             // apply times kept for the benchmark

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
  if (st.uavs.length) centreOnce(num(st.uavs[0].e, 0), num(st.uavs[0].n, 0));

  updatePanels(st);
  updateImage(st.image);
  updateVideo(st);
  updateTimeline(st.replay);
}

// A state, drawn before the handler returns; t0: when its message came.
function onState(m, t0) {
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
}

function onHello(h) {
  cgs.hello = h;
  applyRelief(h.relief);
  setOrigin(h.origin);
  setOperator(h.operator === true, h.replay === true);
}

bindInput();
bindTimeline();
preloadSymbols();
setOperator(false);
ui.access.hidden = true;   // until the hello says otherwise
connect({
  state: onState,
  hello: onHello,
  reply: showReply,
  mgrs: onMgrs,
  error: (m) => showResult('error: ' + (m.error || 'protocol error'), 'err'),
  status: setConnection,
});
