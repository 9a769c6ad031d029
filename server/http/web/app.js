// SPDX-License-Identifier: Apache-2.0
// The ispq web view: lists the server's jobs, starts one from an uploaded T-mesh (JSON or binary,
// with its scaling, method and time limit), and follows a job live over server-sent events
// (GET /v1/jobs/{id}:watch), drawing its objective over time and its mesh in 3-D, coloured by the
// intermediate quantizations as they stream (mesh_view.js).
// Plain JavaScript against the server's JSON API; nothing is loaded from elsewhere.
'use strict';

const $ = (id) => document.getElementById(id);
const JOB_LIST_INTERVAL_MS = 1000;

// ---- The API ----------------------------------------------------------------------------------

function token() { return $('token').value.trim(); }

async function api(path, options = {}) {
  const headers = Object.assign({}, options.headers || {});
  if (token()) headers['Authorization'] = 'Bearer ' + token();
  const response = await fetch(path, Object.assign({}, options, { headers }));
  const text = await response.text();
  let body = null;
  try { body = text ? JSON.parse(text) : null; } catch (e) { body = null; }
  if (!response.ok) {
    const message = body && body.message ? body.message : text || response.statusText;
    const status = body && body.status ? body.status : String(response.status);
    throw new Error(status + ': ' + message);
  }
  return body;
}

// ---- Formatting -------------------------------------------------------------------------------

function jobId(name) { return name.replace(/^jobs\//, ''); }
function number(value, digits = 4) {
  if (value === undefined || value === null || value === '') return '—';
  const n = Number(value);
  if (!Number.isFinite(n)) return String(value);
  return Math.abs(n) >= 1e5 || (n !== 0 && Math.abs(n) < 1e-3) ? n.toExponential(digits) : String(+n.toFixed(digits));
}
function levelOf(job) {
  const scaling = job.options && job.options.scaling;
  if (!scaling) return '—';
  if (scaling.levelPercent !== undefined) return scaling.levelPercent + ' %';
  if (scaling.factor !== undefined) return 's=' + scaling.factor;
  if (scaling.targetHexes !== undefined) return scaling.targetHexes + ' hexes';
  return '—';
}
function phaseName(phase) { return (phase || '—').replace(/^PHASE_/, '').toLowerCase(); }

// ---- The job list -----------------------------------------------------------------------------

let selected = null;  // the job followed, "jobs/{id}"

async function refreshJobs() {
  try {
    const page = await api('/v1/jobs?pageSize=50');
    const jobs = (page && page.jobs) || [];
    const body = $('jobs').querySelector('tbody');
    body.replaceChildren(...jobs.map(jobRow));
    $('jobs-empty').hidden = jobs.length > 0;
    $('server-status').textContent = 'connected';
    $('server-status').classList.remove('down');
  } catch (error) {
    $('server-status').textContent = 'server: ' + error.message;
    $('server-status').classList.add('down');
  } finally {
    setTimeout(refreshJobs, JOB_LIST_INTERVAL_MS);
  }
}

function jobRow(job) {
  const row = document.createElement('tr');
  row.dataset.job = job.name;
  if (job.name === selected) row.classList.add('selected');
  const result = job.result || {};
  const cells = [jobId(job.name).slice(0, 8), job.meshDisplayName || '', job.state, levelOf(job),
                 result.objective !== undefined && job.state === 'SUCCEEDED' ? number(result.objective) : '',
                 job.state === 'SUCCEEDED' ? String(result.hexes || '') : '',
                 job.createTime ? new Date(job.createTime).toLocaleTimeString() : ''];
  for (const text of cells) {
    const cell = document.createElement('td');
    cell.textContent = text;
    row.appendChild(cell);
  }
  row.children[2].className = 'state-' + job.state;
  row.addEventListener('click', () => follow(job.name));
  return row;
}

// ---- Starting a job ---------------------------------------------------------------------------

function newRequestId() {
  if (window.crypto && crypto.randomUUID) return crypto.randomUUID();
  return 'web-' + Date.now() + '-' + Math.floor(Math.random() * 1e9);
}

// What the form asks for, as the fields of a QuantizeRequest (besides the mesh).
function formOptions() {
  const kind = $('scaling-kind').value;
  const options = { method: $('method').value === 'exact' ? 'METHOD_EXACT' : 'METHOD_ISP' };
  if (kind === 'factor') options.scaling = { factor: Number($('factor').value) };
  else if (kind === 'hexes') options.scaling = { targetHexes: String(Math.round(Number($('target-hexes').value))) };
  else options.scaling = { levelPercent: Number($('level').value) };
  const limit = $('time-limit').value.trim();
  if (limit !== '') options.timeLimitSeconds = Number(limit);
  return options;
}

function scalingText(options) {
  const s = options.scaling;
  if (s.factor !== undefined) return 's = ' + s.factor;
  if (s.targetHexes !== undefined) return s.targetHexes + ' hexes';
  return 'level ' + s.levelPercent + ' %';
}

function durationJson(seconds) { return seconds.toFixed(3).replace(/\.?0+$/, '') + 's'; }

// The request in JSON, with the T-mesh's JSON file spliced in as it is; the server validates it
// and names the offending element if it is not a valid T-mesh.
function jsonRequest(meshText, options) {
  const opts = { scaling: options.scaling, method: options.method };
  if (options.timeLimitSeconds !== undefined) opts.timeLimit = durationJson(options.timeLimitSeconds);
  return '{"mesh":' + meshText + ',"options":' + JSON.stringify(opts) +
         ',"progressInterval":"0.05s","intermediateInterval":"0.1s","requestId":' +
         JSON.stringify(newRequestId()) + '}';
}

// The request in binary protobuf, for a `.tmesh.pb` file: its bytes are the TMesh message, so they
// become field 1 (mesh) as they are; the few other fields are written here
// (proto/ispq/v1/service.proto, quantization.proto).
const Proto = {
  varint(out, value) {  // value < 2^53
    while (value >= 128) { out.push((value % 128) | 128); value = Math.floor(value / 128); }
    out.push(value);
  },
  tag(out, field, wire) { Proto.varint(out, field * 8 + wire); },
  bytes(out, field, bytes) {
    Proto.tag(out, field, 2); Proto.varint(out, bytes.length);
    for (const b of bytes) out.push(b);
  },
  double(out, field, value) {
    Proto.tag(out, field, 1);
    const data = new DataView(new ArrayBuffer(8));
    data.setFloat64(0, value, true);
    for (let i = 0; i < 8; i++) out.push(data.getUint8(i));
  },
  duration(out, field, seconds) {
    const whole = Math.floor(seconds), nanos = Math.round((seconds - whole) * 1e9);
    const message = [];
    if (whole) { Proto.tag(message, 1, 0); Proto.varint(message, whole); }
    if (nanos) { Proto.tag(message, 2, 0); Proto.varint(message, nanos); }
    Proto.bytes(out, field, message);
  },
};

function binaryRequest(meshBytes, options) {
  const scaling = [], opts = [], rest = [];
  const s = options.scaling;
  if (s.factor !== undefined) Proto.double(scaling, 1, s.factor);
  else if (s.targetHexes !== undefined) { Proto.tag(scaling, 3, 0); Proto.varint(scaling, Number(s.targetHexes)); }
  else { Proto.tag(scaling, 2, 0); Proto.varint(scaling, s.levelPercent); }
  Proto.bytes(opts, 1, scaling);
  if (options.timeLimitSeconds !== undefined) Proto.duration(opts, 6, options.timeLimitSeconds);
  Proto.tag(opts, 7, 0); Proto.varint(opts, options.method === 'METHOD_EXACT' ? 2 : 1);
  Proto.bytes(rest, 3, opts);
  Proto.duration(rest, 4, 0.05);
  Proto.duration(rest, 5, 0.1);
  Proto.bytes(rest, 6, new TextEncoder().encode(newRequestId()));
  const head = [];
  Proto.tag(head, 1, 2);
  Proto.varint(head, meshBytes.length);
  return new Blob([new Uint8Array(head), meshBytes, new Uint8Array(rest)]);
}

function checkForm(options) {
  const s = options.scaling;
  if (s.factor !== undefined && !(s.factor > 0)) return 'the scaling factor must be a positive number';
  if (s.targetHexes !== undefined && !(Number(s.targetHexes) > 0)) return 'the target hex count must be positive';
  if (options.timeLimitSeconds !== undefined && !(options.timeLimitSeconds > 0)) return 'the time limit must be a positive number of seconds';
  return '';
}

async function submitJob(event) {
  event.preventDefault();
  const file = $('mesh-file').files[0];
  if (!file) return;
  const options = formOptions();
  const problem = checkForm(options);
  $('form-message').className = problem ? 'message error' : 'message';
  $('form-message').textContent = problem;
  if (problem) return;
  $('submit-job').disabled = true;
  $('form-message').textContent = 'Uploading ' + file.name + '…';
  try {
    const binary = /\.(pb|binpb)$/i.test(file.name);
    const request = binary
      ? { body: binaryRequest(new Uint8Array(await file.arrayBuffer()), options), type: 'application/x-protobuf' }
      : { body: jsonRequest(await file.text(), options), type: 'application/json' };
    const job = await api('/v1/jobs', { method: 'POST', body: request.body, headers: { 'Content-Type': request.type } });
    $('form-message').textContent = 'Started ' + job.name + ' (' + file.name + ', ' + scalingText(options) +
                                    (options.method === 'METHOD_EXACT' ? ', exact' : '') + ')';
    follow(job.name);
  } catch (error) {
    $('form-message').className = 'message error';
    $('form-message').textContent = error.message;
  } finally {
    $('submit-job').disabled = false;
  }
}

function showScalingInput() {
  const kind = $('scaling-kind').value;
  $('level-field').hidden = kind !== 'level';
  $('factor-field').hidden = kind !== 'factor';
  $('hexes-field').hidden = kind !== 'hexes';
}

// ---- Following a job --------------------------------------------------------------------------

let source = null;     // the EventSource of the followed job
let points = [];       // {t, objective, separating}
let meshName = 'mesh';
// For tests and the curious: every event received, with the delay from its creation on the server.
window.ispq = { events: [], latenciesMs: [] };

const view = new MeshView.View({
  container: $('mesh-view'), mode: $('colour-mode'), reset: $('reset-view'), faces: $('show-faces'),
  rows: $('show-rows'), legend: $('mesh-legend'), tooltip: $('mesh-tooltip'), caption: $('mesh-caption'),
});

// The geometry of the followed job, drawn once it arrives (the events may come first: the view
// keeps the latest q and draws it then).
async function loadGeometry(name) {
  const startedAt = performance.now();
  $('mesh-status').textContent = 'loading the mesh…';
  try {
    const headers = token() ? { Authorization: 'Bearer ' + token() } : {};
    const response = await fetch('/v1/' + name + '/geometry', { headers });
    if (!response.ok) {
      let message = response.statusText;
      try { message = (await response.json()).message; } catch (e) { /* not JSON */ }
      throw new Error(message);
    }
    const buffer = await response.arrayBuffer();
    if (selected !== name) return;
    view.show(buffer, startedAt);
    $('mesh-status').textContent = '';
  } catch (error) {
    if (selected === name) $('mesh-status').textContent = 'no 3-D view: ' + error.message;
  }
}

function follow(name) {
  if (source) source.close();
  selected = name;
  view.clear();
  snapshots = [];
  replayIndex = null;
  cursorT = null;
  updateReplay();
  loadGeometry(name);
  points = [];
  window.ispq.events = [];
  window.ispq.latenciesMs = [];
  $('job-detail').hidden = false;
  $('job-title').textContent = 'Job ' + jobId(name);
  for (const id of ['job-state', 'job-phase', 'job-objective', 'job-violated', 'job-separating',
                    'job-iteration', 'job-rounds', 'job-lp-solves', 'job-elapsed', 'job-arcs']) {
    $(id).textContent = '—';
  }
  $('result').hidden = true;
  $('job-error').hidden = true;
  $('cancel-job').hidden = false;
  for (const row of $('jobs').querySelectorAll('tbody tr')) {
    row.classList.toggle('selected', row.dataset.job === name);
  }
  drawCurve();
  let url = '/v1/' + name + ':watch';
  if (token()) url += '?access_token=' + encodeURIComponent(token());
  source = new EventSource(url);  // reconnects by itself with Last-Event-ID
  const followed = source;
  source.onmessage = (message) => { if (source === followed) onEvent(JSON.parse(message.data)); };
  source.addEventListener('end', (message) => {
    followed.close();
    const status = JSON.parse(message.data);
    if (status.status !== 'OK') showError(status.status + ': ' + status.message);
    $('cancel-job').hidden = true;
  });
  source.onerror = () => {
    if (followed.readyState === EventSource.CLOSED) showError('the event stream was refused');
  };
}

function onEvent(event) {
  const delay = Date.now() - Date.parse(event.time);
  window.ispq.events.push(Number(event.sequence));
  if (Number.isFinite(delay)) window.ispq.latenciesMs.push(delay);
  if (event.accepted) {
    meshName = event.accepted.meshDisplayName || 'mesh';
    $('job-title').textContent = 'Job ' + jobId(event.job) + ' — ' + meshName;
    $('job-arcs').textContent = event.accepted.meshStats ? event.accepted.meshStats.arcs : '—';
    $('job-state').textContent = 'accepted (queue position ' + (event.accepted.queuePosition || 0) + ')';
    view.setScaling(Number(event.accepted.scaling));
  }
  if (event.intermediate) {
    view.setQ(event.intermediate.q, false);
    addSnapshot(Number(event.intermediate.progress && event.intermediate.progress.elapsedSeconds),
                event.intermediate.q, false);
  }
  const progress = event.progress || (event.intermediate && event.intermediate.progress);
  if (progress) showProgress(progress);
  if (event.result) showResult(event.result);
  if (event.error) showError(errorText(event.error));
}

function errorText(error) { return 'the job failed (code ' + (error.code || 0) + '): ' + error.message; }

function showProgress(progress) {
  $('job-state').textContent = 'running';
  $('job-phase').textContent = phaseName(progress.phase);
  $('job-objective').textContent = number(progress.objective);
  $('job-violated').textContent = progress.violatedConstraints;
  $('job-separating').textContent = progress.separating ? 'yes' : 'no';
  $('job-iteration').textContent = progress.iteration;
  $('job-rounds').textContent = progress.separationRound;
  $('job-lp-solves').textContent = progress.lpSolves;
  $('job-elapsed').textContent = number(progress.elapsedSeconds, 3) + ' s';
  points.push({ t: Number(progress.elapsedSeconds), objective: Number(progress.objective),
                separating: !!progress.separating });
  drawCurve();
}

function showResult(result) {
  view.setScaling(Number(result.scaling));
  view.setQ(result.q, true);
  view.setSeparationRows(result.separationRows || []);
  if (result.q && result.q.length) {
    const last = snapshots.length ? snapshots[snapshots.length - 1].t : 0;
    addSnapshot(Math.max(last, Number((result.stats || {}).solveSeconds || 0)), result.q, true);
  }
  $('job-state').textContent = result.termination === 'CONVERGED' ? 'succeeded' : 'ended: ' + result.termination;
  $('job-phase').textContent = 'done';
  $('job-objective').textContent = number(result.objective);
  const stats = result.stats || {};
  const last = points.length ? points[points.length - 1].t : 0;
  points.push({ t: Math.max(last, Number(stats.solveSeconds || 0)), objective: Number(result.objective),
                separating: !!result.valid });
  drawCurve();
  $('result').hidden = false;
  $('result-valid').textContent = result.valid ? 'yes' : 'NO';
  $('result-valid').className = result.valid ? 'state-SUCCEEDED' : 'state-FAILED';
  $('result-objective').textContent = result.objective;
  $('result-hexes').textContent = result.hexes;
  $('result-scaling').textContent = number(result.scaling, 6);
  $('result-termination').textContent = result.termination;
  $('result-lp-solves').textContent = stats.lpSolves;
  $('result-solve-seconds').textContent = number(stats.solveSeconds, 3) + ' s';
  $('job-lp-solves').textContent = stats.lpSolves;
  $('job-elapsed').textContent = number(stats.solveSeconds, 3) + ' s';
  // The last progress event may predate the final checks; a valid result passed all of them.
  if (result.valid) {
    $('job-violated').textContent = 0;
    $('job-separating').textContent = 'yes';
  }
  const blob = new Blob([JSON.stringify(result, null, 2) + '\n'], { type: 'application/json' });
  const link = $('download');
  if (link.href.startsWith('blob:')) URL.revokeObjectURL(link.href);
  link.href = URL.createObjectURL(blob);
  link.download = meshName + '.result.json';
  $('cancel-job').hidden = true;
}

function showError(text) {
  $('job-error').hidden = false;
  $('job-error').textContent = text;
}

async function cancelJob() {
  if (!selected) return;
  try {
    // JSON, as the server asks of a POST without credentials (a cross-site page cannot send it).
    await api('/v1/' + selected + ':cancel', {
      method: 'POST', headers: { 'Content-Type': 'application/json' } });
  } catch (error) {
    showError(error.message);
  }
}

// ---- The curve --------------------------------------------------------------------------------

function drawCurve() {
  const canvas = $('curve');
  canvas.dataset.points = String(points.length);
  canvas.dataset.cursor = cursorT === null ? '' : String(cursorT);
  const g = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height;
  const left = 70, right = 16, top = 14, bottom = 40;
  g.clearRect(0, 0, W, H);
  g.font = '12px system-ui, sans-serif';
  g.fillStyle = '#5d6777';
  g.strokeStyle = '#d8dde6';
  g.strokeRect(left, top, W - left - right, H - top - bottom);
  if (points.length === 0) {
    g.fillText('waiting for progress events…', left + 12, top + 24);
    return;
  }
  const ts = points.map((p) => p.t), ys = points.map((p) => p.objective);
  const tMax = Math.max(...ts) || 1e-3;
  let yMin = Math.min(...ys), yMax = Math.max(...ys);
  // Objectives fall by orders of magnitude early on: a log scale keeps the tail readable.
  const log = yMin > 0 && yMax / yMin > 20;
  const f = (y) => (log ? Math.log10(y) : y);
  let lo = f(yMin), hi = f(yMax);
  if (hi - lo < 1e-12) { lo -= 1; hi += 1; }
  const x = (t) => left + (t / tMax) * (W - left - right);
  const y = (v) => top + (1 - (f(v) - lo) / (hi - lo)) * (H - top - bottom);
  // Axes labels.
  g.textAlign = 'right';
  for (let i = 0; i <= 4; i++) {
    const value = log ? Math.pow(10, lo + (hi - lo) * i / 4) : lo + (hi - lo) * i / 4;
    const py = top + (1 - i / 4) * (H - top - bottom);
    g.fillText(number(value, 2), left - 6, py + 4);
    g.beginPath(); g.moveTo(left, py); g.lineTo(W - right, py); g.stroke();
  }
  g.textAlign = 'center';
  for (let i = 0; i <= 4; i++) {
    g.fillText(number(tMax * i / 4, 2) + ' s', x(tMax * i / 4), H - bottom + 16);
  }
  g.fillText('solve time', left + (W - left - right) / 2, H - 6);
  g.save(); g.translate(14, top + (H - top - bottom) / 2); g.rotate(-Math.PI / 2);
  g.fillText('objective' + (log ? ' (log)' : ''), 0, 0); g.restore();
  // The curve, then its points coloured by separation.
  g.strokeStyle = '#1f6feb';
  g.lineWidth = 2;
  g.beginPath();
  points.forEach((p, i) => (i ? g.lineTo(x(p.t), y(p.objective)) : g.moveTo(x(p.t), y(p.objective))));
  g.stroke();
  for (const p of points) {
    g.fillStyle = p.separating ? '#1a7f37' : '#b35900';
    g.beginPath(); g.arc(x(p.t), y(p.objective), 3, 0, 2 * Math.PI); g.fill();
  }
  // The time cursor: the quantization the 3-D view replays.
  if (cursorT !== null) {
    g.strokeStyle = '#c62828';
    g.lineWidth = 1.5;
    g.setLineDash([5, 4]);
    const cx = x(Math.min(cursorT, tMax));
    g.beginPath(); g.moveTo(cx, top); g.lineTo(cx, H - bottom); g.stroke();
    g.setLineDash([]);
  }
}

// ---- Replaying earlier quantizations ----------------------------------------------------------

// Every quantization received for the followed job ({t, q, final}), for the time cursor. At most
// REPLAY_MAX_VALUES arc values are kept: beyond, the oldest but the first are dropped.
const REPLAY_MAX_VALUES = 8e6;
let snapshots = [];
let replayIndex = null;  // the snapshot replayed, or null: the latest (live)
let cursorT = null;

function addSnapshot(t, q, final) {
  snapshots.push({ t: Number.isFinite(t) ? t : 0, q, final });
  while (snapshots.length > 2 && snapshots.length * q.length > REPLAY_MAX_VALUES) {
    snapshots.splice(1, 1);
    if (replayIndex !== null) replayIndex = Math.max(0, replayIndex - 1);
  }
  updateReplay();
}

function updateReplay() {
  const slider = $('replay');
  slider.max = String(Math.max(0, snapshots.length - 1));
  slider.disabled = snapshots.length < 2;
  slider.value = String(replayIndex === null ? snapshots.length - 1 : replayIndex);
  const live = replayIndex === null;
  const shown = live ? snapshots[snapshots.length - 1] : snapshots[replayIndex];
  $('replay-label').textContent = !shown ? 'none yet'
    : (live ? 'latest' : 'replaying') + ' (' + (Number(slider.value) + 1) + ' of ' + snapshots.length +
      ', at ' + number(shown.t, 3) + ' s' + (shown.final ? ', final' : '') + ')';
  view.replay(live ? null : shown.q);
  cursorT = live ? null : shown.t;
  drawCurve();
}

function onReplay() {
  const index = Number($('replay').value);
  replayIndex = index >= snapshots.length - 1 ? null : index;
  updateReplay();
}

// ---- Start ------------------------------------------------------------------------------------

$('upload-form').addEventListener('submit', submitJob);
$('scaling-kind').addEventListener('change', showScalingInput);
$('replay').addEventListener('input', onReplay);
showScalingInput();
$('cancel-job').addEventListener('click', cancelJob);
$('token').value = sessionStorage.getItem('ispq-token') || '';
$('token').addEventListener('change', () => sessionStorage.setItem('ispq-token', token()));
drawCurve();
refreshJobs();
