// The web player (player/web/index.html) in headless chromium on a stream for
// a few seconds, from the harness's server on 127.0.0.1; writes a screenshot
// and prints what its HUD measured. What tools/demo.sh shows of the page.
//
//   node tools/web/screenshot_player.mjs SITE_DIR STREAM OUT.png [SECONDS]
//        [--size WxH (the canvas; default 800x556)] [--json OUT.json]
//        [--time-frames: WebGL's time taken on every frame, for benchmarks]
//        [--renderer-alone N: after the screenshot, playback paused and the
//         decoder idle, N of the decoded frames set and drawn (each from a
//         view turned a little further, a pixel read back after each): the
//         renderer's own rate, without the decoder beside it on the cores]
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { withBrowser } from './browser_harness.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  if (i < 0) return fallback;
  const v = args[i + 1];
  args.splice(i, 2);
  return v;
};
const [width, height] = option('--size', '800x556').split('x').map(Number);
const json = option('--json');
const rendererAlone = Number(option('--renderer-alone', '0'));
const timeFrames = args.includes('--time-frames');
if (timeFrames) args.splice(args.indexOf('--time-frames'), 1);
const [site, stream, out, seconds = '6'] = args;
if (!out || !(width > 0) || !(height > 0)) {
  console.error('usage: screenshot_player.mjs SITE_DIR STREAM OUT.png [SECONDS] [--size WxH] [--json OUT.json]');
  process.exit(2);
}
const CONTROLS = 44;  // the page's control bar under the canvas
const mounts = { '/site/': path.resolve(site), '/streams/': path.dirname(path.resolve(stream)) };
const s = await withBrowser(mounts, async ({ page, base }) => {
  await page.setViewport({ width, height: height + CONTROLS });
  await page.goto(`${base}/site/index.html?stream=../streams/${path.basename(stream)}` +
                  (timeFrames ? '&time=frames' : ''));
  await page.waitForFunction(() => window.fvvPlayer || window.fvvError, { timeout: 60000 });
  // Counted from the first frame drawn, as fvv play counts from its first.
  await page.waitForFunction(() => window.fvvError || window.fvvPlayer?.stats().framesDrawn > 0,
    { timeout: 60000, polling: 20 });
  const before = await page.evaluate(() => window.fvvPlayer?.stats() ?? null);
  const t0 = Date.now();
  await new Promise((r) => setTimeout(r, 1000 * Number(seconds)));
  await page.screenshot({ path: out });
  const after = await page.evaluate(() => (window.fvvPlayer
    ? { ...window.fvvPlayer.stats(), frameRate: window.fvvPlayer.info.frameRate } : { error: window.fvvError }));
  const renderer = await page.evaluate(() => {
    const gl = window.fvvPlayer?.gl;
    const e = gl?.getExtension('WEBGL_debug_renderer_info');
    return gl ? gl.getParameter(e ? e.UNMASKED_RENDERER_WEBGL : gl.RENDERER) : null;
  });
  const wall = (Date.now() - t0) / 1000;
  const alone = rendererAlone > 0 && after.framesDrawn ? await page.evaluate(async (n) => {
    const p = window.fvvPlayer;
    p.pause();
    // The GOP under decode, if any, finishes first.
    await new Promise((r) => setTimeout(r, 1500));
    const { orbitView } = await import('/site/fvv_view.mjs');
    const gl = p.gl, pixel = new Uint8Array(4), w = p.canvas.width, h = p.canvas.height;
    const sync = () => gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    const frames = [...p.gops.values()].flat().filter(Boolean);
    if (!frames.length) return null;
    const view = (i) => orbitView(p.renderer.actor, { ...p.orbit, yaw: p.orbit.yaw + 0.01 * i, aspect: w / h });
    sync();
    const t = performance.now();
    for (let i = 0; i < n; ++i) {
      p.renderer.setFrame(frames[i % frames.length]);
      p.renderer.draw(view(i), w, h);
      sync();
    }
    return { frames: n, ms: (performance.now() - t) / n };
  }, rendererAlone) : null;
  return {
    renderer_alone: alone,
    ...after, renderer, wall_s: wall, canvas: [width, height],
    drawn_fps: before ? (after.framesDrawn - before.framesDrawn) / wall : 0,
    webgl_share: before ? (after.webglTotalMs - before.webglTotalMs) / (1000 * wall) : 0,
    speed: before ? (after.framesAdvanced - before.framesAdvanced) / (wall * after.frameRate) : 0,
  };
}, { timeoutMs: 120000 + 1000 * Number(seconds) });
if (s.error) {
  console.error(`the page did not play ${stream}: ${s.error}`);
  process.exit(1);
}
console.log(`web player: ${s.drawn_fps.toFixed(1)} fps drawn at ${width}x${height} over ${seconds} s, ` +
  `${s.stalls} stalls, ${(s.bytesFetched / 1e6).toFixed(2)} MB fetched by range requests, ` +
  (timeFrames ? `WebGL ${s.webglMs.toFixed(1)} ms a frame (${(100 * s.webgl_share).toFixed(0)} % of the time) ` : '') +
  `on ${s.renderer} -> ${out}`);
if (s.renderer_alone) {
  console.log(`the renderer alone (paused, the decoder idle): ${s.renderer_alone.ms.toFixed(1)} ms a frame ` +
    `set and drawn, ${(1000 / s.renderer_alone.ms).toFixed(1)} fps (${s.renderer_alone.frames} frames)`);
}
if (json) writeFileSync(json, JSON.stringify(s, null, 2));
