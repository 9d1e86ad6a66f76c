// The web player (player/web/index.html) in headless chromium, served by the
// harness on 127.0.0.1 with byte ranges:
// - it plays a stream: the playhead moves through several GOPs, every frame
//   shown textured, the fetches all range requests;
// - a still of a frame from a fixed view matches `fvv render --path` of the
//   same frame, view, size and bytes (>= 35 dB over the actor: the same
//   decoder, the same shaders), for a stream with masks and one without
//   (depth maps), whole and at a byte budget, and for the generic body
//   without masks (its depth maps drawn from the simplified body);
// - a missing, damaged or cut stream: the page says what happened and
//   never hangs; a server that drops connections mid-fragment or ignores
//   Range: the page plays on from what arrived and says so;
// - seeking and stepping while paused; a stream without an index plays
//   from the start as it downloads;
// - the three.js adapter: the actor in a three.js scene, drawn as fvv render
//   draws it.
//
//   node web_player_test.mjs SITE_DIR WORK_DIR
// WORK_DIR holds masks.fvv, depth.fvv, surface.fvv, body.fvv, live.fvv, damaged.fvv,
// cut.fvv, path.json and the native stills native_KIND.png (web_player_test.sh).
import { readFileSync, statSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { withBrowser } from '../tools/web/browser_harness.mjs';

const [siteDir, work] = process.argv.slice(2);
const STILL_FRAME = 5, WIDTH = 640, HEIGHT = 480, MIN_PSNR = 35, BYTES = 600;
const key = JSON.parse(readFileSync(path.join(work, 'path.json'))).keyframes[0];
const view = { eye: key.eye, target: key.target, fovDeg: key.fov };
let failures = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) ++failures;
};

// Opens the page on `stream`; resolves when it plays or says why it cannot.
async function open(page, base, stream, { autoplay = true } = {}) {
  await page.goto(`${base}/site/index.html?stream=../data/${stream}&autoplay=${autoplay ? 1 : 0}`);
  await page.waitForFunction(() => window.fvvPlayer || window.fvvError, { timeout: 30000 });
}
const stats = (page) => page.evaluate(() => window.fvvPlayer?.stats() ?? null);
const message = (page) => page.evaluate(() => ({
  text: document.getElementById('message').textContent,
  error: document.getElementById('message').className === 'error',
  notice: document.getElementById('notice').textContent,
}));
// Waits until `done(stats)` or `ms` pass; the last stats.
async function waitFor(page, done, ms) {
  const until = Date.now() + ms;
  let s;
  do {
    await new Promise((r) => setTimeout(r, 250));
    s = await stats(page);
  } while (s && !done(s) && Date.now() < until);
  return s;
}

function psnrOverActor(a, b, background) {
  let se = 0, n = 0;
  for (let i = 0; i < a.length; i += 3) {
    const isActor = [0, 1, 2].some((k) => Math.abs(b[i + k] - background[k]) > 2) ||
                    [0, 1, 2].some((k) => Math.abs(a[i + k] - background[k]) > 2);
    if (!isActor) continue;
    for (let k = 0; k < 3; ++k) se += (a[i + k] - b[i + k]) ** 2;
    n += 3;
  }
  return { psnr: n === 0 ? 0 : se === 0 ? 99 : 10 * Math.log10((255 * 255 * n) / se), pixels: n / 3 };
}

// A still of the page at `bytes` per fragment (0: whole) against fvv render's
// (its PNG decoded by the page's own image decoder); returns the page's RGB.
async function stillAgainst(page, kind, bytes) {
  const name = bytes ? `${kind}_${bytes}` : kind;
  await open(page, base0, `${kind}.fvv`, { autoplay: false });
  await waitFor(page, (t) => t.hasFrame, 20000);
  const out = await page.evaluate(async (frame, v, w, h, b, pngUrl) => {
    const rgb = await window.fvvPlayer.still(frame, v, { width: w, height: h, bytes: b });
    const img = new Image();
    img.src = pngUrl;
    await img.decode();
    const c = new OffscreenCanvas(w, h).getContext('2d');
    c.drawImage(img, 0, 0);
    const rgba = c.getImageData(0, 0, w, h).data;
    const native = new Uint8Array(w * h * 3);
    for (let i = 0; i < w * h; ++i) native.set(rgba.subarray(4 * i, 4 * i + 3), 3 * i);
    return { page: Array.from(rgb), native: Array.from(native) };
  }, STILL_FRAME, view, WIDTH, HEIGHT, bytes, `../data/native_${name}.png`);
  const bg = [0.12, 0.12, 0.14].map((v) => Math.round(v * 255));
  const rgb = Uint8Array.from(out.page);
  const { psnr, pixels } = psnrOverActor(rgb, Uint8Array.from(out.native), bg);
  writeFileSync(`${work}/page_${name}_still.rgb`, rgb);
  writeFileSync(`${work}/native_${name}_still.rgb`, Uint8Array.from(out.native));
  check(pixels > 2000 && psnr >= MIN_PSNR,
    `${kind}: the page's still of frame ${STILL_FRAME}${bytes ? ` at ${bytes} bytes a fragment` : ''} against ` +
    `fvv render's: ${psnr.toFixed(2)} dB over ${pixels} actor pixels (>= ${MIN_PSNR})`);
  return rgb;
}

const mounts = { '/site/': path.resolve(siteDir), '/data/': path.resolve(work) };
const faults = {
  '/data/dropped.fvv': { closeAfter: 3000, from: 200000 },
  '/data/whole.fvv': { ignoreRange: true },
};
let base0;
await withBrowser(mounts, async ({ page, base, requests }) => {
  base0 = base;
  await page.setViewport({ width: 480, height: 400 });

  const wholeStills = {};
  for (const kind of ['masks', 'depth']) {
    await open(page, base, `${kind}.fvv`);
    const s = await waitFor(page, (t) => t.framesAdvanced >= 12, 30000);
    check(s && !s.error && s.framesAdvanced >= 12,
      `${kind}: plays (${s?.framesAdvanced} frames advanced, ${s?.framesDrawn} drawn, ${s?.fps} fps, error ${s?.error})`);
    check(s && s.framesWithoutTexture === 0, `${kind}: no frame shown untextured`);
    const shot = `${work}/page_${kind}_playing.png`;
    await page.screenshot({ path: shot });
    const whole = await stillAgainst(page, kind, 0);
    wholeStills[kind] = whole;
    if (kind === 'depth') {
      // The same at a budget: each fragment's texture cut at BYTES, here and
      // in fvv render --bytes; unlike the whole still, so the bytes count.
      const cut = await stillAgainst(page, kind, BYTES);
      const differ = psnrOverActor(cut, whole, [0.12, 0.12, 0.14].map((v) => Math.round(v * 255))).psnr;
      check(differ < 32, `depth: the still at ${BYTES} bytes is not the whole one (${differ.toFixed(2)} dB apart)`);
    }
  }
  // A stream with the surface of every frame (format version 12): the page
  // draws each frame's own surface as fvv render does, not the model's.
  {
    const surfaced = await stillAgainst(page, 'surface', 0);
    const apart = psnrOverActor(surfaced, wholeStills.masks, [0.12, 0.12, 0.14].map((v) => Math.round(v * 255))).psnr;
    check(apart < 30, `surface: the still is not the model's (${apart.toFixed(2)} dB from the stream without it)`);
  }
  // The generic body without masks: both players draw its depth maps from
  // the simplified body (player/playback/depth_map_triangles.h).
  await stillAgainst(page, 'body', 0);
  // The three.js adapter: the actor (FvvActor) in a scene of three.js's own
  // (floor, grid, box), drawn by three's render() in its context: over the
  // actor, fvv render's still again; around it, three's scene.
  await page.setViewport({ width: WIDTH, height: HEIGHT });
  const q = `frame=${STILL_FRAME}&eye=${view.eye.join(',')}&target=${view.target.join(',')}&fov=${view.fovDeg}`;
  await page.goto(`${base}/site/three.html?stream=../data/depth.fvv&${q}`);
  await page.waitForFunction(() => window.fvvStill || window.fvvError, { timeout: 60000 });
  const three = await page.evaluate(() => window.fvvStill ?? { error: window.fvvError });
  if (three.error) {
    check(false, `three.js: ${three.error}`);
  } else {
    const rgb = new Uint8Array(WIDTH * HEIGHT * 3);
    for (let y = 0; y < HEIGHT; ++y) {
      for (let x = 0; x < WIDTH; ++x) {
        for (let k = 0; k < 3; ++k) rgb[(y * WIDTH + x) * 3 + k] = three.rgba[((HEIGHT - 1 - y) * WIDTH + x) * 4 + k];
      }
    }
    const native = readFileSync(`${work}/native_depth_still.rgb`);
    const bg = [0.12, 0.12, 0.14].map((v) => Math.round(v * 255));
    let se = 0, n = 0, scene = 0;
    for (let i = 0; i < native.length; i += 3) {
      const actor = [0, 1, 2].some((k) => Math.abs(native[i + k] - bg[k]) > 2);
      if (!actor) {
        scene += [0, 1, 2].some((k) => Math.abs(rgb[i + k] - bg[k]) > 8);
        continue;
      }
      for (let k = 0; k < 3; ++k) se += (rgb[i + k] - native[i + k]) ** 2;
      n += 3;
    }
    const psnr = se === 0 ? 99 : 10 * Math.log10((255 * 255 * n) / se);
    writeFileSync(`${work}/three_still.rgb`, rgb);
    check(three.frame === STILL_FRAME && psnr >= MIN_PSNR,
      `three.js: the actor of frame ${three.frame} against fvv render's: ${psnr.toFixed(2)} dB over ${n / 3} pixels`);
    check(scene > 0.2 * WIDTH * HEIGHT, `three.js drew its own scene around the actor (${scene} pixels)`);
  }
  await page.setViewport({ width: 480, height: 400 });

  // Seeking goes through the index: paused, a step and a seek to a GOP not
  // fetched yet show exactly the frame asked for.
  await open(page, base, 'masks.fvv', { autoplay: false });
  await waitFor(page, (t) => t.hasFrame, 20000);
  await page.evaluate(() => window.fvvPlayer.seek(20));
  let s = await waitFor(page, (t) => t.frame === 20, 20000);
  check(s?.frame === 20 && !s.playing, `a seek to frame 20 (GOP 2) while paused shows it (frame ${s?.frame})`);
  await page.evaluate(() => window.fvvPlayer.step(-1));
  s = await waitFor(page, (t) => t.frame === 19, 20000);
  check(s?.frame === 19, `a step back shows frame 19 (frame ${s?.frame})`);

  // A stream without an index (a live one: conformance/cases/live) plays
  // from the start, whole, and the page says why it cannot seek.
  await open(page, base, 'live.fvv');
  s = await waitFor(page, (t) => t.frame === t.frameCount - 1, 20000);
  const live = await message(page);
  check(s && s.frame === s.frameCount - 1 && s.sequential && !s.error && /no index/.test(live.notice),
    `a stream without an index plays to its end (${s?.frame + 1} of ${s?.frameCount} frames); notice "${live.notice.split('\n')[0]}"`);
  const liveSize = statSync(`${work}/live.fvv`).size;
  check(s && s.bytesFetched === liveSize,
    `its every byte counted, each once: ${s?.bytesFetched} of a ${liveSize}-byte stream`);

  const streamRequests = requests.filter((r) => r.path.startsWith('/data/') && r.path.endsWith('.fvv'));
  check(streamRequests.length > 4 && streamRequests.every((r) => r.path.endsWith('live.fvv') || (r.status === 206 && r.range)),
    `the streams came by range requests only (${streamRequests.length})`);

  // Faults: each ends in the page saying so, within the wait, not in a hang.
  const cases = [
    ['missing.fvv', 'a missing stream', (m) => m.error && /404|not found/i.test(m.text)],
    ['damaged.fvv', 'a damaged stream', (m) => m.error && /checksum|corrupt/i.test(m.text)],
    ['cut.fvv', 'a cut stream', (m) => m.error && /truncat|ends|cut/i.test(m.text)],
    ['empty.fvv', 'an empty file', (m) => m.error && /empty/i.test(m.text)],
  ];
  for (const [stream, what, said] of cases) {
    await open(page, base, stream);
    await waitFor(page, (t) => t.error !== null, 20000);
    const m = await message(page);
    check(said(m), `${what}: the page says "${m.text}"`);
  }
  for (const [stream, what] of [['dropped.fvv', 'connections dropped mid-fragment'],
                                ['whole.fvv', 'a server that ignores Range']]) {
    await open(page, base, stream);
    const s = await waitFor(page, (t) => t.framesAdvanced >= 8 || t.error !== null, 30000);
    const m = await message(page);
    // What arrived decodes: the page plays on, and says what happened.
    check(s && s.framesAdvanced >= 8 && !s.error && s.framesWithoutTexture === 0 && m.notice.length > 0,
      `${what}: ${s?.error ? 'stopped: ' + s.error : `plays (${s?.framesAdvanced} frames)`}; ` +
      `notice "${m.notice.split('\n')[0]}"`);
    await page.screenshot({ path: `${work}/page_${path.basename(stream, '.fvv')}.png` });
  }
}, { timeoutMs: 300000, faults });

console.log(failures ? `FAILED: ${failures} checks` : 'passed: the web player');
process.exit(failures ? 1 : 0);
