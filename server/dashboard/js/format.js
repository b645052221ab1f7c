// Numbers as the page shows them: durations, rates, percentages, relative errors ('—' for none).
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
