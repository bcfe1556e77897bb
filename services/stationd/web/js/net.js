/*
 * net.js — the one WebSocket to stationd (/ws) and its JSON protocol. The
 * server sends `hello` once per connection and the whole picture (`state`)
 * at about 5 Hz, with `reply`, `mgrs` and `error` answers; the page sends
 * operator commands and cursor MGRS look-ups, each with a `req` number. A
 * link that closes or goes quiet is opened again, with a growing delay.
 *
 * connect(handlers) starts it; each message goes to handlers[type]:
 * state(m, t0) (t0: when its handling began), hello(m), reply(m, op),
 * mgrs(m), error(m); status(text, kind) tells the link's state
 * ('wait', 'up' or 'down').
 */
import { cgs } from './hooks.js';

const RECONNECT_MIN_MS = 1000;
const RECONNECT_MAX_MS = 5000;
const REPLIES_KEEP = 1000;

let handlers = null;
let ws = null;
let connected = false;
let reconnectDelay = RECONNECT_MIN_MS;
let reconnectTimer = 0;
let reqSeq = 0;
const pendingOps = new Map();   // req -> op of commands awaiting a reply

export function nextReq() {
  reqSeq += 1;
  return reqSeq;
}

export const isConnected = () => connected;

// A reply, kept for the tests, goes on with its command's op: the reply's
// own, or the one this page sent under its req.
function onReply(m) {
  cgs.stats.replies.push(m);
  if (cgs.stats.replies.length > REPLIES_KEEP) cgs.stats.replies.shift();
  const op = m.op || pendingOps.get(m.req) || 'command';
  pendingOps.delete(m.req);
  handlers.reply(m, op);
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
      handlers.state(m, t0);
      break;
    case 'hello':
      handlers.hello(m);
      break;
    case 'reply':
      onReply(m);
      break;
    case 'mgrs':
      handlers.mgrs(m);
      break;
    case 'error':
      handlers.error(m);
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

function open() {
  reconnectTimer = 0;
  handlers.status('connecting…', 'wait');
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
    handlers.status('connected', 'up');
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

export function connect(h) {
  handlers = h;
  open();
}

// A link that went quiet (the server gave up on this page, or the network
// dropped it without a close) is closed and opened again: pictures come at
// push_hz, so several missed in a row mean the picture is frozen.
let lastMessageAt = 0;
setInterval(() => {
  const hz = cgs.hello && cgs.hello.push_hz > 0 ? cgs.hello.push_hz : 5;
  const quiet = Math.max(3000, 6000 / hz);
  if (ws && connected && performance.now() - lastMessageAt > quiet) {
    handlers.status('no pictures for ' + Math.round(quiet / 1000) + ' s · reconnecting', 'wait');
    ws.close();
  }
}, 1000);

function scheduleReconnect() {
  if (reconnectTimer) return;
  const delay = reconnectDelay;
  reconnectDelay = Math.min(RECONNECT_MAX_MS, reconnectDelay * 2);
  handlers.status('disconnected · retry in ' + Math.round(delay / 1000) + ' s', 'down');
  reconnectTimer = setTimeout(open, delay);
}

// ---------------------------------------------------------------------------
// Sending

// A message to the server; false when there is no open link.
export function send(obj) {
  if (!ws || !connected || ws.readyState !== WebSocket.OPEN) return false;
  ws.send(JSON.stringify(obj));
  return true;
}

// A command `op` with its fields, under a new req whose reply will name it.
export function request(op, fields) {
  const req = nextReq();
  const msg = Object.assign({ op: op, req: req }, fields);
  pendingOps.set(req, op);
  send(msg);
}
