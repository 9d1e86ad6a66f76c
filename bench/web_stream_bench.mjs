// The web player over a throttled network (a benchmark, not a test): the page
// (player/web/index.html) in headless chromium plays STREAM from the
// harness's server on 127.0.0.1 while the DevTools protocol holds the
// network to each rate, and reports per rate:
// - start-up: from opening the stream on a page whose code is loaded to its
//   first frame drawn and to its playhead moving (the start holds the first
//   frame until the GOP after it is decoded: PlaybackLoop's preroll), and
//   from opening the page with nothing loaded to its first frame (with
//   --lighttpd, served as docs/web.md serves it: tools/web/lighttpd.conf, the
//   page's code compressed and kept by the browser, and then also a second
//   visit's, the code asked again by its ETag and the stream fetched anew);
// - after the first frame: waits (the playhead held for a GOP not there
//   yet) and stalls (frames on screen over two frame times, a slow display's
//   too);
// - frames shown without texture (must be none);
// - bytes per GOP fetched against what the rate allows in a GOP's play time
//   (every fetched byte counted: heads, index, model, motion);
// - PSNR of the decoded textures against the whole stream's decode, for the
//   first frame of every 4th GOP, over the cameras the page decoded;
// and, unthrottled, whether it fetched whole fragments.
//
//   node bench/web_stream_bench.mjs SITE_DIR STREAM [--rates 0.5,1] [--seconds 25]
//        [--latency-ms 20] [--lighttpd] [--json OUT]
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync, symlinkSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { withBrowser } from '../tools/web/browser_harness.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};
const [site, stream] = args;
if (!stream) {
  console.error('usage: web_stream_bench.mjs SITE_DIR STREAM [--rates 0.5,1] [--seconds 25] ' +
                '[--latency-ms 20] [--json OUT]');
  process.exit(2);
}
const rates = option('--rates', '0.5,1,0').split(',').map(Number);  // Mbit/s; 0: unthrottled
const seconds = Number(option('--seconds', '25'));
const latencyMs = Number(option('--latency-ms', '20'));
const useLighttpd = args.includes('--lighttpd');
const mounts = { '/site/': path.resolve(site), '/streams/': path.dirname(path.resolve(stream)) };
const url = `../streams/${path.basename(stream)}`;

async function throttle(cdp, mbit) {
  await cdp.send('Network.emulateNetworkConditions', {
    offline: false, latency: mbit > 0 ? latencyMs : 0,
    downloadThroughput: mbit > 0 ? (mbit * 1e6) / 8 : -1, uploadThroughput: -1,
  });
}

// Start-up with nothing loaded: the page, its modules and the stream all
// come over the throttled network (no-store: nothing is cached).
async function coldStart(page, base, mbit) {
  const cdp = await page.createCDPSession();
  await cdp.send('Network.enable');
  await throttle(cdp, mbit);
  const opened = Date.now();
  await page.goto(`${base}/site/index.html?stream=${url}`);
  await page.waitForFunction(() => window.fvvPlayer?.stats().framesDrawn > 0 || window.fvvError,
    { timeout: 120000, polling: 20 });
  return (Date.now() - opened) / 1000;
}

// The same start through lighttpd as docs/web.md serves a page: the first
// visit with nothing cached, then a second (the page's code kept, asked again
// by its ETag; the stream fetched anew). Seconds to the first frame of each.
async function servedStarts(mbit) {
  const root = mkdtempSync(path.join(os.tmpdir(), 'fvv-bench-'));
  symlinkSync(mounts['/site/'], path.join(root, 'site'));
  symlinkSync(mounts['/streams/'], path.join(root, 'streams'));
  const port = await new Promise((resolve) => {
    const probe = createServer().listen(0, '127.0.0.1', () => {
      const p = probe.address().port;
      probe.close(() => resolve(p));
    });
  });
  const conf = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../tools/web/lighttpd.conf');
  const server = spawn('lighttpd', ['-D', '-f', conf], {
    env: { ...process.env, FVV_WEB_ROOT: root, FVV_WEB_PORT: String(port) }, stdio: 'ignore',
  });
  try {
    const base = `http://127.0.0.1:${port}`;
    for (let i = 0; i < 50; ++i) {
      if (await fetch(`${base}/site/index.html`).then((r) => r.ok, () => false)) break;
      await new Promise((r) => setTimeout(r, 100));
    }
    return await withBrowser(mounts, async ({ page }) => {
      await page.setViewport({ width: 640, height: 520 });
      const first = await coldStart(page, base, mbit);
      await page.goto('about:blank');
      const second = await coldStart(page, base, mbit);
      return { first, second };
    }, { timeoutMs: 480000, server: base });
  } finally {
    server.kill();
    rmSync(root, { recursive: true, force: true });
  }
}

async function run(page, base, mbit) {
  const cdp = await page.createCDPSession();
  await cdp.send('Network.enable');
  // The page records each GOP's fetch and keeps the first frame of every 4th
  // GOP's textures for the comparison with the whole decode.
  await page.evaluateOnNewDocument(() => {
    window.benchGops = [];
    window.benchFrames = new Map();
    window.fvvOnGop = ({ gop, cameras, fetched, fetchBytes, seconds, whole, frames, started, ended }) => {
      const r = frames[0].report ?? {};
      window.benchGops.push({ gop, cameras: cameras.length, fetched, fetchBytes, seconds, whole,
                              at: performance.now(), started, ended,
                              report: [Math.round(r.decodeMs), Math.round(r.maxMs), r.complete, r.bytesDecoded, r.bytesAvailable, ...(r.bitplanes ?? [])] });
      if (gop % 4 === 0 && !window.benchFrames.has(frames[0].index)) {
        window.benchFrames.set(frames[0].index, frames[0].views.map((v) => v.pixels));
      }
    };
  });
  // The page and its module loaded (as for a viewer who opens a second
  // stream, or a page whose code is cached); then the stream, throttled.
  await page.goto(`${base}/site/index.html`);
  if (!(await page.evaluate(() => window.fvvReady))) throw new Error('the page could not load its module');
  await throttle(cdp, mbit);
  const opened = Date.now();
  await page.evaluate((u) => { window.benchOpenedAt = performance.now(); window.fvvOpen(u); }, url);
  await page.waitForFunction(() => window.fvvPlayer || window.fvvError, { timeout: 60000, polling: 20 });
  const error = await page.evaluate(() => window.fvvError ?? null);
  if (error) throw new Error(`the page cannot play the stream: ${error}`);
  await page.waitForFunction(() => window.fvvPlayer.stats().framesDrawn > 0, { timeout: 60000, polling: 20 });
  const startup = (Date.now() - opened) / 1000;
  const atStart = await page.evaluate(() => window.fvvPlayer.stats());
  await page.waitForFunction(() => window.fvvPlayer.stats().framesAdvanced > 0, { timeout: 60000, polling: 20 });
  const moving = (Date.now() - opened) / 1000;
  // When each wait began, from the first frame on (ms, the frame waited at).
  await page.evaluate(() => {
    window.benchWaits = [];
    const t0 = performance.now();
    let waits = window.fvvPlayer.stats().waits;
    setInterval(() => {
      const s = window.fvvPlayer.stats();
      if (s.waits !== waits) window.benchWaits.push([Math.round(performance.now() - t0), s.frame]);
      waits = s.waits;
    }, 10);
  });
  await new Promise((r) => setTimeout(r, seconds * 1000));
  const end = await page.evaluate(() => window.fvvPlayer.stats());
  const gops = await page.evaluate(() => window.benchGops);
  const waitTimes = await page.evaluate(() => window.benchWaits);
  const openedAt = await page.evaluate(() => window.benchOpenedAt);
  const info = await page.evaluate(() => window.fvvPlayer.info);
  await throttle(cdp, 0);
  // The whole decode of the kept frames, on the page's own thread, from the
  // whole stream fetched unthrottled.
  const psnr = await page.evaluate(async (streamUrl) => {
    const { FvvDecoder } = await import('/site/fvv_decoder_api.mjs');
    const { decompress } = await import('/site/fzstd/index.mjs');
    const bytes = new Uint8Array(await (await fetch(streamUrl, { cache: 'no-store' })).arrayBuffer());
    const dec = await FvvDecoder.create({ moduleUrl: '/site/fvv_decoder.mjs', zstd: decompress });
    dec.openRanges(bytes.length);
    dec.addRange(0, bytes);
    while (dec.process() === 'need');
    const out = [];
    for (const [index, views] of window.benchFrames) {
      const whole = dec.decodeFrame(index);
      let se = 0, n = 0;
      views.forEach((pixels, c) => {
        if (!pixels) return;
        const w = whole.views[c].pixels;
        for (let i = 0; i < w.length; ++i) se += (pixels[i] - w[i]) ** 2;
        n += w.length;
      });
      out.push(n ? (se === 0 ? 99 : 10 * Math.log10((255 * 255 * n) / se)) : 0);
    }
    dec.destroy();
    return out;
  }, `/streams/${path.basename(stream)}`);
  await cdp.detach();
  const gopSeconds = info.gopFrames / info.frameRate;
  const allowed = mbit > 0 ? (mbit * 1e6 / 8) * gopSeconds : 0;
  const played = gops.filter((g) => g.at > 0);
  const share = played.map((g) => (allowed ? g.fetched / allowed : 0));
  const wholeFragments = played.every((g) => g.whole);
  return {
    mbit, startup_s: startup, moving_s: moving, seconds,
    frames_advanced: end.framesAdvanced - atStart.framesAdvanced,
    frames_drawn: end.framesDrawn - atStart.framesDrawn,
    stalls_after_start: end.stalls - atStart.stalls,
    waits_after_start: end.waits - atStart.waits,
    frames_without_texture: end.framesWithoutTexture,
    gops: played.length,
    bytes_fetched: end.bytesFetched,
    mean_gop_bytes: played.reduce((s, g) => s + g.fetched, 0) / Math.max(1, played.length),
    allowed_gop_bytes: allowed,
    mean_share_of_allowed: share.reduce((s, v) => s + v, 0) / Math.max(1, share.length),
    // After the first two seconds' GOPs, which start low to get ahead.
    later_share_of_allowed: share.slice(Math.ceil(2 / gopSeconds)).reduce((s, v) => s + v, 0) /
      Math.max(1, share.length - Math.ceil(2 / gopSeconds)),
    wait_times: waitTimes,
    opened_at: openedAt,
    gop_shares: share.map((v) => Math.round(v * 100) / 100),
    gop_budgets: played.map((g) => (allowed ? Math.round(100 * g.fetchBytes / allowed) / 100 : 0)),
    gop_at: played.map((g) => Math.round(g.at)),
    gop_reports: played.map((g) => g.report),
    gop_cameras: played.map((g) => g.cameras),
    gop_fetch: played.map((g) => [Math.round(g.started), Math.round(g.ended), g.fetched]),
    // The link's time used: every byte fetched after the first frame, against
    // what the rate brings in that time.
    link_share: mbit > 0 ? (end.bytesFetched - atStart.bytesFetched) / ((mbit * 1e6 / 8) * seconds) : 0,
    mean_cameras: played.reduce((s, g) => s + g.cameras, 0) / Math.max(1, played.length),
    whole_fragments: wholeFragments,
    psnr_vs_whole_db: psnr.length ? psnr.reduce((s, v) => s + v, 0) / psnr.length : null,
    psnr_frames: psnr.length,
    real_time_speed: (end.framesAdvanced - atStart.framesAdvanced) / (seconds * info.frameRate),
  };
}

const results = [];
for (const mbit of rates) {
  const r = await withBrowser(mounts, async ({ page, base }) => {
    await page.setViewport({ width: 640, height: 520 });
    return run(page, base, mbit);
  }, { timeoutMs: (seconds + 240) * 1000 });
  r.cold_startup_s = await withBrowser(mounts, async ({ page, base }) => {
    await page.setViewport({ width: 640, height: 520 });
    return coldStart(page, base, mbit);
  }, { timeoutMs: 240000 });
  if (useLighttpd) {
    const served = await servedStarts(mbit);
    r.served_first_visit_s = served.first;
    r.served_second_visit_s = served.second;
  }
  results.push(r);
  const label = mbit > 0 ? `${mbit} Mbit/s` : 'unthrottled';
  console.log(`${label}: first frame ${r.startup_s.toFixed(2)} s and playing ${r.moving_s.toFixed(2)} s ` +
    `after opening the stream ` +
    `(${r.cold_startup_s.toFixed(2)} s after opening the page with nothing loaded` +
    (useLighttpd ? `; served by lighttpd, the code compressed: ${r.served_first_visit_s.toFixed(2)} s on a ` +
      `first visit, ${r.served_second_visit_s.toFixed(2)} s on a second` : '') + '); ' +
    `after it ${r.waits_after_start} waits for a GOP, ${r.stalls_after_start} frames held over two frame times; ` +
    `${r.frames_without_texture} frames untextured; ${r.gops} GOPs, ${(r.mean_gop_bytes / 1024).toFixed(1)} KiB each` +
    (r.allowed_gop_bytes ? ` of ${(r.allowed_gop_bytes / 1024).toFixed(1)} KiB allowed ` +
      `(${(100 * r.mean_share_of_allowed).toFixed(0)} %; ${(100 * r.later_share_of_allowed).toFixed(0)} % after ` +
      `the first 2 s; the link ${(100 * r.link_share).toFixed(0)} % used)` : '') +
    `, ${r.mean_cameras.toFixed(1)} cameras; ` +
    (r.psnr_vs_whole_db === null ? 'no frame kept for' : r.psnr_vs_whole_db >= 99 ? 'identical to'
      : `${r.psnr_vs_whole_db.toFixed(2)} dB against`) + ` the whole ` +
    `decode (${r.psnr_frames} frames); ${r.real_time_speed.toFixed(2)}x real time; ` +
    `${r.frames_drawn} frames drawn in ${seconds} s` + (mbit > 0 ? '' : `; whole fragments: ${r.whole_fragments}`));
}
const out = option('--json');
if (out) writeFileSync(out, JSON.stringify({ stream, latency_ms: latencyMs, results }, null, 2));
