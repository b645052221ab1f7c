// The tile map: each tile coloured by its samples per pixel (of the target) or by its estimated
// relative error (log scale between the smallest and largest over the tiles).
import { $ } from './dom.js';
import { state } from './state.js';

function heat(t) {
  t = Math.min(1, Math.max(0, t));
  const stops = [[13, 8, 135], [126, 3, 168], [204, 71, 120], [248, 149, 64], [240, 249, 33]];
  const x = t * (stops.length - 1), i = Math.min(stops.length - 2, Math.floor(x)), f = x - i;
  const c = stops[i].map((v, k) => Math.round(v + f * (stops[i + 1][k] - v)));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}

export function drawTileMap(j) {
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

/// Redraws the map when the metric (samples or error) is switched.
export function installTileMetric() {
  for (const r of document.querySelectorAll('input[name="tile-metric"]')) {
    r.addEventListener('change', () => { state.metric = r.value; if (state.detail) drawTileMap(state.detail); });
  }
}
