// The playback loop compiled into the module (player/web/playback_module.cc,
// player/playback/playback_loop.h): the same playhead, time budgets, waits,
// camera choice and, here, fetch budgets as the native player's. The page
// ticks it, serves the GOP requests it makes (fetch, decode in the worker) and
// delivers their reports; it never decides itself what to fetch or decode.
//
//   const pb = await FvvPlayback.create({ moduleUrl, info, centres });
//   pb.advance(dt, eye, target);  const s = pb.state();   // s.frame, s.changed ...
//   const r = pb.nextRequest();   // { gop, cameras, maxMs, floorShare, fetchBytes } or null
//   pb.fetched(r.gop);            // its bytes are in: the next fetch may start
//   const d = pb.nextDecode();    // a fetched GOP due for decoding, or null
//   pb.deliver(d.gop, frame.report, cameras.length);   // the cameras it decoded

import { depthMapTrianglesAt, instantiateFrom, planPrefixes } from './fvv_decoder_api.mjs';

const STATE = [
  'hasFrame', 'frame', 'changed', 'playhead', 'playing', 'bytesPerSecond', 'fetchBudget',
  'stalls', 'framesWithoutTexture', 'gops', 'bytesFetched', 'decodeMs', 'nextMaxMs',
  'belowRealTime', 'framesDrawn', 'framesAdvanced', 'bytesDecoded', 'bytesAvailable',
  'gopBytesDecoded', 'gopBytesAvailable', 'gopDecodeMs', 'lumaPlanes', 'cbPlanes', 'crPlanes',
  'waits', 'maxCameras',
];

export class FvvPlayback {
  // info: FvvDecoder.info(); centres: the cameras' centres ([x, y, z] each).
  // wasmModule: the module's .wasm compiled already (WebAssembly.Module).
  static async create({ moduleUrl, moduleFactory, wasmModule, info, centres, floorShare = 0 }) {
    const factory = moduleFactory ?? (await import(moduleUrl)).default;
    // The loop decodes nothing: no zstd frame reaches this instance.
    const m = await factory({
      fvvZstdDecompress: () => { throw new Error('no decoding here'); },
      ...(wasmModule ? { instantiateWasm: instantiateFrom(wasmModule) } : {}),
    });
    return new FvvPlayback(m, info, centres, floorShare);
  }

  constructor(m, info, centres, floorShare) {
    this.m = m;
    this.info = info;
    this.cameraCount = centres.length;
    this.centres = m._malloc(12 * centres.length);
    m.HEAPF32.set(centres.flat(), this.centres >> 2);
    this.handle = m._fvv_web_playback_create(info.frameCount, info.frameRateNum, info.frameRateDen,
      info.gopFrames, this.centres, centres.length, floorShare);
    if (!this.handle) throw new Error('this stream cannot play (no frames, no frame rate or no cameras)');
    this.out = m._malloc(8 * STATE.length);
  }

  destroy() {
    if (!this.handle) return;
    this.m._fvv_web_playback_destroy(this.handle);
    this.m._free(this.out);
    this.m._free(this.centres);
    this.handle = 0;
  }

  advance(dt, eye, target) {
    if (this.m._fvv_web_playback_advance(this.handle, dt, ...eye, ...target) !== 0) {
      throw new Error('the playback loop failed');
    }
  }

  state() {
    this.m._fvv_web_playback_state(this.handle, this.out);
    const v = this.m.HEAPF64.subarray(this.out >> 3, (this.out >> 3) + STATE.length);
    const s = {};
    STATE.forEach((name, i) => { s[name] = v[i]; });
    s.hasFrame = s.hasFrame !== 0;
    s.changed = s.changed !== 0;
    s.playing = s.playing !== 0;
    s.belowRealTime = s.belowRealTime !== 0;
    return s;
  }

  // The next GOP to fetch: { gop, cameras, maxMs, floorShare, fetchBytes }, or null.
  nextRequest() {
    return this.#request(this.m._fvv_web_playback_next_request);
  }
  // The next fetched GOP to decode (the same fields), or null.
  nextDecode() {
    return this.#request(this.m._fvv_web_playback_next_decode);
  }
  #request(call) {
    if (!call(this.handle, this.out)) return null;
    const v = this.m.HEAPF64.subarray(this.out >> 3, (this.out >> 3) + 6);
    const mask = BigInt(v[1]) | (BigInt(v[2]) << 32n);
    const cameras = [];
    for (let c = 0; c < this.cameraCount; ++c) if (mask === 0n || (mask >> BigInt(c)) & 1n) cameras.push(c);
    return { gop: v[0], cameras, maxMs: v[3], floorShare: v[4], fetchBytes: v[5] };
  }

  // `cameras`: how many it decoded (0 or absent: as many as nextDecode asked).
  deliver(gop, report, cameras = 0) {
    const [y, u, v] = report.bitplanes;
    this.m._fvv_web_playback_deliver(this.handle, gop, report.bytesDecoded, report.bytesAvailable,
      report.decodeMs, report.maxMs ?? 0, report.complete ? 1 : 0, y, u, v, cameras);
  }
  fetched(gop) { this.m._fvv_web_playback_fetched(this.handle, gop); }
  failed(gop) { this.m._fvv_web_playback_failed(this.handle, gop); }
  forget(gop) { this.m._fvv_web_playback_forget(this.handle, gop); }
  held(gop) { return this.m._fvv_web_playback_held(this.handle, gop) !== 0; }
  fetchMeasured(bytes, seconds) { this.m._fvv_web_playback_fetch_measured(this.handle, bytes, seconds); }
  frameDrawn(ms) { this.m._fvv_web_playback_frame_drawn(this.handle, ms); }
  seek(frame) { this.m._fvv_web_playback_seek(this.handle, frame); }
  setTransport({ playing, loop, speed }) {
    this.m._fvv_web_playback_set_transport(this.handle, playing ? 1 : 0, loop ? 1 : 0, speed ?? 1);
  }

  // The fetch plan (player/playback/fetch_plan.h): the prefix of each
  // fragment ({ headSize, size }) to fetch within `budget` bytes.
  planPrefixes(fragments, budget) {
    return planPrefixes(this.m, fragments, budget);
  }

  // The renderer's constants (container/geometric_visibility.h).
  renderConstants() {
    const p = this.m._malloc(56);
    this.m._fvv_web_render_constants(p);
    const [depthTolerance, slopeTexels, minFacing, fullFacing, angleEpsilon, viewExponent,
      facingExponent] = this.m.HEAPF64.subarray(p >> 3, (p >> 3) + 7);
    this.m._free(p);
    return { depthTolerance, slopeTexels, minFacing, fullFacing, angleEpsilon, viewExponent,
      facingExponent };
  }
  // The triangles the depth maps draw (player/playback/depth_map_triangles.h):
  // the model simplified, over its own vertices, as the native renderer draws
  // them. positions: Float32Array (x y z per vertex); triangles: Uint32Array.
  depthMapTriangles(positions, triangles) {
    const m = this.m;
    const p = m._malloc(positions.byteLength), t = m._malloc(triangles.byteLength);
    try {
      m.HEAPF32.set(positions, p >> 2);
      m.HEAPU32.set(triangles, t >> 2);
      return depthMapTrianglesAt(m, p, positions.length / 3, t, triangles.length / 3);
    } finally {
      m._free(t);
      m._free(p);
    }
  }
  // A camera's depth map size for its image size: [width, height].
  depthMapSize(width, height) {
    const p = this.m._malloc(8);
    this.m._fvv_web_depth_map_size(width, height, p);
    const size = [this.m.HEAP32[p >> 2], this.m.HEAP32[(p >> 2) + 1]];
    this.m._free(p);
    return size;
  }

  // The cameras a view blends, as the native renderer picks them, among the
  // cameras given (indices into the centres).
  viewCameras(present, eye, target) {
    const m = this.m, p = m._malloc(12 * present.length + 8);
    try {
      present.forEach((c, i) => m.HEAPF32.set(
        m.HEAPF32.subarray((this.centres >> 2) + 3 * c, (this.centres >> 2) + 3 * c + 3), (p >> 2) + 3 * i));
      const out = p + 12 * present.length;
      m._fvv_web_view_cameras(p, present.length, ...eye, ...target, out);
      const mask = BigInt(m.HEAPU32[out >> 2]) | (BigInt(m.HEAPU32[(out >> 2) + 1]) << 32n);
      return present.filter((_, i) => (mask >> BigInt(i)) & 1n);
    } finally {
      m._free(p);
    }
  }
}
