// A stream played from a server in headless chromium through FvvStream
// (player/web/fvv_stream.mjs), cleanly and under the faults real servers
// have: every case ends in a decoded frame or an error that says what
// happened, never a hang or a blank.
//
//   node web_stream_faults_test.mjs BUILD_WASM_DIR STREAM NATIVE_WHOLE_OUT_DIR WORK_DIR
import { copyFileSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { withBrowser } from '../tools/web/browser_harness.mjs';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const [buildDir, streamPath, wholeDir, work] = process.argv.slice(2);
// The stream, a copy with one byte of a chunk of fragment 1 changed, and one
// cut in the middle of its last fragment.
const stream = readFileSync(streamPath);
copyFileSync(streamPath, path.join(work, 'clean.fvv'));
const mounts = {
  '/wasm/': path.resolve(buildDir), '/web/': path.join(root, 'player/web'),
  '/fzstd/': path.join(root, 'tools/web/node_modules/fzstd/esm'), '/data/': path.resolve(work),
};

// In the page: open the stream, fetch GOP 0 (whole, or within `budget` bytes when
// given), decode frame 0; what happened, or the error.
const play = (page, base, name, budget) => page.evaluate(async (url, budget) => {
  const { FvvDecoder } = await import('/web/fvv_decoder_api.mjs');
  const { FvvStream } = await import('/web/fvv_stream.mjs');
  const { decompress } = await import('/fzstd/index.mjs');
  const decoder = await FvvDecoder.create({ moduleUrl: '/wasm/fvv_decoder.mjs', zstd: decompress });
  const notices = [];
  try {
    const s = await FvvStream.open(url, decoder, { headBytes: 2048, timeoutMs: 5000,
                                                   onNotice: (t) => notices.push(t) });
    const fragments = await s.fragmentsFor(0);
    const heads = fragments.reduce((n, f) => n + f.headSize, 0);
    const fetched = await s.fetchGop(0, undefined, budget === null ? Number.MAX_SAFE_INTEGER : heads + budget);
    const frame = await s.frame(0);
    return { notices, fetched, heads, fragments: fragments.length, firstFragment: fragments[0].offset,
             complete: frame.report.complete, views: frame.views.map((v) => (v.pixels ? Array.from(v.pixels) : null)) };
  } catch (e) {
    return { notices, error: e.message };
  } finally {
    decoder.destroy();
  }
}, base + '/data/' + name, budget);

let failures = 0;
const check = (ok, what) => { if (!ok) { console.error(`FAIL: ${what}`); ++failures; } };
const isWhole = (views) => views.every((got, c) => {
  const want = readFileSync(path.join(wholeDir, `rgb_000000_${String(c).padStart(3, '0')}.bin`));
  return got.length === want.length && got.every((v, i) => v === want[i]);
});
const run = (faults, fn) => withBrowser(mounts, async (h) => {
  await h.page.goto(h.base + '/web/fvv_stream.mjs');  // any page of the origin
  return fn(h);
}, { timeoutMs: 60000, faults });

// Cleanly: whole fragments decode to the native RGB; under a budget, what the
// fetch plan allows, and a frame that is not complete.
const clean = await run({}, async ({ page, base }) => ({
  whole: await play(page, base, 'clean.fvv', null),
  budgeted: await play(page, base, 'clean.fvv', 600),
}));
check(!clean.whole.error && isWhole(clean.whole.views), `clean: ${clean.whole.error ?? 'RGB differs'}`);
// One request for the GOP's prefixes: a multipart answer's own lines (a
// boundary and two header lines, under 128 bytes a part) come on top.
check(!clean.budgeted.error && !clean.budgeted.complete &&
      clean.budgeted.fetched <= clean.budgeted.heads + 600 + 128 * clean.budgeted.fragments,
  `budgeted: ${JSON.stringify({ ...clean.budgeted, views: undefined })}`);
const firstFragment = clean.whole.firstFragment;

// Damaged and cut copies.
const damaged = Buffer.from(stream);
damaged[firstFragment + Math.floor((stream.length - firstFragment) / 3)] ^= 0x20;
writeFileSync(path.join(work, 'damaged.fvv'), damaged);
writeFileSync(path.join(work, 'cut.fvv'), stream.subarray(0, stream.length - 100));

const faulty = await run({
  '/data/norange.fvv': { ignoreRange: true },
  '/data/closing.fvv': { closeAfter: 1500, from: firstFragment },
}, async ({ page, base }) => {
  copyFileSync(streamPath, path.join(work, 'norange.fvv'));
  copyFileSync(streamPath, path.join(work, 'closing.fvv'));
  return {
    missing: await play(page, base, 'missing.fvv', null),
    norange: await play(page, base, 'norange.fvv', null),
    closing: await play(page, base, 'closing.fvv', null),
    damaged: await play(page, base, 'damaged.fvv', null),
    cut: await play(page, base, 'cut.fvv', null),
  };
});
check(/not found \(404\)/.test(faulty.missing.error ?? ''), `404: ${JSON.stringify(faulty.missing)}`);
check(!faulty.norange.error && isWhole(faulty.norange.views) &&
      faulty.norange.notices.some((t) => /does not answer Range/.test(t)),
  `a server that ignores Range: ${faulty.norange.error ?? faulty.norange.notices}`);
// What arrived decodes: the cameras whose fragments hold their heads.
check(!faulty.closing.error && !faulty.closing.complete && faulty.closing.views[0] !== null &&
      faulty.closing.notices.some((t) => /connection closed/.test(t)),
  `a connection closed mid-fragment: ${faulty.closing.error ?? faulty.closing.notices}`);
check(/checksum/i.test(faulty.damaged.error ?? ''), `a damaged chunk: ${JSON.stringify({ ...faulty.damaged, views: undefined })}`);
check(/truncated/i.test(faulty.cut.error ?? ''), `a cut stream: ${JSON.stringify({ ...faulty.cut, views: undefined })}`);
for (const [name, r] of Object.entries({ ...faulty, clean: clean.whole })) {
  console.log(`${name}: ${r.error ? 'error: ' + r.error : 'frame 0 decoded'}${r.notices.length ? ' (' + r.notices.join('; ') + ')' : ''}`);
}
console.log(`${failures ? 'FAILED' : 'passed'}: a stream over HTTP in chromium, cleanly and under 5 faults`);
process.exit(failures ? 1 : 0);
