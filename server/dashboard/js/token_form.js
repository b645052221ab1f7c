// The token form: saves the server's client token for this tab (sessionStorage, never the URL),
// or clears it when saved empty.
import { TOKEN_KEY } from './api.js';
import { $ } from './dom.js';
import { message } from './job_actions.js';
import { state } from './state.js';

/// `refresh` polls again at once with the new token.
export function installTokenForm(refresh) {
  $('#token-form').addEventListener('submit', (ev) => {
    ev.preventDefault();
    const v = $('#token-input').value.trim();
    if (v) sessionStorage.setItem(TOKEN_KEY, v); else sessionStorage.removeItem(TOKEN_KEY);
    $('#token-input').value = '';
    $('#token-input').placeholder = v ? 'token saved for this tab' : 'the server\'s client token';
    $('#token-needed').hidden = true;
    message(v ? 'token saved for this tab' : 'token cleared', true);
    state.previewKey = '';
    refresh();
  });
  if (sessionStorage.getItem(TOKEN_KEY)) $('#token-input').placeholder = 'token saved for this tab';
}
