// The store's banner, above everything on every page (docs/dashboard.md, "The store"): amber
// while the database is checked after an unclean stop, red when the check found damage or the
// store cannot write (a full disk). SQLite's words are shown escaped, at most their first lines.
import { $, esc } from './dom.js';
import { percent } from './format.js';

const STORE_DAMAGE_LINES = 6;

export function renderStore(store) {
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
  if (shown === 'full') {
    banner.innerHTML = `<strong>The database cannot write: its disk is full.</strong>
      SQLite reported:
      <pre>${esc(firstLines(store.write_error))}</pre>
      <p>Uploads of results and new submissions fail until there is space; what is stored can
      still be read, and <code>/readyz</code> fails meanwhile. Free space on the database's disk:
      the server notices within seconds and this banner goes away; see docs/reliability.md,
      "A full disk".</p>`;
    return;
  }
  banner.innerHTML = `<strong>The database is damaged.</strong> SQLite reported:
    <pre>${esc(firstLines(store.damage))}</pre>
    <p>The server has stopped leasing: workers get no more work (uploads of units already leased
    still commit), and <code>/readyz</code> fails. Stop the server, then restore the database
    from a backup, or salvage what SQLite can read with
    <code>sqlite3 DB .recover | sqlite3 NEW.db</code> and start on the new file; see
    docs/reliability.md, "A consistent database after any crash".</p>`;
}

function firstLines(text) {
  const lines = String(text).split('\n');
  return lines.slice(0, STORE_DAMAGE_LINES).join('\n') +
         (lines.length > STORE_DAMAGE_LINES ? '\n…' : '');
}
