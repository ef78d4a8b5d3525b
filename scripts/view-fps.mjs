#!/usr/bin/env node
// Measures `pbs view` as a user sees it, in a real (headless) Chromium: frames a second delivered to the
// page while the camera orbits (rendered, encoded, sent, decoded and shown), and the time from the camera
// stopping to the first still frame and to each refinement. Node's own modules only; chromedriver and
// Chromium from Debian (scripts/setup.sh installs them).
//
//   node scripts/view-fps.mjs SCENE [--surfels F] [--size 1280x720] [--seconds 10] [--step 1.5] [--json]
//
// The camera turns by --step degrees every 16 ms (a drag at 60 events a second), as the page's own drag
// handler would turn it. Everything listens on 127.0.0.1 and is stopped by its process id at the end.
import { commandLine, withViewInBrowser } from './view-browser.mjs';

const { args, scene, option } = commandLine();
if (!scene) {
  console.error('usage: node scripts/view-fps.mjs SCENE [--surfels F] [--size WxH] [--seconds S] [--step DEG] [--json]');
  process.exit(2);
}
const size = option('--size', '1280x720');
const seconds = Number(option('--seconds', '10'));
const step = Number(option('--step', '1.5'));
const [width, height] = size.split('x').map(Number);

const result = await withViewInBrowser({ scene, surfels: option('--surfels', ''), width: width + 320, height: height + 40 },
  async (page) => {
    await page.open('?size=' + size);
    await page.waitFor('window.pbsView && window.pbsView.refined');
    // Orbit for `seconds`, then stop and time the still frames that follow.
    return page.runAsync(`
      const [seconds, step, done] = arguments;
      const view = window.pbsView;
      const movingBefore = view.movingShown;
      view.deliveredMs.length = 0;
      view.renderMs.length = 0;
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
        const rendered = view.renderMs.slice().sort((a, b) => a - b);
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
                   render_ms_median: rendered[Math.floor(rendered.length / 2)] || 0,
                   stills, errors: view.errors });
          }
        }, 2);
      }, 16);`, [seconds, step], seconds + 120);
  });

if (args.includes('--json')) {
  console.log(JSON.stringify(result, null, 2));
} else {
  console.log(`${size}, ${result.seconds.toFixed(1)} s orbiting: ${result.moving_frames} frames shown, ` +
              `${result.fps.toFixed(1)} a second; delivered in ${result.delivered_ms_median.toFixed(1)} ms (median), ` +
              `${result.delivered_ms_p90.toFixed(1)} ms (90th percentile), rendered in ` +
              `${result.render_ms_median.toFixed(1)} ms (median)`);
  for (const still of result.stills)
    console.log(`  still: ${still.label} shown ${still.ms.toFixed(0)} ms after the camera stopped ` +
                `(rendered in ${still.render_ms.toFixed(0)} ms)`);
  if (result.errors.length) console.log('  errors: ' + result.errors.join('; '));
}
