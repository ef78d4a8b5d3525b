#!/usr/bin/env node
// Measures `pbs view` as a user sees it, in a real (headless) Chromium: frames a second delivered to the
// page while the camera orbits (rendered, encoded, sent, decoded and shown), and the time from the camera
// stopping to the first still frame and to each refinement. Node's own modules only; chromedriver and
// Chromium from Debian (scripts/setup.sh installs them).
//
//   node scripts/view-fps.mjs SCENE [--surfels F] [--size 1280x720] [--seconds 10] [--step 1.5]
//                             [--screenshot FILE.png] [--json]
//
// The camera turns by --step degrees every 16 ms (a drag at 60 events a second), as the page's own drag
// handler would turn it. Everything listens on 127.0.0.1 and is stopped by its process id at the end.
import { spawn } from 'node:child_process';
import { writeFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const args = process.argv.slice(2);
const option = (name, fallback) => {
  const at = args.indexOf(name);
  return at >= 0 ? args[at + 1] : fallback;
};
const scene = args[0];
if (!scene || scene.startsWith('--')) {
  console.error('usage: node scripts/view-fps.mjs SCENE [--surfels F] [--size WxH] [--seconds S] [--step DEG] [--screenshot F] [--json]');
  process.exit(2);
}
const surfels = option('--surfels', '');
const size = option('--size', '1280x720');
const seconds = Number(option('--seconds', '10'));
const step = Number(option('--step', '1.5'));
const screenshot = option('--screenshot', '');
const json = args.includes('--json');

const freePort = () => new Promise((resolve) => {
  const server = createServer();
  server.listen(0, '127.0.0.1', () => { const { port } = server.address(); server.close(() => resolve(port)); });
});

// Starts a program and resolves with it once its output matches `pattern` (with the match).
const startAndWait = (command, commandArgs, pattern) => new Promise((resolve, reject) => {
  const child = spawn(command, commandArgs, { stdio: ['ignore', 'pipe', 'pipe'] });
  let output = '';
  const timer = setTimeout(() => reject(new Error(command + ' did not start: ' + output)), 120000);
  const read = (chunk) => {
    output += chunk;
    const match = output.match(pattern);
    if (match) { clearTimeout(timer); resolve({ child, match }); }
  };
  child.stdout.on('data', read);
  child.stderr.on('data', read);
  child.on('exit', (code) => { clearTimeout(timer); reject(new Error(command + ' exited with ' + code + ': ' + output)); });
});

const viewArgs = ['view', scene, '--port', '0'].concat(surfels ? ['--surfels', surfels] : []);
const view = await startAndWait(join(root, 'build/bin/pbs'), viewArgs, /http:\/\/127\.0\.0\.1:(\d+)\//);
const driverPort = await freePort();
const driver = await startAndWait('/usr/bin/chromedriver', ['--port=' + driverPort, '--allowed-ips=127.0.0.1'], /started successfully/);
const webdriver = async (method, path, body) => {
  const response = await fetch('http://127.0.0.1:' + driverPort + path, {
    method, headers: { 'Content-Type': 'application/json' }, body: body ? JSON.stringify(body) : undefined,
  });
  const answer = await response.json();
  if (!response.ok) throw new Error(method + ' ' + path + ': ' + JSON.stringify(answer).slice(0, 400));
  return answer.value;
};

let session = null;
try {
  const [width, height] = size.split('x').map(Number);
  session = (await webdriver('POST', '/session', { capabilities: { alwaysMatch: {
    browserName: 'chrome',
    'goog:chromeOptions': { binary: '/usr/bin/chromium', args: ['--headless=new', '--no-sandbox', '--disable-gpu',
      '--window-size=' + (width + 320) + ',' + (height + 40)] },
  } } })).sessionId;
  const at = (path) => '/session/' + session + path;
  const run = (script, scriptArgs = []) => webdriver('POST', at('/execute/sync'), { script, args: scriptArgs });
  const waitFor = async (condition, limit = 120) => {
    const deadline = Date.now() + limit * 1000;
    while (Date.now() < deadline) {
      if (await run('return Boolean(' + condition + ');')) return;
      await new Promise((r) => setTimeout(r, 50));
    }
    throw new Error('timed out waiting for ' + condition);
  };
  await webdriver('POST', at('/url'), { url: 'http://127.0.0.1:' + view.match[1] + '/?size=' + size });
  await waitFor('window.pbsView && window.pbsView.refined');

  // Orbit for `seconds`, then stop and time the still frames that follow.
  await webdriver('POST', at('/timeouts'), { script: (seconds + 120) * 1000 });
  const result = await webdriver('POST', at('/execute/async'), { args: [seconds, step], script: `
    const [seconds, step, done] = arguments;
    const view = window.pbsView;
    const movingBefore = view.movingShown;
    view.deliveredMs.length = 0;
    const start = performance.now();
    const turn = setInterval(() => {
      if (performance.now() - start < seconds * 1000) {
        view.setCamera({ az: view.camera().az + step });
        return;
      }
      clearInterval(turn);
      const stopped = performance.now();
      const moving = view.movingShown - movingBefore;
      const delivered = view.deliveredMs.slice().sort((a, b) => a - b);
      const stills = [];
      const watch = setInterval(() => {
        const shown = view.shown;
        if (shown.still && shown.at > stopped && !stills.some((s) => s.at === shown.at))
          stills.push({ label: shown.label, at: shown.at, ms: shown.at - stopped, render_ms: shown.stats.render_ms });
        if (view.refined || performance.now() - stopped > 60000) {
          clearInterval(watch);
          done({ seconds: (stopped - start) / 1000, moving_frames: moving, fps: moving / ((stopped - start) / 1000),
                 delivered_ms_median: delivered[Math.floor(delivered.length / 2)] || 0,
                 delivered_ms_p90: delivered[Math.floor(delivered.length * 0.9)] || 0,
                 stills, errors: view.errors });
        }
      }, 2);
    }, 16);` });
  if (screenshot) writeFileSync(screenshot, Buffer.from(await webdriver('GET', at('/screenshot')), 'base64'));
  if (json) {
    console.log(JSON.stringify(result, null, 2));
  } else {
    console.log(`${size}, ${result.seconds.toFixed(1)} s orbiting: ${result.moving_frames} frames shown, ` +
                `${result.fps.toFixed(1)} a second; delivered in ${result.delivered_ms_median.toFixed(1)} ms (median), ` +
                `${result.delivered_ms_p90.toFixed(1)} ms (90th percentile)`);
    for (const still of result.stills)
      console.log(`  still: ${still.label} shown ${still.ms.toFixed(0)} ms after the camera stopped (rendered in ${still.render_ms.toFixed(0)} ms)`);
    if (result.errors.length) console.log('  errors: ' + result.errors.join('; '));
  }
} finally {
  if (session) await webdriver('DELETE', '/session/' + session).catch(() => {});
  driver.child.kill('SIGTERM');
  view.child.kill('SIGINT');
}
