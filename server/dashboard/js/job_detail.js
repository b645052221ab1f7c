// The selected job: its state and any failure (at the top of the page), the live preview, the
// tile map, and its options, progress and provenance.
import { imageUrl } from './api.js';
import { $, dl } from './dom.js';
import { duration, errorText, jobStateText, percent, rate } from './format.js';
import { provenanceRows } from './provenance.js';
import { state } from './state.js';
import { drawTileMap } from './tile_map.js';

function renderHeading(j) {
  $('#detail-id').textContent = j.id;
  const st = $('#detail-state');
  st.textContent = jobStateText(j);
  st.className = `state state-${j.state}`;
  $('#detail-scene').textContent = `${j.scene_file} · priority ${j.priority}`;
  // Why a job failed comes first: at the top of the page (above the job list, so never below
  // the fold however many jobs there are) and above the job's images.
  // A done job whose files could not be written says so in the same places.
  const outputError = j.output_error ? `output not written: ${j.output_error}` : '';
  $('#detail-error').hidden = !j.error && !outputError;
  $('#detail-error').textContent = j.error ? `Failed: ${j.error}` : outputError;
  $('#selected-failure').hidden = !j.error && !outputError;
  $('#selected-failure').textContent = j.error ? `Job ${j.id} failed: ${j.error}`
    : outputError ? `Job ${j.id}: ${outputError}` : '';
  const final = ['done', 'failed', 'cancelled'].includes(j.state);
  $('#cancel-job').disabled = final;
  $('#set-priority').disabled = final;
  if (document.activeElement !== $('#priority-input')) $('#priority-input').value = j.priority;
}

// A new preview only when more results are merged; fetched with the token, then swapped in.
// A --denoise job shows its raw or denoised image (the toggle); the server denoises a running
// job's preview on each request, so the denoised one is asked again only when its spp grows.
function renderPreview(j) {
  const denoised = j.denoise && state.imageKind === 'denoised';
  $('#image-kind').hidden = !j.denoise;
  const key = denoised ? `${j.id}:denoised:${j.spp_merged}:${j.state}`
    : `${j.id}:${j.counters.results_merged}:${j.state}`;
  if (key === state.previewKey) return;
  state.previewKey = key;
  const url = `${j.preview_url}?${denoised ? 'denoised=1&' : ''}v=${encodeURIComponent(key)}`;
  imageUrl(url).then((url) => {
    if (!url) return;
    if (state.detail?.id !== j.id || state.previewKey !== key) { URL.revokeObjectURL(url); return; }
    const p = $('#preview');
    if (p.src.startsWith('blob:')) URL.revokeObjectURL(p.src);
    p.src = url;
    p.dataset.version = key;
    // The error estimate is the raw image's, denoised or not: the denoiser's own error is unknown.
    $('#preview-caption').textContent =
      `${denoised ? 'denoised · ' : ''}${j.spp_merged} spp merged${j.state === 'done' ? ' (final)' : ''}`
      + ` · ${j.options.width}×${j.options.height} · raw est. error ${errorText(j.relative_error)}`;
  });
}

function renderFacts(j) {
  const o = j.options;
  dl($('#detail-options'), [['size', `${o.width}×${o.height}`], ['spp', o.spp],
    ['max depth', o.max_depth], ['seed', o.seed], ['tile', o.tile_size], ['batch', o.batch_schedule === 'progressive' ? `1, 1, 2, 4, … up to ${o.batch_spp} spp` : `${o.batch_spp} spp`],
    ['isa', o.isa || 'auto'], ['units', `${j.counters.units_total} (${j.tile_count} tiles × ${j.batch_count} batches)`],
    ...(j.denoise ? [['denoise', j.guides ? 'yes, guides in the EXR' : 'yes']] : []),
    ...(j.denoise_error ? [['not denoised', j.denoise_error]] : [])]);
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
    ['NaN / Inf dropped', `${c.nan_dropped} / ${c.inf_dropped}`],
    ['renderer build', j.any_build ? 'any (--any-build)'
      : (j.pinned_build || 'not pinned yet (no unit leased)')],
    ...(j.waiting_for_build ? [['waiting', `no online worker of build ${j.pinned_build}`]] : [])]);
  // Workers of other builds may give other bits for the same unit (docs/design.md).
  const builds = j.renderer_builds || [];
  dl($('#detail-provenance'), [...provenanceRows(j.provenance), ...(builds.length > 1
    ? [['mixed builds', `${builds.length} renderer builds rendered this job: its pixels are not one build's bits`]] : [])]);
}

export function renderDetail() {
  const j = state.detail;
  $('#job-detail').hidden = !j;
  if (!j) { $('#selected-failure').hidden = true; return; }
  renderHeading(j);
  renderPreview(j);
  drawTileMap(j);
  renderFacts(j);
}

/// Switches a --denoise job's preview between its raw and denoised image.
export function installImageKind() {
  for (const r of document.querySelectorAll('input[name="image-kind"]')) {
    r.addEventListener('change', () => {
      state.imageKind = r.value;
      state.previewKey = '';
      if (state.detail) renderPreview(state.detail);
    });
  }
}

/// Forgets the preview shown (a job was selected; the next detail fetches its own).
export function clearPreview() {
  state.previewKey = '';
  const p = $('#preview');
  if (p.src.startsWith('blob:')) URL.revokeObjectURL(p.src);
  p.removeAttribute('src'); delete p.dataset.version;
}
