// The WebAssembly decoder in a real browser (Debian's chromium, headless): a
// page fetches a stream with HTTP Range requests (player/web/fvv_stream.mjs)
// from the harness's server on 127.0.0.1 (the head as the decoder asks, then
// span 0's fragments whole),
// decodes frame 0 through the JavaScript API, on the page and in a Web Worker
// (fvv_decoder_worker.mjs, a GOP's frames in one message), and its RGB must be the native
// reference decoder's conformance output, byte for byte. The server's log
// must show only range requests (206) for the stream, and the page must be
// cross-origin isolated (the headers threads will need).
//
//   node web_browser_decode_test.mjs BUILD_WASM_DIR STREAM NATIVE_WHOLE_OUT_DIR
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { withBrowser } from '../tools/web/browser_harness.mjs';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
// FVV_WEB_SERVER: the base URL of a server already serving these paths
// (tests/web_lighttpd_test.sh), instead of the harness's own.
const [buildDir, streamPath, wholeDir] = process.argv.slice(2);
const external = process.env.FVV_WEB_SERVER;
const mounts = {
  '/wasm/': path.resolve(buildDir),
  '/web/': path.join(root, 'player/web'),
  '/fzstd/': path.join(root, 'tools/web/node_modules/fzstd/esm'),
  '/data/': path.dirname(path.resolve(streamPath)),
};
const streamUrl = '/data/' + path.basename(streamPath);

const result = await withBrowser(mounts, async ({ page, base, requests }) => {
  await page.goto(base + '/web/fvv_decoder_api.mjs');  // any page of the origin
  // The same fetches and decode on the page's thread and in a Web Worker.
  const run = (inWorker) => page.evaluate(async (url, worker) => {
    const { FvvDecoder } = await import('/web/fvv_decoder_api.mjs');
    const { FvvDecoderWorker } = await import('/web/fvv_decoder_worker_client.mjs');
    const { FvvStream } = await import('/web/fvv_stream.mjs');
    const { decompress } = await import('/fzstd/index.mjs');
    const dec = worker
      ? await FvvDecoderWorker.create('/web/fvv_decoder_worker.mjs',
          { moduleUrl: '/wasm/fvv_decoder.mjs', zstdUrl: '/fzstd/index.mjs' })
      : await FvvDecoder.create({ moduleUrl: '/wasm/fvv_decoder.mjs', zstd: decompress });
    // The stream client every page uses: the head by Range requests as the
    // decoder asks, then span 0's fragments whole.
    const stream = await FvvStream.open(url, dec, { headBytes: 4096 });
    const info = stream.info;
    await stream.fetchGop(0, undefined, Number.MAX_SAFE_INTEGER);
    // In the worker, as the player asks: a GOP's frames in one message,
    // after the memory the stream's head asked to be readied (warmMemory).
    const frames = worker ? await dec.decodeFrames(0, 2) : [await dec.decodeFrame(0)];
    const frame = frames[0];
    await dec.destroy();
    if (worker) dec.terminate();
    return { isolated: crossOriginIsolated, cameras: info.cameraCount,
             indices: frames.map((f) => f.index),
             views: frame.views.map((v) => Array.from(v.pixels)) };
  }, base + streamUrl, inWorker);
  const out = await run(false);
  out.worker = await run(true);
  return { ...out, requests: requests?.filter((r) => r.path === streamUrl) ?? null };
}, { timeoutMs: 90000, server: external });

let failures = 0;
const check = (ok, what) => { if (!ok) { console.error(`FAIL: ${what}`); ++failures; } };
check(result.isolated, 'the page is cross-origin isolated');
// The page itself refuses any answer but 206; the harness's log says so too.
check(result.requests === null ||
      (result.requests.length >= 2 && result.requests.every((r) => r.status === 206 && r.range)),
  `only range requests for the stream: ${JSON.stringify(result.requests)}`);
check(JSON.stringify(result.worker.indices) === '[0,1]',
  `decodeFrames(0, 2) in the worker gives frames 0 and 1: ${result.worker.indices}`);
for (const [where, views] of [['page', result.views], ['worker', result.worker.views]]) {
  for (let c = 0; c < result.cameras; ++c) {
    const want = readFileSync(path.join(wholeDir, `rgb_000000_${String(c).padStart(3, '0')}.bin`));
    const got = views[c];
    check(got.length === want.length && got.every((v, i) => v === want[i]),
      `frame 0 camera ${c}, decoded on the ${where}`);
  }
}
console.log(`${failures ? 'FAILED' : 'passed'}: frame 0 of ${result.cameras} cameras in chromium, ` +
  `on the page and in a Web Worker, from ${external ?? 'the harness'}` +
  (result.requests ? `, ${result.requests.length} range requests, ` +
    `${result.requests.reduce((n, r) => n + r.bytes, 0)} bytes` : ''));
process.exit(failures ? 1 : 0);
