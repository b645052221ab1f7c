// What the page holds between polls: the lists, the selected job and its detail, the preview
// shown, the tile map's metric, and whether a refresh is under way. The job list is one page
// (jobs_list.js): `filter` its states ('' = every state), `before` its cursor (null = the
// newest), `newer` the cursors of the pages before it (for Newer), `total` the jobs that
// match, `nextBefore` the next page's cursor (null on the last page). `again`: a refresh was
// asked for while one was under way.
// `imageKind`: the preview shown of a --denoise job, 'raw' or 'denoised'.
export const state = { jobs: [], workers: [], selected: null, detail: null, previewKey: '',
                       imageKind: 'raw',
                       metric: 'spp', timer: null, busy: false, again: false,
                       filter: '', before: null, newer: [], total: 0, nextBefore: null };
