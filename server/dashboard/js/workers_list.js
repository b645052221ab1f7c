// The workers table: one row per registered worker, what it renders, the units it holds and its
// counts, its spot checks (a quarantined worker's reason on its state) and its renderer build.
import { $, esc } from './dom.js';
import { duration, rate } from './format.js';
import { state } from './state.js';

// A quarantined worker's state says why on hover: the unit whose spot check it failed.
function quarantineTitle(w) {
  const q = w.quarantine;
  if (!q) return '';
  return ` title="${esc(`job ${q.job} · tile ${q.tile} · batch ${q.batch}: ${q.reason}`)}"`;
}

function workerRow(w) {
  const unit = w.unit ? `job ${w.unit.job_id} · tile ${w.unit.tile} · batch ${w.unit.batch}` : '—';
  return `<tr data-worker-id="${w.id}" data-state="${esc(w.state)}">
    <td>${esc(w.name)}</td><td class="num">${w.threads}</td>
    <td><span class="state state-${esc(w.state)}"${quarantineTitle(w)}>${esc(w.state)}</span></td>
    <td>${unit}</td>
    <td class="num">${w.units_held ?? 0}</td>
    <td class="num">${rate(w.samples_per_s)}</td><td class="num wide">${duration(w.last_seen_s)} ago</td>
    <td class="num wide">${w.units_done}</td><td class="num">${w.failures}</td>
    <td class="num wide">${w.checks ?? 0}</td><td class="num wide">${w.mismatches ?? 0}</td>
    <td class="wide build">${esc(w.version || '—')}</td></tr>`;
}

export function renderWorkers() {
  $('#workers tbody').innerHTML = state.workers.map(workerRow).join('');
  const online = state.workers.filter((w) => w.online).length;
  $('#worker-count').textContent = `(${online} online / ${state.workers.length})`;
  $('#no-workers').hidden = state.workers.length > 0;
}
