// What the page changes on the selected job: cancel it, set its priority, download its EXR
// (through the API with the token). Each says how it went in #action-message.
import { api, imageUrl } from './api.js';
import { $ } from './dom.js';
import { state } from './state.js';

export function message(text, ok) {
  const m = $('#action-message');
  m.textContent = text; m.className = ok ? 'ok' : 'error';
}

async function change(path, body) {
  const headers = { 'Content-Type': 'application/json' };
  try {
    await api(path, { method: 'POST', headers, body: JSON.stringify(body) });
    return true;
  } catch (e) {
    message(e.status === 401 ? `${e.message}: enter the server's token above` : e.message, false);
    if (e.status === 401) $('#token-input').focus();
    return false;
  }
}

// The EXR through the API with the token: a blob saved under the job's name.
async function downloadExr(ev) {
  ev.preventDefault();
  const j = state.detail;
  if (!j) return;
  const url = await imageUrl(j.image_url);
  if (!url) { message('the EXR could not be downloaded', false); return; }
  const a = document.createElement('a');
  a.href = url; a.download = `tessera-job-${j.id}.exr`;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 60000);
}

/// The buttons of the job's detail; `refresh` redraws the page after a change.
export function installJobActions(refresh) {
  $('#cancel-job').addEventListener('click', async () => {
    const id = state.selected;
    if (id !== null && await change(`/api/jobs/${id}/cancel`, {})) message(`job ${id} cancelled`, true);
    refresh();
  });
  $('#set-priority').addEventListener('click', async () => {
    const id = state.selected;
    const text = $('#priority-input').value.trim(), p = Number(text);
    if (text === '' || !Number.isInteger(p)) { message('priority must be an integer', false); return; }
    if (id !== null && await change(`/api/jobs/${id}/priority`, { priority: p })) {
      message(`job ${id}: priority ${p}`, true);
    }
    refresh();
  });
  $('#download-exr').addEventListener('click', downloadExr);
}
