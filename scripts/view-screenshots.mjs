#!/usr/bin/env node
// The README's pictures of `pbs view`, taken in a headless Chromium:
//
//   node scripts/view-screenshots.mjs default --surfels d.surfels -o images/view
//
// writes sources.png (each pixel tinted by what drew it: geometry, surfels, a transition band's thinned
// prefixes) and nodes.png (node boxes with their projected size, and a clicked node seen close, its first
// 300 surfels drawn alone, with its panel: path, array, ρ(k) and capture views).
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { commandLine, withViewInBrowser } from './view-browser.mjs';

const { scene, option } = commandLine();
const output = option('-o', '');
if (!scene || !output) {
  console.error('usage: node scripts/view-screenshots.mjs SCENE [--surfels F] -o FOLDER');
  process.exit(2);
}
mkdirSync(output, { recursive: true });

await withViewInBrowser({ scene, surfels: option('--surfels', ''), width: 1300, height: 1300 }, async (page) => {
  await page.open('?size=980x760&refine=0');
  await page.waitFor('window.pbsView && window.pbsView.refined');
  await page.click('input[name=show][value=source]');
  await page.waitFor('window.pbsView.refined && window.pbsView.shown.label === "source"');
  writeFileSync(join(output, 'sources.png'), await page.screenshot());
  await page.click('input[name=show][value=surfels]');
  await page.click('#boxes');
  await page.waitFor('window.pbsView.refined && window.pbsView.shown.label === "surfels"');
  // The node under the frame's centre of mass, its panel, then a short prefix of it seen close.
  const [x, y] = await page.run(`
    const f = document.getElementById('frame'), c = document.createElement('canvas');
    c.width = f.naturalWidth; c.height = f.naturalHeight;
    const g = c.getContext('2d'); g.drawImage(f, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let sx = 0, sy = 0, n = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i + 3] === 255) { sx += (i / 4) % c.width; sy += Math.floor(i / 4 / c.width); n++; }
    for (let r = 0; r < 200; r++) for (let a = 0; a < 16; a++) {
      const px = Math.round(sx / n + r * Math.cos(a * Math.PI / 8)), py = Math.round(sy / n + r * Math.sin(a * Math.PI / 8));
      if (px >= 0 && py >= 0 && px < c.width && py < c.height && d[(py * c.width + px) * 4 + 3] === 255) return [px, py];
    }
    return [0, 0];`);
  await page.clickAt('#frame', x, y);
  await page.waitFor('window.pbsView.node && document.getElementById("node-views").naturalWidth > 0');
  await page.waitFor('document.querySelector("#rho polyline")');
  await page.click('#node-look');
  await page.waitFor('window.pbsView.refined');
  // The prefix slider (log scale) moved as a user's drag would leave it, at 300 surfels.
  await page.run(`const slider = document.getElementById('prefix');
    slider.value = Math.log(300) / Math.log(window.pbsView.node.array.surfels);
    slider.dispatchEvent(new Event('input'));`);
  await page.waitFor('window.pbsView.refined && window.pbsView.shown.label === "prefix"');
  writeFileSync(join(output, 'nodes.png'), await page.screenshot());
});
console.log('wrote ' + join(output, 'sources.png') + ' and ' + join(output, 'nodes.png'));
