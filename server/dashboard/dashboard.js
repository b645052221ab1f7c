// Tessera dashboard: polls the JSON API (docs/dashboard.md) and redraws. No build step, no
// dependencies. With a client token on the server every API call needs it: the page asks for it
// first, keeps it in sessionStorage (never in the URL) and sends it as an Authorization header,
// images included (fetched as blobs).
'use strict';

const params = new URLSearchParams(location.search);
const POLL_MS = Math.max(100, Number(params.get('poll')) || 1000);
const TOKEN_KEY = 'tessera-token';
const $ = (sel) => document.querySelector(sel);

const state = { jobs: [], workers: [], selected: null, detail: null, previewKey: '',
                metric: 'spp', timer: null, busy: false };

function esc(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;',
                                                 '"': '&quot;', "'": '&#39;' }[c]));
}
function duration(s) {
  if (s === null || s === undefined || !isFinite(s)) return '—';
  s = Math.max(0, Math.round(s));
  const h = Math.floor(s / 3600), m = Math.floor((s % 3600) / 60), sec = s % 60;
  return h ? `${h}h ${m}m` : m ? `${m}m ${sec}s` : `${sec}s`;
}
function rate(v) {
  if (!v) return '—';
  const units = [[1e9, 'G'], [1e6, 'M'], [1e3, 'k']];
  for (const [f, u] of units) if (v >= f) return (v / f).toFixed(1) + u;
  return v.toFixed(0);
}
function percent(x) { return (100 * x).toFixed(x >= 1 ? 0 : 1) + ' %'; }
function errorText(e) { return e === null || e === undefined ? '—' : (100 * e).toFixed(2) + ' %'; }

function authHeaders(extra = {}) {
  const token = sessionStorage.getItem(TOKEN_KEY) || '';
  return token ? { ...extra, Authorization: `Bearer ${token}` } : extra;
}

async function request(path, options = {}) {
  const sent = sessionStorage.getItem(TOKEN_KEY) || '';
  const res = await fetch(path, { cache: 'no-store', ...options,
                                  headers: authHeaders(options.headers || {}) });
  // Only an answer to the token held now says anything about it: a poll sent before the token
  // was saved may come back 401 after.
  if (sent === (sessionStorage.getItem(TOKEN_KEY) || '')) {
    if (res.status === 401) askForToken();
    else if (res.ok) $('#token-needed').hidden = true;
  }
  return res;
}

async function api(path, options = {}) {
  const res = await request(path, options);
  const body = res.headers.get('Content-Type')?.startsWith('application/json') ? await res.json() : null;
  if (!res.ok) throw Object.assign(new Error(body?.error || `HTTP ${res.status}`), { status: res.status });
  return body;
}

// An image through the API (with the token): a blob URL, or null when the server refused it.
async function imageUrl(path) {
  const res = await request(path);
  return res.ok ? URL.createObjectURL(await res.blob()) : null;
}

function askForToken() {
  if (!$('#token-needed').hidden) return;
  $('#token-needed').hidden = false;
  $('#token-input').placeholder = 'this server needs a token';
  $('#token-input').focus();
}

function jobRow(j) {
  const sel = j.id === state.selected ? ' class="selected"' : '';
  return `<tr data-job-id="${j.id}" data-state="${esc(j.state)}"${sel}>
    <td class="num">${j.id}</td><td>${esc(j.scene_file)}</td>
    <td><span class="state state-${esc(j.state)}">${esc(j.state)}</span></td>
    <td class="progress-col"><div class="bar" data-progress="${j.progress}"><span style="width:${(100 * j.progress).toFixed(2)}%"></span><b>${percent(j.progress)}</b></div></td>
    <td class="num">${j.spp_merged}/${j.options.spp}</td><td class="num wide">${rate(j.samples_per_s)}</td>
    <td class="num wide">${duration(j.wall_time_s)}</td><td class="num">${j.state === 'running' ? duration(j.eta_s) : '—'}</td>
    <td class="num wide">${errorText(j.relative_error)}</td><td class="num wide">${j.priority}</td></tr>`;
}

function workerRow(w) {
  const unit = w.unit ? `job ${w.unit.job_id} · tile ${w.unit.tile} · batch ${w.unit.batch}` : '—';
  return `<tr data-worker-id="${w.id}" data-state="${esc(w.state)}">
    <td>${esc(w.name)}</td><td class="num">${w.threads}</td>
    <td><span class="state state-${esc(w.state)}">${esc(w.state)}</span></td><td>${unit}</td>
    <td class="num">${rate(w.samples_per_s)}</td><td class="num wide">${duration(w.last_seen_s)} ago</td>
    <td class="num wide">${w.units_done}</td><td class="num">${w.failures}</td></tr>`;
}

// The store's banner, above everything on every page (docs/dashboard.md, "The store"): amber
// while the database is checked after an unclean stop, red when the check found damage. The
// damage is SQLite's words: shown escaped, at most its first lines.
const STORE_DAMAGE_LINES = 6;
function renderStore(store) {
  const banner = $('#store-banner');
  const shown = store && store.state !== 'ok' ? store.state : '';
  banner.hidden = !shown;
  banner.className = shown ? `banner banner-${shown}` : '';
  banner.dataset.state = shown || 'ok';
  if (!shown) { banner.innerHTML = ''; return; }
  if (shown === 'checking') {
    const read = store.check_progress === null || store.check_progress === undefined
      ? '' : ` (${percent(store.check_progress)} read)`;
    banner.innerHTML = `<strong>Checking the database after an unclean stop${esc(read)}.</strong>
      The farm serves meanwhile; if the check (PRAGMA quick_check) finds damage, the server stops
      handing out work and this banner turns red.`;
    return;
  }
  const lines = String(store.damage).split('\n');
  const first = lines.slice(0, STORE_DAMAGE_LINES).join('\n') +
                (lines.length > STORE_DAMAGE_LINES ? '\n…' : '');
  banner.innerHTML = `<strong>The database is damaged.</strong> SQLite reported:
    <pre>${esc(first)}</pre>
    <p>The server has stopped leasing: workers get no more work (uploads of units already leased
    still commit), and <code>/readyz</code> fails. Stop the server, then restore the database
    from a backup, or salvage what SQLite can read with
    <code>sqlite3 DB .recover | sqlite3 NEW.db</code> and start on the new file; see
    docs/reliability.md, "A consistent database after any crash".</p>`;
}

function renderLists() {
  const t0 = performance.now();
  $('#jobs tbody').innerHTML = state.jobs.map(jobRow).join('');
  $('#job-count').textContent = `(${state.jobs.length})`;
  $('#no-jobs').hidden = state.jobs.length > 0;
  $('#workers tbody').innerHTML = state.workers.map(workerRow).join('');
  const online = state.workers.filter((w) => w.online).length;
  $('#worker-count').textContent = `(${online} online / ${state.workers.length})`;
  $('#no-workers').hidden = state.workers.length > 0;
  document.body.dataset.renderMs = (performance.now() - t0).toFixed(1);
}

// Provenance as a person reads it: labels in words, numbers without trailing zeros
// ("spp_mean 220.000000" reads "spp mean 220"), empty values left out.
const PROVENANCE_LABELS = {
  scene_sha256: 'scene SHA-256', spp_min: 'spp min', spp_mean: 'spp mean', spp_max: 'spp max',
  stop_rule: 'stopping rule', stop_reason: 'stopped', max_depth: 'max depth', tile: 'tile size',
  batch: 'batch spp', isa: 'ISA', estimated_relative_error: 'est. error',
  tile_error_max: 'tile error max', tile_error_mean: 'tile error mean',
  nan_inf_dropped: 'NaN / Inf dropped', wall_time_s: 'wall time', noise_target: 'noise target',
  time_budget_s: 'time budget', max_spp: 'max spp', scene_file: 'scene',
  worker_isas: 'worker ISAs', renderer_version: 'renderer', job_id: 'job',
  samples_merged: 'samples merged', nan_dropped: 'NaN dropped', inf_dropped: 'Inf dropped',
};
function provenanceValue(key, v) {
  if (key === 'wall_time_s' || key === 'time_budget_s') return duration(Number(v));
  if (key === 'estimated_relative_error' || key.startsWith('tile_error')) return errorText(Number(v));
  if (/^-?\d+(\.\d+)?(e[-+]?\d+)?$/i.test(v)) return String(Number(Number(v).toPrecision(6)));
  return String(v).replace(/_/g, ' ');
}
function provenanceRows(provenance) {
  return Object.entries(provenance)
    .map(([k, v]) => [k.replace('tessera:', ''), String(v ?? '').trim()])
    .filter(([k, v]) => k !== 'job_options' && v !== '' && !(k === 'stop_reason' && v === 'none'))
    .map(([k, v]) => [PROVENANCE_LABELS[k] || k.replace(/_/g, ' '),
                      k === 'scene_sha256' ? v : provenanceValue(k, v)]);
}

function dl(el, pairs) {
  el.innerHTML = pairs.map(([k, v]) => `<dt>${esc(k)}</dt><dd>${esc(v)}</dd>`).join('');
}

function renderDetail() {
  const j = state.detail;
  $('#job-detail').hidden = !j;
  if (!j) { $('#selected-failure').hidden = true; return; }
  $('#detail-id').textContent = j.id;
  const st = $('#detail-state');
  st.textContent = j.state; st.className = `state state-${j.state}`;
  $('#detail-scene').textContent = `${j.scene_file} · priority ${j.priority}`;
  // Why a job failed comes first: at the top of the page (above the job list, so never below
  // the fold however many jobs there are) and above the job's images.
  $('#detail-error').hidden = !j.error;
  $('#detail-error').textContent = j.error ? `Failed: ${j.error}` : '';
  $('#selected-failure').hidden = !j.error;
  $('#selected-failure').textContent = j.error ? `Job ${j.id} failed: ${j.error}` : '';
  const final = ['done', 'failed', 'cancelled'].includes(j.state);
  $('#cancel-job').disabled = final;
  $('#set-priority').disabled = final;
  if (document.activeElement !== $('#priority-input')) $('#priority-input').value = j.priority;
  // A new preview only when more results are merged; fetched with the token, then swapped in.
  const key = `${j.id}:${j.counters.results_merged}:${j.state}`;
  if (key !== state.previewKey) {
    state.previewKey = key;
    imageUrl(`${j.preview_url}?v=${encodeURIComponent(key)}`).then((url) => {
      if (!url) return;
      if (state.detail?.id !== j.id || state.previewKey !== key) { URL.revokeObjectURL(url); return; }
      const p = $('#preview');
      if (p.src.startsWith('blob:')) URL.revokeObjectURL(p.src);
      p.src = url;
      p.dataset.version = key;
      $('#preview-caption').textContent =
        `${j.spp_merged} spp merged${j.state === 'done' ? ' (final)' : ''} · ${j.options.width}×${j.options.height}`;
    });
  }
  drawTileMap(j);
  const o = j.options;
  dl($('#detail-options'), [['size', `${o.width}×${o.height}`], ['spp', o.spp],
    ['max depth', o.max_depth], ['seed', o.seed], ['tile', o.tile_size], ['batch', `${o.batch_spp} spp`],
    ['isa', o.isa || 'auto'], ['units', `${j.counters.units_total} (${j.tile_count} tiles × ${j.batch_count} batches)`]]);
  const c = j.counters;
  const rule = j.stop_rule === 'time' ? `time ${j.options.time_budget_s} s (max ${j.options.spp} spp)`
    : j.stop_rule === 'noise' ? `noise ${j.options.noise_target} (max ${j.options.spp} spp)` : `${j.options.spp} spp`;
  const r = j.reached;
  dl($('#detail-progress'), [['stopping rule', rule], ...(j.stop_reason ? [['stopped', j.stop_reason.replace(/_/g, ' ')]] : []),
    ['progress', percent(j.progress)], ['spp reached', `${j.spp_merged} / ${j.options.spp}`],
    ...(j.stop_rule !== 'spp' ? [['spp per tile', `min ${r.spp_min} · mean ${r.spp_mean.toFixed(1)} · max ${r.spp_max}`],
      ['tiles finished', `${r.tiles_finished} / ${j.tile_count}`]] : []),
    ['samples/s', rate(j.samples_per_s)], ['elapsed', duration(j.wall_time_s)],
    ['ETA', j.state === 'running' ? duration(j.eta_s) : '—'], ['est. error', errorText(j.relative_error)],
    ['units done', `${c.units_done} / ${c.units_total}`], ['leased now', c.units_leased],
    ['leases expired', c.leases_expired], ['results dropped', c.results_dropped],
    ['NaN / Inf dropped', `${c.nan_dropped} / ${c.inf_dropped}`]]);
  // Workers of other builds may give other bits for the same unit (docs/design.md).
  const builds = j.renderer_builds || [];
  dl($('#detail-provenance'), [...provenanceRows(j.provenance), ...(builds.length > 1
    ? [['mixed builds', `${builds.length} renderer builds rendered this job: its pixels are not one build's bits`]] : [])]);
}

// Heat map: each tile coloured by its samples per pixel (of the target) or by its estimated
// relative error (log scale between the smallest and largest over the tiles).
function heat(t) {
  t = Math.min(1, Math.max(0, t));
  const stops = [[13, 8, 135], [126, 3, 168], [204, 71, 120], [248, 149, 64], [240, 249, 33]];
  const x = t * (stops.length - 1), i = Math.min(stops.length - 2, Math.floor(x)), f = x - i;
  const c = stops[i].map((v, k) => Math.round(v + f * (stops[i + 1][k] - v)));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}
function drawTileMap(j) {
  const canvas = $('#tile-map');
  const w = j.options.width, h = j.options.height;
  const scale = Math.max(1, Math.floor(512 / Math.max(w, h)));
  if (canvas.width !== w * scale || canvas.height !== h * scale) {
    canvas.width = w * scale; canvas.height = h * scale;
  }
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#000'; ctx.fillRect(0, 0, canvas.width, canvas.height);
  const errors = j.tiles.map((t) => t.relative_error).filter((e) => e > 0);
  const lo = Math.log(Math.min(...errors)), hi = Math.log(Math.max(...errors));
  for (const t of j.tiles) {
    let v = null, label = '';
    if (state.metric === 'spp') { v = t.spp / j.options.spp; label = String(t.spp); }
    else if (t.relative_error > 0) {
      v = hi > lo ? (Math.log(t.relative_error) - lo) / (hi - lo) : 0.5;
      label = (100 * t.relative_error).toFixed(1) + '%';
    }
    const x = t.x0 * scale, y = t.y0 * scale, tw = (t.x1 - t.x0) * scale, th = (t.y1 - t.y0) * scale;
    ctx.fillStyle = v === null ? '#222' : heat(v);
    ctx.fillRect(x, y, tw, th);
    ctx.strokeStyle = '#000'; ctx.strokeRect(x + 0.5, y + 0.5, tw - 1, th - 1);
    if (label && tw >= 36 && th >= 16) {
      ctx.fillStyle = v !== null && v > 0.6 ? '#000' : '#fff';
      ctx.font = `${Math.min(14, th / 3)}px system-ui`;
      ctx.fillText(label, x + 4, y + Math.min(16, th / 2));
    }
  }
  $('#tile-legend').textContent = state.metric === 'spp'
    ? `dark: 0 spp · bright: ${j.options.spp} spp`
    : errors.length ? `dark: ${(100 * Math.exp(lo)).toFixed(2)} % · bright: ${(100 * Math.exp(hi)).toFixed(2)} %`
                    : 'no estimate yet (needs 2 spp)';
}

async function refresh() {
  if (state.busy) return;  // a slow server never piles requests up
  state.busy = true;
  try {
    // The store's state first and on its own: it needs no query, so it is shown even when a
    // damaged store cannot answer for the jobs or the workers.
    const store = await api('/api/store').catch(() => null);
    if (store) renderStore(store);
    const [jobs, workers] = await Promise.all([api('/api/jobs'), api('/api/workers')]);
    state.jobs = jobs.jobs;
    state.workers = workers.workers;
    $('#farm-rate').textContent = `${rate(jobs.samples_per_s)} samples/s`;
    if (state.selected === null && state.jobs.length) {
      const running = state.jobs.find((j) => j.state === 'running');
      state.selected = (running || state.jobs[0]).id;
    }
    renderLists();
    if (state.selected !== null) {
      try { state.detail = await api(`/api/jobs/${state.selected}`); }
      catch (e) { if (e.status === 404) { state.selected = null; state.detail = null; } else throw e; }
      renderDetail();
    }
    $('#conn').textContent = '';
  } catch (e) {
    $('#conn').textContent = `⚠ ${e.message}`;
  } finally {
    state.busy = false;
  }
}

function message(text, ok) {
  const m = $('#action-message');
  m.textContent = text; m.className = ok ? 'ok' : 'error';
}

async function change(path, body) {
  const headers = { 'Content-Type': 'application/json' };
  try {
    await api(path, { method: 'POST', headers, body: JSON.stringify(body) });
    return true;
  } catch (e) {
    message(e.status === 401 ? `${e.message}: enter the server's token above` : e.message, false);
    if (e.status === 401) $('#token-input').focus();
    return false;
  }
}

function select(id) {
  state.selected = id; state.detail = null; state.previewKey = '';
  const p = $('#preview');
  if (p.src.startsWith('blob:')) URL.revokeObjectURL(p.src);
  p.removeAttribute('src'); delete p.dataset.version;
  message('', true);
  refresh();
}

$('#jobs tbody').addEventListener('click', (ev) => {
  const row = ev.target.closest('tr[data-job-id]');
  if (row) select(Number(row.dataset.jobId));
});
$('#cancel-job').addEventListener('click', async () => {
  const id = state.selected;
  if (id !== null && await change(`/api/jobs/${id}/cancel`, {})) message(`job ${id} cancelled`, true);
  refresh();
});
$('#set-priority').addEventListener('click', async () => {
  const id = state.selected;
  const text = $('#priority-input').value.trim(), p = Number(text);
  if (text === '' || !Number.isInteger(p)) { message('priority must be an integer', false); return; }
  if (id !== null && await change(`/api/jobs/${id}/priority`, { priority: p })) {
    message(`job ${id}: priority ${p}`, true);
  }
  refresh();
});
$('#token-form').addEventListener('submit', (ev) => {
  ev.preventDefault();
  const v = $('#token-input').value.trim();
  if (v) sessionStorage.setItem(TOKEN_KEY, v); else sessionStorage.removeItem(TOKEN_KEY);
  $('#token-input').value = '';
  $('#token-input').placeholder = v ? 'token saved for this tab' : 'the server\'s client token';
  $('#token-needed').hidden = true;
  message(v ? 'token saved for this tab' : 'token cleared', true);
  state.previewKey = '';
  refresh();
});
// The EXR through the API with the token: a blob saved under the job's name.
$('#download-exr').addEventListener('click', async (ev) => {
  ev.preventDefault();
  const j = state.detail;
  if (!j) return;
  const url = await imageUrl(j.image_url);
  if (!url) { message('the EXR could not be downloaded', false); return; }
  const a = document.createElement('a');
  a.href = url; a.download = `tessera-job-${j.id}.exr`;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 60000);
});
for (const r of document.querySelectorAll('input[name="tile-metric"]')) {
  r.addEventListener('change', () => { state.metric = r.value; if (state.detail) drawTileMap(state.detail); });
}
if (sessionStorage.getItem(TOKEN_KEY)) $('#token-input').placeholder = 'token saved for this tab';
const fromHash = /job=(\d+)/.exec(location.hash);
if (fromHash) state.selected = Number(fromHash[1]);
refresh();
state.timer = setInterval(refresh, POLL_MS);
