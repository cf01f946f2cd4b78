// The web app against a hostile page in the user's own browser (issue 42's acceptance; the
// threat model of docs/serve.md): the user has opened `gmwm serve` (its cookie is in the
// browser), then visits a page served from a second loopback origin. That page tries what any
// site can: fetch the listing (with the cookie), post a text/plain form and a url-encoded one
// into a hidden frame, fetch a job and an upload without asking (no-cors), an upload that asks
// first (octet-stream: a preflight), an image and a script of the API; and a page whose domain
// re-resolves to 127.0.0.1 (DNS rebinding, Chromium's --host-resolver-rules mapping evil.test
// to loopback) loads the app's own address under its name. It can neither read the listing
// nor open a recording, start a job or store an upload: the app's own counts (GET
// /api/status, with the token) are the same before and after, and no upload file is left.
//
//   GMWM_CLI=build/gmwm node tests/browser/serve_guard_test.mjs
//
// Exits 0 when every check holds, 1 naming the first that fails, 77 (ctest's skip) when
// Chromium or playwright-core is missing, unless GMWM_REQUIRE_BROWSER=1 makes it a failure.

import { spawn, spawnSync } from 'node:child_process';
import { createServer } from 'node:http';
import { existsSync, mkdtempSync, readdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';

const here = dirname(fileURLToPath(import.meta.url));
const CHROMIUM = process.env.GMWM_CHROMIUM || '/usr/bin/chromium';
// How long the hostile page's attempts may take to settle (each is refused at once).
const ATTEMPTS_TIMEOUT_MS = 20000;

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

// The served folder: a simulated recording written by the program itself.
const folder = mkdtempSync(join(tmpdir(), 'gmwm-guard-'));
const sim = spawnSync(cli, ['simulate', '--model', 'WN(sigma2=1e-4)+RW(gamma2=1e-10)', '--n', '4096', '--freq', '100',
                            '--names', 'gyro_x', '--output', 'imu.csv', '--quiet'], { cwd: folder, encoding: 'utf8' });
assert.equal(sim.status, 0, sim.stderr);

let serverLog = '';
const server = spawn(cli, ['serve', folder, '--port', '0', '--log-level', 'info'], { stdio: ['ignore', 'pipe', 'pipe'] });
server.stderr.on('data', (d) => { serverLog += d; });
let hostile;
process.on('exit', () => {
  if (server.exitCode === null && server.signalCode === null) server.kill('SIGKILL');
  if (hostile) hostile.close();
  rmSync(folder, { recursive: true, force: true });
});
const { base: app, token, port } = await new Promise((resolve, reject) => {
  let out = '';
  server.stdout.on('data', (d) => {
    out += d;
    const m = /(http:\/\/127\.0\.0\.1:(\d+)\/)\?token=([0-9a-f]+)\s/.exec(out);
    if (m) resolve({ base: m[1], port: Number(m[2]), token: m[3] });
  });
  server.on('exit', (code) => reject(new Error(`gmwm serve exited with ${code}`)));
  setTimeout(() => reject(new Error('gmwm serve printed no address in 10 s')), 10000);
});

// What the app holds, asked with the token as a script would.
async function status() {
  const r = await fetch(app + 'api/status', { headers: { 'X-Gmwm-Token': token } });
  assert.equal(r.status, 200);
  return r.json();
}

// The hostile page, from a second loopback origin (another port of 127.0.0.1: the same site
// as the app, not the same origin). Each attempt's outcome goes to window.attempts.
const page = `<!doctype html><meta charset="utf-8"><title>a page elsewhere</title>
<iframe name="sink" style="display:none"></iframe>
<form id="plain" method="POST" enctype="text/plain" action="${app}api/open" target="sink">
  <input name='{"file": "imu.csv", "freq": 100, "x": "' value='"}'></form>
<form id="url" method="POST" action="${app}api/fit" target="sink">
  <input name="dataset" value="d"><input name="model" value="WN"></form>
<script>
const app = ${JSON.stringify(app)};
const attempts = {};
async function attempt(name, f) {
  try { attempts[name] = await f(); } catch (e) { attempts[name] = 'threw: ' + e.name; }
}
(async () => {
  await attempt('read the listing with the cookie', async () => {
    const r = await fetch(app + 'api/files', { credentials: 'include' });
    return 'read: ' + (await r.text());
  });
  await attempt('post JSON without asking (no-cors, text/plain)', async () => {
    const r = await fetch(app + 'api/open', { method: 'POST', mode: 'no-cors', credentials: 'include',
                                               body: JSON.stringify({ file: 'imu.csv', freq: 100 }) });
    return 'sent, answer ' + r.type;
  });
  await attempt('start a job without asking', async () => {
    const r = await fetch(app + 'api/fit', { method: 'POST', mode: 'no-cors', credentials: 'include',
                                              body: JSON.stringify({ dataset: 'd', column: 'gyro_x', model: 'WN' }) });
    return 'sent, answer ' + r.type;
  });
  await attempt('upload without asking', async () => {
    const r = await fetch(app + 'api/upload?name=planted.csv', { method: 'POST', mode: 'no-cors',
                                                                  credentials: 'include', body: 'timestamp,gyro_x\\n0,1\\n' });
    return 'sent, answer ' + r.type;
  });
  await attempt('upload after asking (octet-stream)', async () => {
    const r = await fetch(app + 'api/upload?name=planted2.csv', { method: 'POST', credentials: 'include',
                                                                   headers: { 'Content-Type': 'application/octet-stream' },
                                                                   body: 'timestamp,gyro_x\\n0,1\\n' });
    return 'read: ' + r.status;
  });
  await attempt('open as JSON after asking', async () => {
    const r = await fetch(app + 'api/open', { method: 'POST', credentials: 'include',
                                               headers: { 'Content-Type': 'application/json' },
                                               body: JSON.stringify({ file: 'imu.csv', freq: 100 }) });
    return 'read: ' + r.status;
  });
  await attempt('the listing as a script', () => new Promise((resolve) => {
    const s = document.createElement('script');
    s.src = app + 'api/files';
    s.onload = () => resolve('loaded');
    s.onerror = () => resolve('refused');
    document.body.appendChild(s);
  }));
  await attempt('the listing as an image', () => new Promise((resolve) => {
    const i = new Image();
    i.onload = () => resolve('loaded');
    i.onerror = () => resolve('refused');
    i.src = app + 'api/files';
  }));
  document.getElementById('plain').submit();
  await new Promise((r) => setTimeout(r, 300));
  document.getElementById('url').submit();
  await new Promise((r) => setTimeout(r, 300));
  attempts['forms'] = 'posted';
  window.attempts = attempts;
})();
</script>`;
hostile = createServer((req, res) => {
  res.writeHead(200, { 'Content-Type': 'text/html; charset=utf-8' });
  res.end(page);
});
await new Promise((r) => hostile.listen(0, '127.0.0.1', r));
const hostileUrl = `http://127.0.0.1:${hostile.address().port}/`;

// The rebound domain: evil.test resolves to 127.0.0.1 (as an attacker's DNS would answer
// once the page is loaded), so http://evil.test:PORT/ is the app's own socket under a name
// that is not the app's.
const browser = await chromium.launch({
  executablePath: CHROMIUM,
  args: ['--no-sandbox', '--host-resolver-rules=MAP evil.test 127.0.0.1'],
});
const results = [];
let failed = false;
async function check(name, f) {
  try {
    await f();
    results.push(`ok   ${name}`);
  } catch (e) {
    failed = true;
    results.push(`FAIL ${name}: ${e.stack || e}`);
  }
}

const context = await browser.newContext();
const user = await context.newPage();
let before;

await check('the user opens the app with its address: the page loads and the cookie is set', async () => {
  await user.goto(app + '?token=' + token);
  await user.waitForFunction(() => document.getElementById('status').textContent.includes('ready'));
  const cookies = await context.cookies(app);
  assert.ok(cookies.some((c) => c.name === `gmwm_serve_${port}` && c.httpOnly && c.sameSite === 'Strict'),
            JSON.stringify(cookies));
  assert.ok(!user.url().includes('token='), 'the token left the address bar: ' + user.url());
  before = await status();
});

await check('a page from a second loopback origin can neither read the listing nor open, fit or upload', async () => {
  const evil = await context.newPage();
  await evil.goto(hostileUrl);
  await evil.waitForFunction(() => window.attempts, null, { timeout: ATTEMPTS_TIMEOUT_MS });
  const a = await evil.evaluate(() => window.attempts);
  for (const [name, outcome] of Object.entries(a))
    assert.ok(!String(outcome).includes('imu.csv') && !/read: 2\d\d/.test(String(outcome)),
              `${name}: ${outcome}`);
  assert.match(a['read the listing with the cookie'], /^threw/, 'the listing was readable');
  assert.equal(a['the listing as a script'], 'refused');
  assert.equal(a['the listing as an image'], 'refused');
  await new Promise((r) => setTimeout(r, 500));  // the frames' posts land
  const after = await status();
  assert.deepEqual(after, before, 'the app holds what it held before the page came');
  const kept = readdirSync(tmpdir()).filter((d) => d.startsWith('gmwm-serve-uploads-'))
    .flatMap((d) => { try { return readdirSync(join(tmpdir(), d)); } catch { return []; } })
    .filter((f) => f.includes('planted'));
  assert.deepEqual(kept, [], 'an upload was stored');
  await evil.close();
});

await check('a rebound domain (evil.test -> 127.0.0.1) gets neither the page nor the listing', async () => {
  const evil = await context.newPage();
  for (const path of ['', '?token=' + token, 'api/files', 'app.js']) {
    const r = await evil.goto(`http://evil.test:${port}/${path}`);
    assert.equal(r.status(), 403, path);
    const text = await r.text();
    assert.ok(!text.includes('imu.csv') && text.includes('is not this server'), text);
  }
  assert.deepEqual(await status(), before);
  await evil.close();
});

await check('the user\'s own page still works after all that', async () => {
  await user.selectOption('#file', 'imu.csv');
  await user.fill('#freq', '100');
  await user.click('#open');
  await user.waitForFunction(() => /WV of gyro_x: done/.test(document.getElementById('status').textContent));
  const after = await status();
  assert.equal(after.datasets, before.datasets + 1, 'the user opened one');
});

await browser.close();
server.kill('SIGTERM');
await new Promise((r) => server.on('exit', r));
hostile.close();
for (const line of results) console.log(line);
if (failed) console.log('server log:\n' + serverLog);
process.exit(failed ? 1 : 0);
