// The jobs table: one page of at most PAGE_JOBS jobs, newest first, the selected one marked; a
// click on a row selects its job. Newer/Older walk the pages by the server's cursor (`before`)
// and the state filter narrows them, so each poll fetches one page whatever the number of jobs.
import { $, esc } from './dom.js';
import { duration, errorText, jobStateText, percent, rate } from './format.js';
import { state } from './state.js';

// Rows on a page: 50, or `/?page=N` (1..1000).
export const PAGE_JOBS = Math.min(1000, Math.max(1, Math.floor(Number(
  new URLSearchParams(location.search).get('page'))) || 50));

function jobRow(j) {
  const sel = j.id === state.selected ? ' class="selected"' : '';
  return `<tr data-job-id="${j.id}" data-state="${esc(j.state)}"${sel}>
    <td class="num">${j.id}</td><td class="scene" title="${esc(j.scene_file)}">${esc(j.scene_file)}</td>
    <td><span class="state state-${esc(j.state)}">${esc(jobStateText(j))}</span></td>
    <td class="progress-col"><div class="bar" data-progress="${j.progress}"><span style="width:${(100 * j.progress).toFixed(2)}%"></span><b>${percent(j.progress)}</b></div></td>
    <td class="num">${j.spp_merged}/${j.options.spp}</td><td class="num wide">${rate(j.samples_per_s)}</td>
    <td class="num wide">${duration(j.wall_time_s)}</td><td class="num">${j.state === 'running' ? duration(j.eta_s) : '—'}</td>
    <td class="num wide">${errorText(j.relative_error)}</td><td class="num wide">${j.priority}</td></tr>`;
}

/// The /api/jobs path of the page shown: its size, filter and cursor.
export function jobsPath() {
  const query = new URLSearchParams({ limit: String(PAGE_JOBS) });
  if (state.filter) query.set('state', state.filter);
  if (state.before !== null) query.set('before', String(state.before));
  return `/api/jobs?${query}`;
}

/// Keeps an /api/jobs answer for the page asked for by `path`; an answer to a page left since
/// (the user paged or filtered while it was in flight) is dropped.
export function takeJobs(path, answer) {
  if (path !== jobsPath()) return;
  state.jobs = answer.jobs;
  state.total = answer.total;
  state.nextBefore = answer.next_before;
}

export function renderJobs() {
  $('#jobs tbody').innerHTML = state.jobs.map(jobRow).join('');
  const shown = state.jobs.length;
  $('#job-count').textContent = shown < state.total ? `(${shown} of ${state.total})` : `(${state.total})`;
  $('#no-jobs').hidden = state.total > 0 || state.filter !== '';
  $('#no-matching-jobs').hidden = shown > 0 || (state.total === 0 && state.filter === '');
  $('#jobs-newer').disabled = state.before === null;
  $('#jobs-older').disabled = state.nextBefore === null;
  $('#jobs-pager').hidden = state.before === null && state.nextBefore === null;
  $('#jobs-page').textContent = `page ${state.newer.length + 1}`;
}

/// Calls `select(id)` when a job's row is clicked, and `refresh()` when the page or the filter
/// changes.
export function installJobsList(select, refresh) {
  $('#jobs tbody').addEventListener('click', (ev) => {
    const row = ev.target.closest('tr[data-job-id]');
    if (!row) return;
    select(Number(row.dataset.jobId));
    // Narrow screens show the job above its list: bring it into view.
    if (!matchMedia('(min-width: 1200px)').matches) $('#job-detail').scrollIntoView();
  });
  const go = (before, newer) => { state.before = before; state.newer = newer; refresh(); };
  $('#jobs-older').addEventListener('click', () => {
    if (state.nextBefore !== null) go(state.nextBefore, [...state.newer, state.before]);
  });
  $('#jobs-newer').addEventListener('click', () => {
    if (state.before !== null) go(state.newer.at(-1), state.newer.slice(0, -1));
  });
  $('#jobs-newest').addEventListener('click', () => go(null, []));
  $('#job-filter').addEventListener('change', (ev) => {
    state.filter = ev.target.value;
    go(null, []);
  });
}
