// Shared by scripts/view-fps.mjs and scripts/view-screenshots.mjs: starts `pbs view` and a headless
// Chromium driven through chromedriver (W3C WebDriver over HTTP, Node's own fetch), all on 127.0.0.1,
// and stops both by process id when done.
import { spawn } from 'node:child_process';
import { createServer } from 'node:net';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');

// The command line: its first argument (the scene) and `option(name, fallback)` for the value after a name.
export function commandLine() {
  const args = process.argv.slice(2);
  const option = (name, fallback) => {
    const at = args.indexOf(name);
    return at >= 0 ? args[at + 1] : fallback;
  };
  return { args, scene: args[0] && !args[0].startsWith('-') ? args[0] : '', option };
}

const freePort = () => new Promise((resolve) => {
  const server = createServer();
  server.listen(0, '127.0.0.1', () => { const { port } = server.address(); server.close(() => resolve(port)); });
});

// Starts a program and resolves with it once its output matches `pattern` (with the match).
const startAndWait = (command, args, pattern) => new Promise((resolve, reject) => {
  const child = spawn(command, args, { stdio: ['ignore', 'pipe', 'pipe'] });
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

// `pbs view SCENE [--surfels F]` and a browser window of width × height; `work` gets the page helpers.
export async function withViewInBrowser({ scene, surfels, width, height }, work) {
  const viewArgs = ['view', scene, '--port', '0'].concat(surfels ? ['--surfels', surfels] : []);
  const view = await startAndWait(join(root, 'build/bin/pbs'), viewArgs, /http:\/\/127\.0\.0\.1:(\d+)\//);
  const driverPort = await freePort();
  let driver = null, session = null;
  const webdriver = async (method, path, body) => {
    const response = await fetch('http://127.0.0.1:' + driverPort + path, {
      method, headers: { 'Content-Type': 'application/json' }, body: body ? JSON.stringify(body) : undefined,
    });
    const answer = await response.json();
    if (!response.ok) throw new Error(method + ' ' + path + ': ' + JSON.stringify(answer).slice(0, 400));
    return answer.value;
  };
  try {
    driver = await startAndWait('/usr/bin/chromedriver', ['--port=' + driverPort, '--allowed-ips=127.0.0.1'],
                                /started successfully/);
    session = (await webdriver('POST', '/session', { capabilities: { alwaysMatch: {
      browserName: 'chrome',
      'goog:chromeOptions': { binary: '/usr/bin/chromium', args: ['--headless=new', '--no-sandbox', '--disable-gpu',
        '--window-size=' + width + ',' + height] },
    } } })).sessionId;
    const at = (path) => '/session/' + session + path;
    const element = async (css) => Object.values(await webdriver('POST', at('/element'), { using: 'css selector', value: css }))[0];
    const page = {
      url: (query) => 'http://127.0.0.1:' + view.match[1] + '/' + query,
      open: (query) => webdriver('POST', at('/url'), { url: page.url(query) }),
      run: (script, args = []) => webdriver('POST', at('/execute/sync'), { script, args }),
      runAsync: async (script, args, seconds) => {
        await webdriver('POST', at('/timeouts'), { script: seconds * 1000 });
        return webdriver('POST', at('/execute/async'), { script, args });
      },
      waitFor: async (condition, seconds = 120) => {
        const deadline = Date.now() + seconds * 1000;
        while (Date.now() < deadline) {
          if (await page.run('return Boolean(' + condition + ');')) return;
          await new Promise((r) => setTimeout(r, 50));
        }
        throw new Error('timed out waiting for ' + condition);
      },
      click: async (css) => webdriver('POST', at('/element/' + (await element(css)) + '/click'), {}),
      // A click at (x, y) from the element's top-left corner (pointer offsets count from its centre).
      clickAt: async (css, x, y) => {
        const id = await element(css);
        const rect = await webdriver('GET', at('/element/' + id + '/rect'));
        await webdriver('POST', at('/actions'), { actions: [{ type: 'pointer', id: 'mouse', parameters: { pointerType: 'mouse' },
          actions: [{ type: 'pointerMove', origin: { 'element-6066-11e4-a52e-4f735466cecf': id },
                      x: Math.round(x - rect.width / 2), y: Math.round(y - rect.height / 2) },
                    { type: 'pointerDown', button: 0 }, { type: 'pointerUp', button: 0 }] }] });
      },
      screenshot: async () => Buffer.from(await webdriver('GET', at('/screenshot')), 'base64'),
    };
    return await work(page);
  } finally {
    if (session) await webdriver('DELETE', '/session/' + session).catch(() => {});
    if (driver) driver.child.kill('SIGTERM');
    view.child.kill('SIGINT');
  }
}
