// The dashboard in a real browser (Debian's headless Chromium driven by playwright-core):
//  1. a farm (server with a token + 2 workers): the page asks for the token before it shows
//     anything; the Cornell box submitted with many small units appears, its preview (fetched
//     with the token) changes at least twice while it renders, it reaches 100 %, its provenance
//     reads as words and plain numbers; a second job is cancelled from the page;
//  2. a farm with 50 jobs and 32 registered workers: every row listed, the page still quick; a
//     failed job's reason shows above its images; the store's banner while its check runs and
//     when it found damage (escaped, above the job list);
//  3. the same page at a phone's viewport: no sideways scrolling of the page;
//  4. more jobs than a page: the total, Older/Newer by the server's cursor (a job submitted
//     meanwhile shifts nothing), the state filter, every poll asking for one page, and the
//     selected job beside its list (above it on a narrower screen);
//  5. a --denoise job: a raw / denoised toggle (none for a plain job) swaps the preview, whose
//     caption keeps the raw image's error estimate.
// Screenshots go to $ARTIFACTS. Waits are bounded by a generous patience, never timed.
// Environment: TESSERA_BIN_DIR, TESSERA_SOURCE_DIR, TOOLS_DIR (setup.sh), ARTIFACTS,
// REGISTER_WORKERS (the tessera_register_workers binary).
import { spawn, execFile } from 'node:child_process';
import { createHash } from 'node:crypto';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { promisify } from 'node:util';

const env = (name) => {
  const v = process.env[name];
  if (!v) throw new Error(`${name} is not set`);
  return v;
};
const BIN = env('TESSERA_BIN_DIR');
const SRC = env('TESSERA_SOURCE_DIR');
const ARTIFACTS = env('ARTIFACTS');
const REGISTER = env('REGISTER_WORKERS');
const require = createRequire(path.join(env('TOOLS_DIR'), 'package.json'));
const { chromium } = require('playwright-core');
const run = promisify(execFile);
const PATIENCE_MS = 240_000;
const TOKEN = 'browser-test-token';

fs.mkdirSync(ARTIFACTS, { recursive: true });
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'tessera-dashboard-'));
const children = [];
let passed = 0, failed = 0;

function check(cond, what) {
  if (!cond) throw new Error(`check failed: ${what}`);
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
async function until(what, probe, patience = PATIENCE_MS) {
  const end = Date.now() + patience;
  for (;;) {
    const v = await probe();
    if (v) return v;
    if (Date.now() > end) throw new Error(`gave up waiting for ${what}`);
    await sleep(100);
  }
}

function start(name, argv) {
  const log = fs.openSync(path.join(work, `${name}.log`), 'a');
  const child = spawn(argv[0], argv.slice(1), { stdio: ['ignore', log, log] });
  children.push(child);
  return child;
}

async function startFarm(name, extra = []) {
  const dir = path.join(work, name);
  fs.mkdirSync(dir);
  const server = start(`${name}-server`, [path.join(BIN, 'tessera-server'), '--grpc', '127.0.0.1:0',
    '--port-file', path.join(dir, 'port'), '--http', '127.0.0.1:0', '--http-port-file',
    path.join(dir, 'http-port'), '--db', path.join(dir, 'farm.db'), '--output-dir',
    path.join(dir, 'outputs'), ...extra]);
  await until(`${name} server`, () => {
    if (server.exitCode !== null) throw new Error(`${name} server exited: see ${work}`);
    return fs.existsSync(path.join(dir, 'port'));
  });
  const grpc = `127.0.0.1:${fs.readFileSync(path.join(dir, 'port'), 'utf8').trim()}`;
  const http = `http://127.0.0.1:${fs.readFileSync(path.join(dir, 'http-port'), 'utf8').trim()}`;
  return { dir, grpc, http };
}

async function submit(farm, args, token = '') {
  const argv = ['--server', farm.grpc, ...(token ? ['--token', token] : []), 'submit', ...args, '--json'];
  const { stdout } = await run(path.join(BIN, 'tessera'), argv);
  return JSON.parse(stdout).id;
}

async function apiJob(farm, id, token = TOKEN) {
  const res = await fetch(`${farm.http}/api/jobs/${id}`, { headers: { Authorization: `Bearer ${token}` } });
  return res.json();
}

async function test(name, body) {
  const t0 = Date.now();
  try {
    await body();
    passed++;
    console.log(`[ OK ] ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
  } catch (e) {
    failed++;
    console.log(`[FAIL] ${name}: ${e.stack || e}`);
  }
}

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const rowState = (page, id) =>
  page.locator(`#jobs tr[data-job-id="${id}"]`).getAttribute('data-state').catch(() => null);

try {
  await test('a job renders live, reaches 100 %, and a second job is cancelled from the page', async () => {
    const farm = await startFarm('live', ['--token', TOKEN]);
    for (let i = 0; i < 2; ++i) {
      start(`live-worker-${i}`, [path.join(BIN, 'tessera-worker'), '--server', farm.grpc, '--token', TOKEN,
        '--threads', '1', '--cache', path.join(farm.dir, 'cache'), '--name', `browser-worker-${i}`]);
    }
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    const pageErrors = [];
    page.on('pageerror', (e) => pageErrors.push(String(e)));
    await page.goto(`${farm.http}/?poll=200`);
    // With a client token every read needs it: the page asks for it before showing anything.
    await page.locator('#token-needed').waitFor({ state: 'visible', timeout: PATIENCE_MS });
    check((await page.locator('#jobs tbody tr').count()) === 0, 'no jobs shown without the token');
    check((await fetch(`${farm.http}/api/jobs`)).status === 401, '/api/jobs refused without the token');
    await page.locator('#token-input').fill(TOKEN);
    await page.locator('#token-save').click();
    await page.locator('#token-needed').waitFor({ state: 'hidden', timeout: PATIENCE_MS });
    // 4 tiles x 128 batches of 2 spp: hundreds of small units, so the page sees many merges.
    const cornell = path.join(SRC, 'scenes', 'cornell.json');
    const id = await submit(farm, [cornell, '--width', '96', '--height', '96', '--tile', '48',
      '--spp', '256', '--batch', '2'], TOKEN);
    await page.locator(`#jobs tr[data-job-id="${id}"]`).waitFor({ timeout: PATIENCE_MS });
    await page.locator(`#jobs tr[data-job-id="${id}"]`).click();
    await page.locator('#detail-id', { hasText: String(id) }).waitFor({ timeout: PATIENCE_MS });

    // Every new preview the page shows is hashed by its pixels as the browser paints them.
    const seen = new Set();
    let lastVersion = null, midShot = false;
    await until('the job to reach done in the page', async () => {
      const version = await page.locator('#preview').getAttribute('data-version');
      if (version && version !== lastVersion) {
        lastVersion = version;
        const shot = await page.locator('#preview').screenshot();
        seen.add(createHash('sha256').update(shot).digest('hex'));
        if (seen.size === 2 && !midShot) {
          midShot = true;
          await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard-rendering.png'), fullPage: true });
        }
      }
      return (await rowState(page, id)) === 'done' && version?.endsWith(':done');
    });
    // The final preview too (the loop may have ended on the state before its image arrived).
    await until('the final preview', async () =>
      (await page.locator('#preview').getAttribute('data-version'))?.endsWith(':done'));
    seen.add(createHash('sha256').update(await page.locator('#preview').screenshot()).digest('hex'));
    console.log(`  distinct previews seen while rendering: ${seen.size}`);
    check(seen.size >= 3, `the preview changed at least twice (saw ${seen.size} distinct images)`);
    const bar = page.locator(`#jobs tr[data-job-id="${id}"] .bar b`);
    check((await bar.textContent()).trim() === '100 %', 'the progress bar reads 100 %');
    check((await page.locator('#detail-progress').textContent()).includes('256 / 256'), 'spp 256 / 256');
    // Provenance as words and plain numbers: "spp mean 256", never "spp_mean 256.000000".
    const provenance = await page.locator('#detail-provenance').textContent();
    check(provenance.includes('spp mean256'), `provenance reads "spp mean 256" (${provenance})`);
    check(!/\.000000|spp_mean|stop_reason/.test(provenance), `no raw keys or padded numbers (${provenance})`);
    check(await page.locator('#detail-error').isHidden(), 'no error line for a done job');
    check(await page.locator('#selected-failure').isHidden(), 'no failure banner for a done job');
    const tiles = (await apiJob(farm, id)).tiles;
    check(tiles.length === 4 && tiles.every((t) => t.spp === 256), 'every tile at 256 spp');
    await page.locator('input[name="tile-metric"][value="error"]').check();
    await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard-done.png') });
    await page.locator('input[name="tile-metric"][value="spp"]').check();

    // A second job, cancelled from the page (with the token the page already holds).
    const second = await submit(farm, [cornell, '--width', '96', '--height', '96', '--spp', '100000'], TOKEN);
    await page.locator(`#jobs tr[data-job-id="${second}"]`).click();
    await page.locator('#detail-id', { hasText: String(second) }).waitFor({ timeout: PATIENCE_MS });
    await page.locator('#cancel-job').click();
    await until('the second job to show cancelled', async () => (await rowState(page, second)) === 'cancelled');
    check((await apiJob(farm, second)).state === 'cancelled', 'the server says cancelled');
    await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard-cancelled.png') });
    check(pageErrors.length === 0, `no script errors in the page (${pageErrors.join('; ')})`);
    await page.close();
  });

  await test('50 jobs and 32 workers listed; a phone-sized screen', async () => {
    const farm = await startFarm('busy');
    await run(REGISTER, [farm.grpc, '32']);
    const tiny = path.join(SRC, 'tests', 'farm', 'data', 'tiny.json');
    // Job 1's scene has a long name: on a phone it must not push State and Progress off screen.
    const longName = path.join(work, `${'a-very-long-scene-name-'.repeat(8)}tiny.json`);
    fs.copyFileSync(tiny, longName);
    await submit(farm, [longName, '--spp', '8']);
    for (let i = 1; i < 50; i += 7) {
      const batch = [0, 1, 2, 3, 4, 5, 6].filter((k) => i + k < 50);
      await Promise.all(batch.map((k) => submit(farm, [tiny, '--spp', String(8 + i + k)])));
    }
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    await page.goto(`${farm.http}/`);
    await until('50 job rows', async () => (await page.locator('#jobs tbody tr').count()) === 50);
    await until('32 worker rows', async () => (await page.locator('#workers tbody tr').count()) === 32);
    // How long a redraw and a click take is logged, never asserted (tests are not timed).
    const renderMs = Number(await page.evaluate(() => document.body.dataset.renderMs));
    console.log(`  redraw of 50 jobs + 32 workers: ${renderMs} ms`);
    const t0 = Date.now();
    await page.locator('#jobs tr[data-job-id="17"]').click();
    await page.locator('#detail-id', { hasText: '17' }).waitFor({ timeout: PATIENCE_MS });
    console.log(`  click to details: ${Date.now() - t0} ms`);
    await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard-50-jobs.png'), fullPage: true });
    await page.close();

    // A failed job says why first, above its images. The server's real answer for job 23, with
    // its state and reason changed as a unit failing on every worker would leave them.
    const failing = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    const reason = 'tile 0 batch 0 failed on 3 workers: w1: out of memory; w2: out of memory; w3: out of memory';
    await failing.route('**/api/jobs/23', async (route) => {
      const response = await route.fetch();
      const job = await response.json();
      await route.fulfill({ response, json: { ...job, state: 'failed', error: reason } });
    });
    await failing.goto(`${farm.http}/#job=23`);
    await failing.locator('#selected-failure').waitFor({ state: 'visible', timeout: PATIENCE_MS });
    const banner = await failing.locator('#selected-failure').textContent();
    check(banner.includes('Job 23 failed') && banner.includes(reason), `the reason is shown (${banner})`);
    const bannerBox = await failing.locator('#selected-failure').boundingBox();
    check(bannerBox.y + bannerBox.height <= 900, `the reason is above the fold (y ${bannerBox.y})`);
    const errorBox = await failing.locator('#detail-error').boundingBox();
    const previewBox = await failing.locator('#preview').boundingBox();
    check((await failing.locator('#detail-error').textContent()).includes(reason), 'and in the job');
    check(!previewBox || errorBox.y < previewBox.y, 'the reason comes before the images');
    await failing.screenshot({ path: path.join(ARTIFACTS, 'dashboard-failed.png') });
    await failing.close();

    // The store's banner on every page: none for this healthy store; amber while the check after
    // an unclean stop runs, red when it found damage. /api/store answers as the server does in
    // those states (tests/dashboard/store_damage_e2e_test.cpp checks the server's side on a
    // really damaged store).
    const storePage = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    let store = null;  // null: the server's own answer
    await storePage.route('**/api/store', async (route) => {
      const response = await route.fetch();
      await route.fulfill({ response, json: store || await response.json() });
    });
    await storePage.goto(`${farm.http}/?poll=200`);
    await until('50 job rows beside the store banner', async () =>
      (await storePage.locator('#jobs tbody tr').count()) === 50);
    check(await storePage.locator('#store-banner').isHidden(), 'no store banner for a healthy store');
    store = { state: 'checking', check: 'checking', check_progress: 0.42, damage: '', leasing: true };
    await storePage.locator('#store-banner.banner-checking').waitFor({ state: 'visible', timeout: PATIENCE_MS });
    const checking = await storePage.locator('#store-banner').textContent();
    check(checking.includes('Checking the database after an unclean stop (42.0 % read)'),
          `the check and its progress are shown (${checking})`);
    const damage = 'database /var/farm/tessera.db is damaged (PRAGMA quick_check: <b>Tree 7 page 4242</b> ' +
                   'cell 3: invalid page number 99999 (and 2 more)); refusing to serve it: restore a backup';
    store = { state: 'damaged', check: 'damaged', check_progress: 0.8, damage, leasing: false };
    await storePage.locator('#store-banner.banner-damaged').waitFor({ state: 'visible', timeout: PATIENCE_MS });
    const damaged = await storePage.locator('#store-banner').textContent();
    check(damaged.includes('The database is damaged') && damaged.includes(damage),
          `SQLite's words are shown as text (${damaged})`);
    check((await storePage.locator('#store-banner b').count()) === 0, 'the damage is escaped, never markup');
    check(damaged.includes('stopped leasing') && damaged.includes('.recover') &&
          damaged.includes('docs/reliability.md'), `what stopped and what to do (${damaged})`);
    const storeBox = await storePage.locator('#store-banner').boundingBox();
    const jobsBox = await storePage.locator('#jobs').boundingBox();
    check(storeBox.y < jobsBox.y, 'the banner comes before the job list');
    const colour = await storePage.locator('#store-banner').evaluate((e) => getComputedStyle(e).borderTopColor);
    check(colour === 'rgb(248, 81, 73)', `the damaged banner is red (${colour})`);
    await storePage.screenshot({ path: path.join(ARTIFACTS, 'dashboard-store-damaged.png') });
    store = null;
    await storePage.locator('#store-banner').waitFor({ state: 'hidden', timeout: PATIENCE_MS });
    await storePage.close();

    const phone = await browser.newContext({ viewport: { width: 390, height: 844 },
                                              deviceScaleFactor: 2, isMobile: true, hasTouch: true });
    const small = await phone.newPage();
    await small.goto(`${farm.http}/`);
    await until('50 job rows on the phone', async () => (await small.locator('#jobs tbody tr').count()) === 50);
    await small.locator('#jobs tr[data-job-id="3"]').tap();
    await small.locator('#detail-id', { hasText: '3' }).waitFor({ timeout: PATIENCE_MS });
    const overflow = await small.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
    check(overflow <= 0, `the page does not scroll sideways on a phone (${overflow} px too wide)`);
    const longState = await small.locator('#jobs tr[data-job-id="1"] .state').boundingBox();
    check(longState && longState.x + longState.width <= 390,
          `a long scene name leaves the job's state on screen (${JSON.stringify(longState)})`);
    const cancelBox = await small.locator('#cancel-job').boundingBox();
    check(cancelBox && cancelBox.x >= 0 && cancelBox.x + cancelBox.width <= 390, 'cancel button on screen');
    await small.screenshot({ path: path.join(ARTIFACTS, 'dashboard-phone.png') });
    await small.screenshot({ path: path.join(ARTIFACTS, 'dashboard-phone-full.png'), fullPage: true });
    await phone.close();
  });

  await test('more jobs than a page: the total, pages, the state filter, the job beside its list', async () => {
    const farm = await startFarm('pages');
    const tiny = path.join(SRC, 'tests', 'farm', 'data', 'tiny.json');
    for (let i = 0; i < 12; i += 6) {
      await Promise.all([0, 1, 2, 3, 4, 5].map(() => submit(farm, [tiny, '--spp', '8'])));
    }
    for (const id of [2, 5, 11]) await run(path.join(BIN, 'tessera'), ['--server', farm.grpc, 'cancel', String(id)]);
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    const pageErrors = [];
    page.on('pageerror', (e) => pageErrors.push(String(e)));
    const asked = [];
    page.on('request', (r) => {
      const url = new URL(r.url());
      if (url.pathname === '/api/jobs') asked.push(url.searchParams.get('limit'));
    });
    const rows = (p) => p.locator('#jobs tbody tr').evaluateAll((trs) => trs.map((tr) => Number(tr.dataset.jobId)));
    const showing = (p, ids) => until(`rows ${ids}`, async () => JSON.stringify(await rows(p)) === JSON.stringify(ids));
    const heading = (text) => until(`heading ${text}`, async () => (await page.locator('#job-count').textContent()) === text);

    await page.goto(`${farm.http}/?page=5&poll=200`);
    await showing(page, [12, 11, 10, 9, 8]);
    await heading('(5 of 12)');
    check(await page.locator('#jobs-newer').isDisabled(), 'no newer page than the first');
    await page.locator('#jobs-older').click();
    await showing(page, [7, 6, 5, 4, 3]);
    await page.locator('#jobs-older').click();
    await showing(page, [2, 1]);
    check(await page.locator('#jobs-older').isDisabled(), 'no older page than the last');
    await page.locator('#jobs-newer').click();
    await showing(page, [7, 6, 5, 4, 3]);
    // A job submitted meanwhile counts, but this page stays where it was.
    const newest = await submit(farm, [tiny, '--spp', '8']);
    await heading('(5 of 13)');
    await showing(page, [7, 6, 5, 4, 3]);
    await page.locator('#jobs-newest').click();
    await showing(page, [newest, 12, 11, 10, 9]);

    await page.locator('#job-filter').selectOption('cancelled');
    await showing(page, [11, 5, 2]);
    await heading('(3)');
    check(await page.locator('#jobs-pager').isHidden(), 'one page: no pager');
    await page.locator('#job-filter').selectOption('queued,running');
    await showing(page, [newest, 12, 10, 9, 8]);
    await heading('(5 of 10)');
    await page.locator('#job-filter').selectOption('failed');
    await until('no failed jobs', async () => (await rows(page)).length === 0 &&
      await page.locator('#no-matching-jobs').isVisible());
    check(await page.locator('#no-jobs').isHidden(), 'the farm has jobs: no "No jobs yet"');
    await page.locator('#job-filter').selectOption('');
    await showing(page, [newest, 12, 11, 10, 9]);
    check(asked.length > 0 && asked.every((limit) => limit === '5'), `every poll asked for one page (${asked})`);

    // The selected job beside the list, not below its rows.
    await page.locator('#jobs tr[data-job-id="9"]').click();
    await page.locator('#detail-id', { hasText: '9' }).waitFor({ timeout: PATIENCE_MS });
    const list = await page.locator('#jobs-section').boundingBox();
    const detail = await page.locator('#job-detail').boundingBox();
    check(detail.x >= list.x + list.width && detail.y < list.y + list.height,
          `the job beside its list (list ${JSON.stringify(list)}, job ${JSON.stringify(detail)})`);
    await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard-pages.png') });
    check(pageErrors.length === 0, `no script errors in the page (${pageErrors.join('; ')})`);
    await page.close();

    // A narrower screen: the job above its list; the default page, 50 jobs.
    const narrow = await browser.newPage({ viewport: { width: 900, height: 900 } });
    const askedNarrow = [];
    narrow.on('request', (r) => {
      const url = new URL(r.url());
      if (url.pathname === '/api/jobs') askedNarrow.push(url.searchParams.get('limit'));
    });
    await narrow.goto(`${farm.http}/#job=4`);
    await narrow.locator('#detail-id', { hasText: '4' }).waitFor({ timeout: PATIENCE_MS });
    await until('13 rows', async () => (await rows(narrow)).length === 13);
    const above = await narrow.locator('#job-detail').boundingBox();
    const table = await narrow.locator('#jobs').boundingBox();
    check(above.y + above.height <= table.y, 'the job above its list on a narrower screen');
    check(askedNarrow.length > 0 && askedNarrow.every((limit) => limit === '50'), `pages of 50 (${askedNarrow})`);
    await narrow.close();
  });

  await test('a --denoise job\'s image toggles between raw and denoised, keeping the raw error', async () => {
    const farm = await startFarm('denoise');
    start('denoise-worker', [path.join(BIN, 'tessera-worker'), '--server', farm.grpc, '--threads', '1',
      '--cache', path.join(farm.dir, 'cache')]);
    const cornell = path.join(SRC, 'scenes', 'cornell.json');
    const plain = await submit(farm, [cornell, '--width', '48', '--height', '48', '--spp', '16']);
    const id = await submit(farm, [cornell, '--width', '48', '--height', '48', '--spp', '16', '--denoise']);
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    const pageErrors = [];
    page.on('pageerror', (e) => pageErrors.push(String(e)));
    const denoisedAsked = [];
    page.on('request', (r) => { if (r.url().includes('denoised=1')) denoisedAsked.push(r.url()); });
    await page.goto(`${farm.http}/?poll=200#job=${plain}`);
    await until('the plain job done', async () => (await rowState(page, plain)) === 'done');
    check(await page.locator('#image-kind').isHidden(), 'no raw / denoised toggle for a plain job');
    await page.locator(`#jobs tr[data-job-id="${id}"]`).click();
    await until('the denoise job done in the page', async () =>
      (await page.locator('#preview').getAttribute('data-version'))?.startsWith(`${id}:`) &&
      (await page.locator('#preview').getAttribute('data-version')).endsWith(':done'));
    check(await page.locator('#image-kind').isVisible(), 'a raw / denoised toggle for a --denoise job');
    const hash = async () => createHash('sha256').update(await page.locator('#preview').screenshot()).digest('hex');
    const raw = await hash();
    const rawCaption = await page.locator('#preview-caption').textContent();
    await page.locator('input[name="image-kind"][value="denoised"]').check();
    await until('the denoised preview', async () =>
      (await page.locator('#preview').getAttribute('data-version'))?.includes(':denoised:'));
    check(denoisedAsked.length > 0, 'the page asked for ?denoised=1');
    check(await hash() !== raw, 'the denoised image differs from the raw one');
    const caption = await page.locator('#preview-caption').textContent();
    check(caption.startsWith('denoised') && caption.includes('raw est. error'),
          `the caption says denoised and keeps the raw error (${caption})`);
    check(rawCaption.endsWith(caption.slice(caption.indexOf('raw est. error'))),
          `the same raw error estimate both ways (${rawCaption} / ${caption})`);
    await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard-denoised.png') });
    await page.locator('input[name="image-kind"][value="raw"]').check();
    await until('the raw preview again', async () => (await hash()) === raw);
    check(pageErrors.length === 0, `no script errors in the page (${pageErrors.join('; ')})`);
    await page.close();
  });
} finally {
  await browser.close();
  for (const c of children) if (c.exitCode === null) c.kill('SIGTERM');
  await sleep(500);
  for (const c of children) if (c.exitCode === null) c.kill('SIGKILL');
  if (failed === 0) fs.rmSync(work, { recursive: true, force: true });
  else console.log(`logs kept in ${work}`);
  console.log(`${passed} passed, ${failed} failed`);
  process.exitCode = failed === 0 ? 0 : 1;
}
