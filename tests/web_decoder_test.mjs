// The WebAssembly decoder through its JavaScript API, in Node: a stream opened
// by byte ranges as a page fetches it (the head as the decoder asks, then each
// fragment as a prefix), decoded to the same RGB as the native reference
// decoder's conformance output at that prefix; fetching more of a fragment
// decodes better; the errors a page meets come back as FvvError statuses.
//
//   node web_decoder_test.mjs BUILD_WASM_DIR STREAM NATIVE_OUT_DIR PREFIX WHOLE_OUT_DIR
//                            SURFACE_STREAM BODY_STREAM NATIVE_DEPTH_TRIANGLES
// NATIVE_OUT_DIR: tools/conformance_decode's output for STREAM at PREFIX bytes
// per fragment; WHOLE_OUT_DIR: at 0 (whole fragments). SURFACE_STREAM: a
// stream with the surface of every frame (format version 12).
// BODY_STREAM: a stream with the generic body model; NATIVE_DEPTH_TRIANGLES:
// "COUNT HASH" of the triangles the native players' depth maps draw for its
// model (tests/depth_map_triangles_print.cc), which the module's
// (FvvPlayback.depthMapTriangles) must equal.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { decompress } from '../tools/web/node_modules/fzstd/esm/index.mjs';
import { FvvDecoder, FvvError } from '../player/web/fvv_decoder_api.mjs';
import { FvvPlayback } from '../player/web/fvv_playback.mjs';
import { lookedAtPoint } from '../player/web/fvv_view.mjs';

const [buildDir, streamPath, prefixDir, prefixArg, wholeDir, surfacePath, bodyPath,
  nativeDepthTriangles] = process.argv.slice(2);
const prefix = Number(prefixArg);
let failures = 0;
const check = (ok, what) => {
  if (!ok) {
    console.error(`FAIL: ${what}`);
    ++failures;
  }
};
const same = (a, b) => a.length === b.length && a.every((v, i) => v === b[i]);
const rgbFile = (dir, frame, camera) =>
  readFileSync(path.join(dir, `rgb_${String(frame).padStart(6, '0')}_${String(camera).padStart(3, '0')}.bin`));
const expectError = (fn, status, what) => {
  try {
    fn();
    check(false, `${what}: no error`);
  } catch (e) {
    check(e instanceof FvvError && e.status === status, `${what}: ${e.message} (status ${e.status}, want ${status})`);
  }
};

const stream = readFileSync(streamPath);
// The module built for Node (fvv_decoder_node.cjs; pages load fvv_decoder.mjs).
const moduleFactory = createRequire(import.meta.url)(path.resolve(buildDir, 'fvv_decoder_node.cjs'));
const dec = await FvvDecoder.create({ moduleFactory, zstd: decompress });
dec.openRanges(stream.length);
// What the decoder asks for, 4 KiB of it at a time: the head boxes and the index.
let requests = 0;
for (let event; (event = dec.process()) === 'need'; ++requests) {
  const want = dec.wantedRange();
  check(want !== null && want.offset + want.size <= stream.length, 'wantedRange within the stream');
  const n = Math.min(want.size, 4096);
  dec.addRange(want.offset, stream.subarray(want.offset, want.offset + n));
  if (requests > 500) throw new Error('the head never completes');
}
const info = dec.info();
check(info.formatVersion === 11, `format version ${info.formatVersion}`);
check(dec.framesAvailable() === info.frameCount, 'every frame available');
const model = dec.model();
check(model.positions.length === info.vertexCount * 3 && model.triangles.length === info.triangleCount * 3,
  'model arrays');
check(dec.camera(0).width > 0, 'camera 0');
const groups = Math.ceil(info.cameraCount / info.gopCameras);
const firstFragment = dec.fragment(0).offset;
dec.destroy();

// A page that knows where the fragments start fetches the head in one range:
// everything before the first fragment (a fast-start stream's index included).
const dec2 = await FvvDecoder.create({ moduleFactory, zstd: decompress });
dec2.openRanges(stream.length);
dec2.addRange(0, stream.subarray(0, firstFragment));
check(dec2.process() === 'ready', 'a fast-start head in one range');
const span0 = Array.from({ length: groups }, (_, g) => dec2.fragment(g));
check(span0.every((f) => f.held === 0), 'no byte of a fragment held yet');

// Before any fragment of span 0 is held: an error, not a crash.
expectError(() => dec2.decodeFrame(0), 1 /* INVALID_ARGUMENT */, 'frame of fragments not fetched');
// Each fragment of span 0 fetched as a prefix, then decoded: the native RGB.
for (const f of span0) {
  const n = Math.min(prefix, f.size);
  check(f.headSize < n, `fragment ${f.index}: head ${f.headSize} within the prefix ${n}`);
  dec2.addRange(f.offset, stream.subarray(f.offset, f.offset + n));
}
let frame = dec2.decodeFrame(0);
for (let c = 0; c < info.cameraCount; ++c) {
  check(same(frame.views[c].pixels, rgbFile(prefixDir, 0, c)), `frame 0 camera ${c} at the prefix`);
}
check(!frame.report.complete, 'a prefix is not the whole texture');
// Where the page's view orbits before the first frame: the cameras' aim,
// near the actor's root (the root's world translation, column-major).
{
  const cams = Array.from({ length: info.cameraCount }, (_, c) => dec2.camera(c));
  const aim = lookedAtPoint(cams);
  const root = [frame.boneWorld[12], frame.boneWorld[13], frame.boneWorld[14]];
  const off = aim ? Math.hypot(...aim.map((v, k) => v - root[k])) : Infinity;
  check(off < 0.6, `the cameras aim ${off.toFixed(2)} m from the actor's root`);
  check(lookedAtPoint(cams.slice(0, 1)) === null, 'one camera aims at no point');
}
// The rest of the fragments: the whole decode.
for (const f of span0) dec2.addRange(f.offset, stream.subarray(f.offset, f.offset + f.size));
frame = dec2.decodeFrame(1);
for (let c = 0; c < info.cameraCount; ++c) {
  check(same(frame.views[c].pixels, rgbFile(wholeDir, 1, c)), `frame 1 camera ${c} whole`);
}
check(frame.report.complete, 'whole fragments decode completely');
// Camera 0 alone of span 1, fetched whole; the other cameras left out.
const f1 = dec2.fragment(groups);
dec2.addRange(f1.offset, stream.subarray(f1.offset, f1.offset + f1.size));
frame = dec2.decodeFrame(info.gopFrames, { cameras: [0] });
check(frame.views[0].pixels !== null && same(frame.views[0].pixels, rgbFile(wholeDir, info.gopFrames, 0)),
  'camera 0 alone');
check(frame.views[info.cameraCount - 1].pixels === null, 'a camera left out has no pixels');
// The fetch policy compiled into the module: heads first, then the same
// share of every fragment's texture, within the budget; the bandwidth's budget.
const plan = dec2.planPrefixes(span0, span0.reduce((n, f) => n + f.headSize, 0) + 1000);
check(plan.every((p, i) => p >= span0[i].headSize && p <= span0[i].size), `plan ${plan}`);
check(plan.reduce((n, p) => n + p, 0) <= span0.reduce((n, f) => n + f.headSize, 0) + 1000, 'plan within budget');
check(same(dec2.planPrefixes(span0, 1e9), span0.map((f) => f.size)), 'whole fragments when they fit');
check(dec2.gopFetchBudget(62500, 0.32) === 18000, 'a GOP at 0.5 Mbit/s');
check(dec2.bandwidthAfter(0, 62500, 1) === 62500 && dec2.bandwidthAfter(62500, 125000, 1) === 62500 * 0.7 + 125000 * 0.3,
  'the bandwidth estimate');
// A damaged chunk among the bytes held.
const damaged = new Uint8Array(stream.subarray(f1.offset, f1.offset + f1.size));
damaged[damaged.length - 1] ^= 1;
const other = await FvvDecoder.create({ moduleFactory, zstd: decompress });
other.openRanges(stream.length);
other.addRange(0, stream.subarray(0, firstFragment));
check(other.process() === 'ready', 'the head again');
other.addRange(f1.offset, damaged);
expectError(() => other.decodeFrame(info.gopFrames, { cameras: [0] }), 6 /* CHECKSUM_MISMATCH */,
  'a damaged chunk');
expectError(() => other.addRange(stream.length, new Uint8Array(1)), 1, 'a range past the end');
other.destroy();
dec2.destroy();

// The surface's size past camera group 0's head: unknown until a frame of the
// fragment decodes, then what the fetch plan keeps whole or leaves out.
const surfaceStream = readFileSync(surfacePath);
const sd = await FvvDecoder.create({ moduleFactory, zstd: decompress });
sd.openRanges(surfaceStream.length);
sd.addRange(0, surfaceStream);
check(sd.process() === 'ready', 'the surface stream opens');
const sinfo = sd.info();
check(sinfo.formatVersion === 12, `the surface stream's format version ${sinfo.formatVersion}`);
const sgroups = Math.ceil(sinfo.cameraCount / sinfo.gopCameras);
check(sd.fragment(0).surfaceSize === 0, 'no surface size before a frame of the fragment decodes');
const sframe = sd.decodeFrame(1);
const g0 = sd.fragment(0);
check(sframe.surface !== null && sframe.surfaceBytes > 0 && sframe.surfaceBytes === g0.surfaceSize,
  `a decoded frame tells its surface's bytes (${sframe.surfaceBytes}, fragment ${g0.surfaceSize})`);
check(g0.headSize + g0.surfaceSize < g0.size, 'the surface lies within the fragment');
const sgop = sd.fragments(0, sgroups);
for (const budget of [g0.headSize + 1, g0.headSize + g0.surfaceSize - 1, g0.headSize + g0.surfaceSize + 500]) {
  const heads = sgop.reduce((n, f) => n + f.headSize, 0) - g0.headSize;
  const p0 = sd.planPrefixes(sgop, budget + heads)[0];
  check(p0 === g0.headSize || p0 >= g0.headSize + g0.surfaceSize,
    `camera group 0 at its head or past its whole surface (${p0} of budget ${budget + heads})`);
}
sd.destroy();

// The page's depth maps draw the native players' triangles, index for index.
{
  const body = readFileSync(bodyPath);
  const bd = await FvvDecoder.create({ moduleFactory, zstd: decompress });
  bd.openRanges(body.length);
  bd.addRange(0, body);
  check(bd.process() === 'ready', 'the body stream opens');
  const binfo = bd.info(), bmodel = bd.model();
  const centres = Array.from({ length: binfo.cameraCount }, (_, c) => bd.camera(c).centre);
  const playback = await FvvPlayback.create({ moduleFactory, info: binfo, centres });
  const kept = playback.depthMapTriangles(bmodel.positions, bmodel.triangles);
  const inWorker = bd.depthMapTriangles();  // what a page's decoder worker gives its renderer
  playback.destroy();
  bd.destroy();
  let hash = 2166136261;
  for (const i of kept) hash = Math.imul((hash ^ i) >>> 0, 16777619) >>> 0;
  const mine = `${kept.length} ${hash.toString(16).padStart(8, '0')}`;
  check(mine === nativeDepthTriangles.trim(),
    `the depth maps' triangles: ${mine} here, ${nativeDepthTriangles.trim()} native`);
  check(same(inWorker, kept), 'FvvDecoder.depthMapTriangles gives FvvPlayback\'s triangles');
  check(kept.length > 0 && kept.length <= bmodel.triangles.length / 3,
    `the depth maps draw a quarter of the body's triangles or fewer (${kept.length / 3} of ${bmodel.triangles.length / 3})`);
}

console.log(`${failures ? 'FAILED' : 'passed'}: ${info.frameCount} frames, ${info.cameraCount} cameras, ` +
  `head in ${requests} requests of 4 KiB`);
process.exit(failures ? 1 : 0);
