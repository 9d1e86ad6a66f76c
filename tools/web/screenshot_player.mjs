// The web player (player/web/index.html) in headless chromium on a stream for
// a few seconds, from the harness's server on 127.0.0.1; writes a screenshot
// and prints what its HUD measured. What tools/demo.sh shows of the page.
//
//   node tools/web/screenshot_player.mjs SITE_DIR STREAM OUT.png [SECONDS]
import path from 'node:path';
import { withBrowser } from './browser_harness.mjs';

const [site, stream, out, seconds = '6'] = process.argv.slice(2);
if (!out) {
  console.error('usage: screenshot_player.mjs SITE_DIR STREAM OUT.png [SECONDS]');
  process.exit(2);
}
const mounts = { '/site/': path.resolve(site), '/streams/': path.dirname(path.resolve(stream)) };
const s = await withBrowser(mounts, async ({ page, base }) => {
  await page.setViewport({ width: 800, height: 600 });
  await page.goto(`${base}/site/index.html?stream=../streams/${path.basename(stream)}`);
  await page.waitForFunction(() => window.fvvPlayer || window.fvvError, { timeout: 60000 });
  await new Promise((r) => setTimeout(r, 1000 * Number(seconds)));
  await page.screenshot({ path: out });
  return page.evaluate(() => window.fvvPlayer?.stats() ?? { error: window.fvvError });
}, { timeoutMs: 120000 + 1000 * Number(seconds) });
if (s.error) {
  console.error(`the page did not play ${stream}: ${s.error}`);
  process.exit(1);
}
console.log(`web player: ${s.framesAdvanced} frames played in ${seconds} s, ${s.framesDrawn} drawn, ` +
  `${s.stalls} stalls, ${(s.bytesFetched / 1e6).toFixed(2)} MB fetched by range requests, ` +
  `WebGL ${s.webglMs.toFixed(1)} ms a frame -> ${out}`);
