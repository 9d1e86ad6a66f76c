// One frame of an exported glTF as three.js draws it in headless Chromium,
// after playing its animation for a moment: a PNG of the canvas, and a line
// of what the page found (animation length, tracks, skinned meshes).
//   node tools/web/screenshot_gltf.mjs FILE.glb OUT.png [--frame N] [--fps F]
//        [--size WxH] [--eye x,y,z] [--target x,y,z] [--fov DEG]
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { withBrowser } from './browser_harness.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const [file, out, ...rest] = process.argv.slice(2);
if (!file || !out) {
  console.error('usage: screenshot_gltf.mjs FILE.glb OUT.png [--frame N] [--fps F] [--size WxH] ' +
                '[--eye x,y,z] [--target x,y,z] [--fov DEG]');
  process.exit(2);
}
const opt = { frame: '0', fps: '25', size: '640x480', eye: '0,1,3.5', target: '0,1,0', fov: '40' };
for (let i = 0; i + 1 < rest.length; i += 2) opt[rest[i].replace(/^--/, '')] = rest[i + 1];
const [width, height] = opt.size.split('x').map(Number);

await withBrowser(
  { '/web/': here, '/three/': path.join(here, 'node_modules/three'),
    '/data/': path.dirname(path.resolve(file)) },
  async ({ page, base }) => {
    await page.setViewport({ width, height, deviceScaleFactor: 1 });
    const query = new URLSearchParams({ file: `/data/${path.basename(file)}`, frame: opt.frame,
      fps: opt.fps, width, height, eye: opt.eye, target: opt.target, fov: opt.fov });
    await page.goto(`${base}/web/view_gltf.html?${query}`);
    await page.waitForFunction('window.fvvResult !== undefined', { timeout: 45000 });
    const result = await page.evaluate('window.fvvResult');
    if (!result.ok) throw new Error(`the page could not show ${file}: ${result.error}`);
    await page.screenshot({ path: out, clip: { x: 0, y: 0, width, height } });
    console.log(`three.js: ${result.duration.toFixed(3)} s animation, ${result.tracks} tracks, ` +
                `${result.skinned} skinned mesh, ${result.played} frames played -> ${out}`);
  });
