// The JSON API (docs/dashboard.md). With a client token on the server every API call needs it:
// the page asks for it first, keeps it in sessionStorage (never in the URL) and sends it as an
// Authorization header, images included (fetched as blobs).
import { $ } from './dom.js';

export const TOKEN_KEY = 'tessera-token';

function authHeaders(extra = {}) {
  const token = sessionStorage.getItem(TOKEN_KEY) || '';
  return token ? { ...extra, Authorization: `Bearer ${token}` } : extra;
}

async function request(path, options = {}) {
  const sent = sessionStorage.getItem(TOKEN_KEY) || '';
  const res = await fetch(path, { cache: 'no-store', ...options,
                                  headers: authHeaders(options.headers || {}) });
  // Only an answer to the token held now says anything about it: a poll sent before the token
  // was saved may come back 401 after.
  if (sent === (sessionStorage.getItem(TOKEN_KEY) || '')) {
    if (res.status === 401) askForToken();
    else if (res.ok) $('#token-needed').hidden = true;
  }
  return res;
}

export async function api(path, options = {}) {
  const res = await request(path, options);
  const body = res.headers.get('Content-Type')?.startsWith('application/json') ? await res.json() : null;
  if (!res.ok) throw Object.assign(new Error(body?.error || `HTTP ${res.status}`), { status: res.status });
  return body;
}

// An image through the API (with the token): a blob URL, or null when the server refused it.
export async function imageUrl(path) {
  const res = await request(path);
  return res.ok ? URL.createObjectURL(await res.blob()) : null;
}

function askForToken() {
  if (!$('#token-needed').hidden) return;
  $('#token-needed').hidden = false;
  $('#token-input').placeholder = 'this server needs a token';
  $('#token-input').focus();
}
