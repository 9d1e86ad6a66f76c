// The decoder in WebAssembly in headless chromium with one decoder worker and
// with several (FvvDecoderPool: each decodes its share of every frame's
// cameras), beside the native decoder with one thread and with as many (a
// benchmark, not a test): every frame of STREAM, every camera, RGB out, the
// whole stream held first. Prints ms per stream decode, the parallel speed-up
// on each side and the WASM/native ratio.
//
//   node bench/web_decode_bench.mjs SITE_DIR STREAM [WORKERS, default 2] [ROUNDS, default 2]
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { withBrowser } from '../tools/web/browser_harness.mjs';

const [site, stream, workers = '2', rounds = '2'] = process.argv.slice(2);
if (!stream) {
  console.error('usage: web_decode_bench.mjs SITE_DIR STREAM [WORKERS] [ROUNDS]');
  process.exit(2);
}
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const mounts = { '/site/': path.resolve(site), '/streams/': path.dirname(path.resolve(stream)) };
const median = (v) => [...v].sort((a, b) => a - b)[Math.floor((v.length - 1) / 2)];

const web = await withBrowser(mounts, async ({ page, base }) => {
  await page.goto(`${base}/site/index.html`);
  return page.evaluate(async (url, n, rounds) => {
    const { FvvDecoderPool } = await import('/site/fvv_decoder_pool.mjs');
    const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
    const out = {};
    for (const count of [1, n]) {
      const times = [];
      for (let r = 0; r < rounds; ++r) {
        const pool = await FvvDecoderPool.create('/site/fvv_decoder_worker.mjs',
          { moduleUrl: '/site/fvv_decoder.mjs', zstdUrl: '/site/fzstd/index.mjs' }, count);
        await pool.openRanges(bytes.length);
        await pool.addRange(0, bytes);
        while ((await pool.process()) === 'need');
        const info = await pool.info();
        const t0 = performance.now();
        for (let f = 0; f < info.frameCount; ++f) await pool.decodeFrame(f);
        times.push(performance.now() - t0);
        pool.terminate();
      }
      out[count] = times;
    }
    return out;
  }, `/streams/${path.basename(stream)}`, Number(workers), Number(rounds));
}, { timeoutMs: 900000 });

const native = {};
for (const threads of [1, Number(workers)]) {
  native[threads] = [];
  for (let r = 0; r < Number(rounds); ++r) {
    const out = execFileSync(path.join(root, 'build/tools/conformance_decode'),
      [stream, '-', '0', '--repeat', '1', '--threads', String(threads)]).toString();
    native[threads].push(Number(out.split(' ')[0]));
  }
}
const n = Number(workers);
const w1 = median(web[1]), wn = median(web[n]), n1 = median(native[1]), nn = median(native[n]);
console.log(`WebAssembly in chromium, 1 worker: ${w1.toFixed(0)} ms; ${n} workers: ${wn.toFixed(0)} ms ` +
  `(x${(w1 / wn).toFixed(2)})`);
console.log(`native, 1 thread: ${n1.toFixed(0)} ms; ${n} threads: ${nn.toFixed(0)} ms (x${(n1 / nn).toFixed(2)})`);
console.log(`WebAssembly / native: ${(w1 / n1).toFixed(2)} with one each, ${(wn / nn).toFixed(2)} with ${n} each ` +
  '(the native figure forms Annex B\'s YUV and RGB of every camera; the page RGB only, copied out to the page)');
