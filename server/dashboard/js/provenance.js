// Provenance as a person reads it: labels in words, numbers without trailing zeros
// ("spp_mean 220.000000" reads "spp mean 220"), empty values left out.
import { duration, errorText } from './format.js';

const PROVENANCE_LABELS = {
  scene_sha256: 'scene SHA-256', spp_min: 'spp min', spp_mean: 'spp mean', spp_max: 'spp max',
  stop_rule: 'stopping rule', stop_reason: 'stopped', max_depth: 'max depth', tile: 'tile size',
  batch: 'batch spp', isa: 'ISA', kernel_isa: 'kernel ISA', estimated_relative_error: 'est. error',
  tile_error_max: 'tile error max', tile_error_mean: 'tile error mean',
  wall_time_s: 'wall time', noise_target: 'noise target',
  time_budget_s: 'time budget', max_spp: 'max spp', scene_file: 'scene',
  worker_isas: 'worker ISAs', renderer_version: 'renderer', job_id: 'job',
  samples_merged: 'samples merged', nan_dropped: 'NaN dropped', inf_dropped: 'Inf dropped',
};
function provenanceValue(key, v) {
  if (key === 'wall_time_s' || key === 'time_budget_s') return duration(Number(v));
  if (key === 'estimated_relative_error' || key.startsWith('tile_error')) return errorText(Number(v));
  // Whole numbers exactly, whatever their size (a Number rounds past 2^53 and toPrecision past
  // six digits); others without trailing zeros, to six significant digits.
  if (/^-?\d+$/.test(v)) return BigInt(v).toLocaleString('en-US');
  if (/^-?\d+(\.\d+)?(e[-+]?\d+)?$/i.test(v)) {
    const x = Number(v);
    return Math.abs(x) >= 1e6 ? x.toLocaleString('en-US', { maximumFractionDigits: 1 })
                              : String(Number(x.toPrecision(6)));
  }
  return String(v).replace(/_/g, ' ');
}
export function provenanceRows(provenance) {
  return Object.entries(provenance)
    .map(([k, v]) => [k.replace('tessera:', ''), String(v ?? '').trim()])
    .filter(([k, v]) => k !== 'job_options' && v !== '' && !(k === 'stop_reason' && v === 'none'))
    .map(([k, v]) => [PROVENANCE_LABELS[k] || k.replace(/_/g, ' '),
                      k === 'scene_sha256' ? v : provenanceValue(k, v)]);
}
