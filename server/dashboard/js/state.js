// What the page holds between polls: the lists, the selected job and its detail, the preview
// shown, the tile map's metric, and whether a refresh is under way.
export const state = { jobs: [], workers: [], selected: null, detail: null, previewKey: '',
                       metric: 'spp', timer: null, busy: false };
