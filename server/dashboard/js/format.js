// Numbers as the page shows them: durations, rates, percentages, relative errors ('—' for none);
// a job's state with what it says about renderer builds.
export function duration(s) {
  if (s === null || s === undefined || !isFinite(s)) return '—';
  s = Math.max(0, Math.round(s));
  const h = Math.floor(s / 3600), m = Math.floor((s % 3600) / 60), sec = s % 60;
  return h ? `${h}h ${m}m` : m ? `${m}m ${sec}s` : `${sec}s`;
}
export function rate(v) {
  if (!v) return '—';
  const units = [[1e9, 'G'], [1e6, 'M'], [1e3, 'k']];
  for (const [f, u] of units) if (v >= f) return (v / f).toFixed(1) + u;
  return v.toFixed(0);
}
export function percent(x) { return (100 * x).toFixed(x >= 1 ? 0 : 1) + ' %'; }
export function errorText(e) { return e === null || e === undefined ? '—' : (100 * e).toFixed(2) + ' %'; }
// Beside the state: several builds rendered it (--any-build), or no online worker is of its build.
export function jobStateText(j) {
  const builds = (j.renderer_builds || []).length;
  return j.state + (builds > 1 ? ` (${builds} renderer builds)` : '')
    + (j.waiting_for_build ? ' (waiting for its build)' : '');
}
