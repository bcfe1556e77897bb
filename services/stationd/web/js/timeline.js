/*
 * timeline.js — a replay's timeline (`mscgs replay`): play and pause, the
 * speed, the position over the recording with the intercept's changes
 * marked (designations, phases, re-plans, hand-overs), and a click on the
 * bar to seek there. Shown only when stationd's hello says the exercise is
 * a replay; each control is a command (replay_pause, replay_resume,
 * replay_speed, replay_seek) that stationd sends to the replay.
 */
import { request } from './net.js';
import { canCommand, showResult } from './panels.js';
import { $ } from './util.js';

const SPEEDS = [0.25, 0.5, 1, 2, 5, 10, 20, 50, 100];

const tl = {
  box: $('timeline'),
  play: $('tl-play'),
  speed: $('tl-speed'),
  track: $('tl-track'),
  fill: $('tl-fill'),
  cursor: $('tl-cursor'),
  marks: $('tl-marks'),
  time: $('tl-time'),
};

let last = null;          // the newest replay state
let marksKey = '';        // the marks drawn (redrawn only when they change)
let speedHeldUntil = 0;   // a speed chosen here is kept until the replay says it

function fmt(t) {
  if (typeof t !== 'number' || !isFinite(t)) return '—';
  const m = Math.floor(t / 60), s = t - 60 * m;
  return m + ':' + (s < 10 ? '0' : '') + s.toFixed(1);
}

function timelineCommand(op, fields) {
  if (!canCommand()) {
    showResult('view only: open the page with ?token=… to drive the replay', 'err');
    return;
  }
  request(op, fields || {});
  showResult(op + ': sent…', 'pending');
}

function drawMarks(r) {
  const key = JSON.stringify(r.marks) + '/' + r.span_s;
  if (key === marksKey) return;
  marksKey = key;
  tl.marks.textContent = '';
  for (const m of r.marks || []) {
    const el = document.createElement('div');
    el.className = 'tl-mark tl-' + (m.kind || 'phase');
    el.style.left = (r.span_s > 0 ? (100 * m.t_s) / r.span_s : 0) + '%';
    el.title = fmt(m.t_s) + ' ' + m.kind + ': ' + m.text;
    el.dataset.t = m.t_s;
    tl.marks.appendChild(el);
  }
}

// A state's `replay` (null: live, the bar stays hidden).
export function updateTimeline(r) {
  last = r || null;
  if (!r) return;
  tl.box.hidden = false;
  const frac = r.span_s > 0 ? Math.min(1, Math.max(0, r.t_s / r.span_s)) : 0;
  tl.fill.style.width = 100 * frac + '%';
  tl.cursor.style.left = 100 * frac + '%';
  tl.play.textContent = r.paused || r.ended ? '▶' : '❚❚';
  tl.play.title = r.paused || r.ended ? 'play' : 'pause';
  tl.play.setAttribute('aria-label', tl.play.title);
  tl.time.textContent = fmt(r.t_s) + ' / ' + fmt(r.span_s) + (r.ended ? ' (end)' : '');
  if (performance.now() > speedHeldUntil) {
    const v = String(r.speed);
    if (![...tl.speed.options].some((o) => o.value === v)) {
      const o = document.createElement('option');
      o.value = v;
      o.textContent = v + '×';
      tl.speed.appendChild(o);
    }
    tl.speed.value = v;
  }
  drawMarks(r);
}

export function bindTimeline() {
  for (const s of SPEEDS) {
    const o = document.createElement('option');
    o.value = String(s);
    o.textContent = s + '×';
    tl.speed.appendChild(o);
  }
  tl.play.addEventListener('click', () => {
    if (!last) return;
    timelineCommand(last.paused || last.ended ? 'replay_resume' : 'replay_pause');
  });
  tl.speed.addEventListener('change', () => {
    speedHeldUntil = performance.now() + 3000;
    timelineCommand('replay_speed', { value: Number(tl.speed.value) });
  });
  tl.track.addEventListener('click', (ev) => {
    if (!last || !(last.span_s > 0)) return;
    const box = tl.track.getBoundingClientRect();
    const frac = Math.min(1, Math.max(0, (ev.clientX - box.left) / box.width));
    timelineCommand('replay_seek', { t: Math.round(frac * last.span_s * 10) / 10 });
  });
}
