// The web app's frequency-stability panel in a real browser (issue 48, item 6): `gmwm serve`
// on a folder holding the shipped example (data/example_imu6.csv.gz), driven in Debian's
// headless Chromium by playwright-core as a user would: open the recording, tick deviations
// among the kinds the server offers, choose the averaging times and run them; the plots must
// render, the table show the document's values, and the document be `gmwm stability --json`'s
// on the same file. Also: listed times with a confidence, exact quantiles and a fixed noise; a
// column read as phase; a time that is no whole number of periods as a message on the page.
//
//   GMWM_CLI=build/gmwm GMWM_SOURCE_DIR=. node tests/browser/serve_stability_test.mjs
//
// Exits 0 when every check holds, 1 naming the first that fails, 77 (ctest's skip) when
// Chromium or playwright-core is missing, unless GMWM_REQUIRE_BROWSER=1 (.ci/run sets it).
// Screenshots go to $GMWM_SCREENSHOT_DIR (default: browser-screenshots in the current folder).

import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, copyFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';

const here = dirname(fileURLToPath(import.meta.url));
const CHROMIUM = process.env.GMWM_CHROMIUM || '/usr/bin/chromium';
const RECORDING = 'example_imu6.csv.gz';  // 65536 samples x 6 axes at 100 Hz, shipped in data/
const STEP_TIMEOUT_MS = 60000;

function skipOrFail(why) {
  if (process.env.GMWM_REQUIRE_BROWSER === '1') {
    console.error(`FAIL: ${why} (GMWM_REQUIRE_BROWSER=1)`);
    process.exit(1);
  }
  console.log(`SKIP: ${why} (set GMWM_REQUIRE_BROWSER=1 to make this a failure)`);
  process.exit(77);
}

const cli = process.env.GMWM_CLI;
if (!cli || !existsSync(cli)) skipOrFail(`no gmwm program (GMWM_CLI=${cli})`);
if (!existsSync(CHROMIUM)) skipOrFail(`no Chromium at ${CHROMIUM} (Debian package chromium)`);
let chromium;
try {
  ({ chromium } = await import(join(here, 'node_modules', 'playwright-core', 'index.mjs')));
} catch (e) {
  skipOrFail('playwright-core is not installed (npm ci --prefix tests/browser; tools/setup.sh does it)');
}
const source = process.env.GMWM_SOURCE_DIR || join(here, '..', '..');
const shots = process.env.GMWM_SCREENSHOT_DIR || join(process.cwd(), 'browser-screenshots');
mkdirSync(shots, { recursive: true });

const folder = mkdtempSync(join(tmpdir(), 'gmwm-browser-stability-'));
copyFileSync(join(source, 'data', RECORDING), join(folder, RECORDING));

// The command line's JSON document of `args` run in the folder ("run" removed).
function cliDocument(args) {
  const r = spawnSync(cli, [...args, '--json', '-', '--quiet'], { cwd: folder, encoding: 'utf8', maxBuffer: 1 << 28 });
  assert.equal(r.status, 0, `gmwm ${args.join(' ')}: ${r.stderr}`);
  const doc = JSON.parse(r.stdout);
  delete doc.run;
  return doc;
}

// %.5g, as the stability report's table prints a deviation (report/src/stability_page.cc).
function g5(x) {
  let s = x.toPrecision(5);
  if (s.includes('e')) {
    let [m, e] = s.split('e');
    if (m.includes('.')) m = m.replace(/0+$/, '').replace(/\.$/, '');
    const n = parseInt(e, 10);
    return `${m}e${n < 0 ? '-' : '+'}${String(Math.abs(n)).padStart(2, '0')}`;
  }
  if (s.includes('.')) s = s.replace(/0+$/, '').replace(/\.$/, '');
  return s;
}

const server = spawn(cli, ['serve', folder, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
process.on('exit', () => {
  if (server.exitCode === null && server.signalCode === null) server.kill('SIGKILL');
  rmSync(folder, { recursive: true, force: true });
});
const { base: url, token } = await new Promise((resolve, reject) => {
  let out = '';
  server.stdout.on('data', (d) => {
    out += d;
    const m = /(http:\/\/127\.0\.0\.1:\d+\/)\?token=([0-9a-f]+)\s/.exec(out);
    if (m) resolve({ base: m[1], token: m[2] });
  });
  server.on('exit', (code) => reject(new Error(`gmwm serve exited with ${code}`)));
  setTimeout(() => reject(new Error('gmwm serve printed no address in 10 s')), 10000);
});

const browser = await chromium.launch({ executablePath: CHROMIUM, args: ['--no-sandbox'] });
const results = [];
let failed = false;
async function check(name, f) {
  const t0 = Date.now();
  try {
    await f();
    results.push(`ok   ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    failed = true;
    results.push(`FAIL ${name}: ${e.stack || e}`);
  }
}

const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
const page = await context.newPage();
page.setDefaultTimeout(STEP_TIMEOUT_MS);
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));

async function api(path) {
  return (await fetch(url + path, { headers: { 'X-Gmwm-Token': token } })).json();
}

async function waitStatus(text) {
  await page.waitForFunction((t) => document.getElementById('status').textContent.includes(t), text);
}

// The last job the page finished, as the server holds it; it must be a finished stability job.
async function lastStability() {
  const id = await page.getAttribute('body', 'data-gmwm-job');
  const j = await api('api/jobs/' + id);
  assert.equal(j.kind, 'stability');
  assert.equal(j.state, 'done', j.error);
  return j.result;
}

// Ticks exactly `kinds` among the panel's boxes.
async function tick(kinds) {
  for (const box of await page.$$('#stability-kinds input[type=checkbox]')) {
    const name = await box.getAttribute('value');
    if (kinds.includes(name)) await box.check();
    else await box.uncheck();
  }
}

// Neither the page's message box nor a report's error box says anything, and no script failed.
async function noErrors() {
  assert.equal(await page.isHidden('#message'), true, `the page says: ${await page.textContent('#message')}`);
  const reported = await page.$$eval('#gmwm-errors', (e) => e.map((x) => x.textContent).join(''));
  assert.equal(reported, '', 'nothing in #gmwm-errors');
  assert.deepEqual(errors, [], 'no script error');
}

await check('the panel offers the kinds, tau sets and quantiles the server lists', async () => {
  await page.goto(url + '?token=' + token);
  await waitStatus('ready');
  const offered = await api('api/stability');
  await page.waitForSelector('#stability-kinds input[value=oadev]');
  const boxes = await page.$$eval('#stability-kinds input', (xs) => xs.map((x) => [x.value, x.checked]));
  assert.deepEqual(boxes, offered.kinds.map((k) => [k.name, k.default]));
  assert.equal(boxes.length, 13, 'the library\'s thirteen kinds');
  const taus = await page.$$eval('#stability-taus option', (xs) => xs.map((x) => x.value));
  assert.deepEqual(taus, [...offered.taus, 'list']);
  assert.equal(await page.inputValue('#stability-taus'), offered.default_taus);
  assert.equal(await page.isHidden('#stability-list'), true, 'no list of times unless asked for');
  assert.equal(await page.isDisabled('#stability'), true, 'nothing to run before a recording is open');
});

await check('opening the example and running oadev, mdev, tdev, totdev at the decades draws them as gmwm stability', async () => {
  await page.selectOption('#file', RECORDING);
  await page.click('#open');
  await waitStatus('WV of gyro_x: done');
  await page.fill('#units', 'gyro=rad/s,accel=m/s^2');
  await tick(['oadev', 'mdev', 'tdev', 'totdev']);
  await page.selectOption('#stability-taus', 'decade');
  await page.click('#stability');
  await waitStatus('stability of gyro_x: done');
  await page.waitForSelector('#result .gmwm-plot[data-plot=stability][data-rendered=svg]');
  await page.waitForSelector('#result .gmwm-plot[data-plot=stability-time][data-rendered=svg]');
  const r = await lastStability();
  assert.deepEqual(r.document, cliDocument(['stability', RECORDING, '--columns', 'gyro_x', '--kind',
                                            'oadev,mdev,tdev,totdev', '--taus', 'decade', '--units',
                                            'gyro=rad/s,accel=m/s^2']));
  // The plots: each kind a curve with its band (the time deviation on its own plot, in (rad/s)*s).
  const main = await page.$eval('#result .gmwm-plot[data-plot=stability]', (e) => e.textContent);
  for (const k of ['oadev', 'mdev', 'totdev']) assert.ok(main.includes(k), `${k} in the legend: ${main}`);
  assert.ok(main.includes('deviation [rad/s]'), main);
  const time = await page.$eval('#result .gmwm-plot[data-plot=stability-time]', (e) => e.textContent);
  assert.ok(time.includes('tdev') && time.includes('deviation [(rad/s)*s]'), time);
  const marks = await page.$$eval('#result .gmwm-plot[data-plot=stability] svg path', (p) => p.length);
  assert.ok(marks > 8, `${marks} paths drawn`);
  // The table: a row per averaging time, each kind (headed by its unit) its value, interval
  // and noise as the document has them, one per line.
  const rows = await page.$$eval('#result table tr',
                                 (trs) => trs.map((tr) => [...tr.children].map((c) => c.innerText.split('\n'))));
  assert.deepEqual(rows[0], [['tau [s]'], ['oadev', '[rad/s]'], ['mdev', '[rad/s]'], ['tdev', '[(rad/s)*s]'],
                             ['totdev', '[rad/s]']]);
  const oadev = r.document.columns[0].deviations.oadev;
  assert.equal(rows.length - 1, oadev.tau.length, 'a row per decade time of oadev');
  oadev.value.forEach((v, i) => assert.deepEqual(rows[i + 1][1], [g5(v), `[${g5(oadev.ci_low[i])},\u00a0${g5(oadev.ci_high[i])}]`,
                                                                  oadev.noise[i]]));
  assert.match(await page.textContent('#result'), /68\.27% chi-square interval \(stable32 quantiles\)/);
  await noErrors();
  await page.screenshot({ path: join(shots, 'serve-stability-1.png') });
  await page.screenshot({ path: join(shots, 'serve-stability-1-full.png'), fullPage: true });
});

await check('listed times, a confidence, exact quantiles and a fixed noise give the command\'s document', async () => {
  await tick(['adev', 'hdev', 'mtie']);
  await page.selectOption('#stability-taus', 'list');
  assert.equal(await page.isVisible('#stability-list'), true, 'the list is asked for');
  await page.fill('#stability-list', '0.01,0.1,1,10');
  await page.fill('#stability-confidence', '0.95');
  await page.selectOption('#stability-intervals', 'exact');
  await page.selectOption('#stability-noise', '0');
  await page.click('#stability');
  await waitStatus('stability of gyro_x: done');
  await page.waitForSelector('#result .gmwm-plot[data-plot=stability][data-rendered=svg]');
  await page.waitForSelector('#result .gmwm-plot[data-plot=stability-time][data-rendered=svg]');
  const r = await lastStability();
  assert.deepEqual(r.document, cliDocument(['stability', RECORDING, '--columns', 'gyro_x', '--kind', 'adev,hdev,mtie',
                                            '--taus', '0.01,0.1,1,10', '--confidence', '0.95', '--intervals',
                                            'exact', '--noise-alpha', '0', '--units', 'gyro=rad/s,accel=m/s^2']));
  await noErrors();
});

await check('a column read as phase is the command\'s --data phase', async () => {
  await page.selectOption('#column', 'accel_y');
  await waitStatus('WV of accel_y: done');
  await tick(['oadev', 'tierms']);
  await page.selectOption('#stability-taus', 'octave');
  await page.fill('#stability-confidence', '');
  await page.selectOption('#stability-intervals', 'stable32');
  await page.selectOption('#stability-noise', '');
  await page.selectOption('#stability-data', 'phase');
  await page.click('#stability');
  await waitStatus('stability of accel_y: done');
  await page.waitForSelector('#result .gmwm-plot[data-plot=stability][data-rendered=svg]');
  const r = await lastStability();
  assert.deepEqual(r.document, cliDocument(['stability', RECORDING, '--columns', 'accel_y', '--kind', 'oadev,tierms',
                                            '--data', 'phase', '--units', 'gyro=rad/s,accel=m/s^2']));
  assert.match(await page.textContent('#result'), /read as phase/);
  await noErrors();
  await page.selectOption('#stability-data', 'rate');
});

await check('the three-cornered hat of three columns draws each one\'s separated deviation as gmwm stability --hat', async () => {
  await page.check('#stability-hat');
  assert.equal(await page.isVisible('#stability-hat-columns'), true, 'the hat asks for its columns');
  await page.selectOption('#stability-hat-a', 'gyro_x');
  await page.selectOption('#stability-hat-b', 'gyro_y');
  await page.selectOption('#stability-hat-c', 'gyro_z');
  await tick(['oadev', 'tdev']);
  await page.selectOption('#stability-taus', 'octave');
  await page.click('#stability');
  await waitStatus('three-cornered hat of gyro_x, gyro_y, gyro_z: done');
  await page.waitForSelector('#result .gmwm-plot[data-plot=stability-hat][data-rendered=svg]');
  const r = await lastStability();
  assert.deepEqual(r.document, cliDocument(['stability', RECORDING, '--columns', 'gyro_x,gyro_y,gyro_z', '--hat',
                                            '--kind', 'oadev,tdev', '--units', 'gyro=rad/s,accel=m/s^2']));
  const hats = await page.$$eval('#result .gmwm-plot[data-plot=stability-hat]', (e) => e.map((x) => x.textContent));
  assert.equal(hats.length, 2, 'a hat plot per kind');
  for (const c of ['gyro_x', 'gyro_y', 'gyro_z']) assert.ok(hats[0].includes(c), `${c} in the legend: ${hats[0]}`);
  assert.ok(hats[1].includes('[(rad/s)*s]'), `tdev's hat in the phase's unit: ${hats[1]}`);
  await noErrors();
  await page.screenshot({ path: join(shots, 'serve-stability-3-hat-full.png'), fullPage: true });
  await page.uncheck('#stability-hat');
});

await check('a time that is no whole number of periods is a message on the page naming "taus"', async () => {
  await page.selectOption('#stability-taus', 'list');
  await page.fill('#stability-list', '0.015');
  await page.click('#stability');
  await page.waitForSelector('#message:not([hidden])');
  const m = await page.textContent('#message');
  assert.ok(m.includes('"taus": 0.015 s is not a whole number of sampling periods of 0.01 s'), m);
  assert.ok(!m.includes('--'), `no option of the command line: ${m}`);
  assert.equal(await page.isEnabled('#stability'), true, 'the page is usable again');
  await page.screenshot({ path: join(shots, 'serve-stability-2-error.png') });
  assert.deepEqual(errors, [], 'no script error');
});

await browser.close();
const exitCode = await new Promise((resolve) => {
  server.on('exit', (code) => resolve(code));
  server.kill('SIGTERM');
  setTimeout(() => resolve('still running 10 s after SIGTERM'), 10000);
});
if (exitCode !== 0) {
  failed = true;
  results.push(`FAIL gmwm serve ended with ${exitCode} on SIGTERM`);
}
for (const r of results) console.log(r);
console.log(`screenshots in ${shots}`);
process.exit(failed ? 1 : 0);
