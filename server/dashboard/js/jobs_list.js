// The jobs table: one row per job, the selected one marked; a click on a row selects its job.
import { $, esc } from './dom.js';
import { duration, errorText, percent, rate } from './format.js';
import { state } from './state.js';

function jobRow(j) {
  const sel = j.id === state.selected ? ' class="selected"' : '';
  return `<tr data-job-id="${j.id}" data-state="${esc(j.state)}"${sel}>
    <td class="num">${j.id}</td><td class="scene" title="${esc(j.scene_file)}">${esc(j.scene_file)}</td>
    <td><span class="state state-${esc(j.state)}">${esc(j.state)}</span></td>
    <td class="progress-col"><div class="bar" data-progress="${j.progress}"><span style="width:${(100 * j.progress).toFixed(2)}%"></span><b>${percent(j.progress)}</b></div></td>
    <td class="num">${j.spp_merged}/${j.options.spp}</td><td class="num wide">${rate(j.samples_per_s)}</td>
    <td class="num wide">${duration(j.wall_time_s)}</td><td class="num">${j.state === 'running' ? duration(j.eta_s) : '—'}</td>
    <td class="num wide">${errorText(j.relative_error)}</td><td class="num wide">${j.priority}</td></tr>`;
}

export function renderJobs() {
  $('#jobs tbody').innerHTML = state.jobs.map(jobRow).join('');
  $('#job-count').textContent = `(${state.jobs.length})`;
  $('#no-jobs').hidden = state.jobs.length > 0;
}

/// Calls `select(id)` when a job's row is clicked.
export function installJobsList(select) {
  $('#jobs tbody').addEventListener('click', (ev) => {
    const row = ev.target.closest('tr[data-job-id]');
    if (row) select(Number(row.dataset.jobId));
  });
}
