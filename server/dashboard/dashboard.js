// Tessera dashboard: polls the JSON API (docs/dashboard.md) and redraws. No build step, no
// dependencies: ES modules, one per view (js/), served from the binary like this one.
import { api } from './js/api.js';
import { $ } from './js/dom.js';
import { rate } from './js/format.js';
import { installJobActions, message } from './js/job_actions.js';
import { clearPreview, installImageKind, renderDetail } from './js/job_detail.js';
import { installJobsList, jobsPath, renderJobs, takeJobs } from './js/jobs_list.js';
import { state } from './js/state.js';
import { renderStore } from './js/store_banner.js';
import { installTileMetric } from './js/tile_map.js';
import { installTokenForm } from './js/token_form.js';
import { renderWorkers } from './js/workers_list.js';

const params = new URLSearchParams(location.search);
const POLL_MS = Math.max(100, Number(params.get('poll')) || 1000);

function renderLists() {
  const t0 = performance.now();
  renderJobs();
  renderWorkers();
  document.body.dataset.renderMs = (performance.now() - t0).toFixed(1);
}

async function refresh() {
  // A change asked for while a refresh is under way (a page, a filter, a job) runs once it is
  // done.
  if (state.busy) { state.again = true; return; }
  state.busy = true; state.again = false;
  try {
    // The store's state first and on its own: it needs no query, so it is shown even when a
    // damaged store cannot answer for the jobs or the workers.
    const store = await api('/api/store').catch(() => null);
    if (store) renderStore(store);
    // One page of jobs (jobs_list.js): the bytes of a poll do not grow with the farm's history.
    const path = jobsPath();
    const [jobs, workers] = await Promise.all([api(path), api('/api/workers')]);
    takeJobs(path, jobs);
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
    if (state.again) refresh();
  }
}

function select(id) {
  state.selected = id; state.detail = null;
  clearPreview();
  message('', true);
  refresh();
}

installJobsList(select, refresh);
installJobActions(refresh);
installTokenForm(refresh);
installTileMetric();
installImageKind();
const fromHash = /job=(\d+)/.exec(location.hash);
if (fromHash) state.selected = Number(fromHash[1]);
refresh();
// A slow server never piles polls up: a tick while a refresh is under way is skipped.
state.timer = setInterval(() => { if (!state.busy) refresh(); }, POLL_MS);
