// The decoder library in WebAssembly, as JavaScript: a thin layer over the C
// API of include/fvv/fvv_decoder.h (the same calls, the same statuses), with
// the structs read into plain objects and the decoded pixels copied out, so
// nothing handed back points into the module's memory.
//
//   import { FvvDecoder } from './fvv_decoder_api.mjs';
//   import { decompress } from 'fzstd';
//   const dec = await FvvDecoder.create({ moduleUrl: '.../fvv_decoder.mjs', zstd: decompress });
//   dec.openRanges(size);                       // then addRange() what process() asks for
//   dec.addRange(0, firstBytes);
//   for (let e; (e = dec.process()) === 'need';) { const r = dec.wantedRange(); ... addRange }
//   const f = dec.fragment(0);                  // { offset, size, headSize, held, ... }
//   dec.addRange(f.offset, prefixOfFragment);
//   const frame = dec.decodeFrame(0, { cameras: [0, 1] });   // views[c].pixels: RGB8
//   dec.destroy();
//
// Errors throw FvvError, whose `status` is the C API's status code (fvv_types.h)
// and `message` the decoder's own.

const EVENTS = ['need', 'ready', 'frames', 'end'];
const FORMATS = { rgb: 0, yuv: 1 };

// The module's instantiation from a WebAssembly.Module compiled already (on
// the page, and handed to its worker), instead of fetching and compiling the
// .wasm once more: emscripten's instantiateWasm hook.
export function instantiateFrom(wasmModule) {
  return (imports, receive) => {
    WebAssembly.instantiate(wasmModule, imports).then((instance) => receive(instance, wasmModule));
    return {};
  };
}

// A u64 of the module's memory, as a Number (exact below 2^53), and from a
// Number or a BigInt.
function readU64(m, p) {
  return m.HEAPU32[p >> 2] + m.HEAPU32[(p >> 2) + 1] * 2 ** 32;
}
function writeU64(m, p, v) {
  const big = typeof v === 'bigint' ? v : BigInt(Math.min(v, Number.MAX_SAFE_INTEGER));
  m.HEAPU32[p >> 2] = Number(big & 0xffffffffn);
  m.HEAPU32[(p >> 2) + 1] = Number(big >> 32n);
}

// The triangles both players' depth maps draw (player/playback/depth_map_triangles.h)
// for the model whose positions and triangles lie at `positions` and
// `triangles` in module instance m's memory.
export function depthMapTrianglesAt(m, positions, vertexCount, triangles, triangleCount) {
  const out = m._malloc(Math.max(4, triangleCount * 12));
  try {
    const n = m._fvv_web_depth_map_triangles(positions, vertexCount, triangles, triangleCount, out);
    return m.HEAPU32.slice(out >> 2, (out >> 2) + n);
  } finally {
    m._free(out);
  }
}

// The fetch plan (player/playback/fetch_plan.h) of a module instance, the
// decoder's or the page's loop's: the prefix of each fragment ({ headSize,
// size, surfaceSize }) to fetch within `budget` bytes.
export function planPrefixes(m, fragments, budget) {
  const n = fragments.length;
  const p = m._malloc(Math.max(1, 32 * n));
  try {
    fragments.forEach((f, i) => {
      writeU64(m, p + 8 * i, f.headSize);
      writeU64(m, p + 8 * (n + i), f.size);
      writeU64(m, p + 8 * (2 * n + i), f.surfaceSize ?? 0);
    });
    m._fvv_web_plan_prefixes(p, p + 8 * n, p + 16 * n, n,
      BigInt(Math.min(budget, Number.MAX_SAFE_INTEGER)), p + 24 * n);
    return fragments.map((_, i) => readU64(m, p + 8 * (3 * n + i)));
  } finally {
    m._free(p);
  }
}

export class FvvError extends Error {
  constructor(status, name, message) {
    // The decoder's messages begin with the status's name already.
    super(message.startsWith(name) ? message : `${name}: ${message}`);
    this.status = status;
    this.statusName = name;
  }
}

export class FvvDecoder {
  // moduleUrl: where the build's fvv_decoder.mjs is; or moduleFactory, its
  // default export. zstd: a zstd decompressor (data, out) => Uint8Array, such
  // as fzstd's decompress. memoryCap, maxGopSamples, maxFragmentBytes:
  // fvv_decoder_settings; the claim (SPEC.md 5.1) defaults to level 2's GOP
  // samples and fragment bytes, about 1.1 GiB of the 4 GiB a page addresses.
  // wasmModule: the module's .wasm compiled already (WebAssembly.Module).
  static async create({
    moduleUrl, moduleFactory, wasmModule, zstd, memoryCap = 0, maxGopSamples = 2 ** 26,
    maxFragmentBytes = 32 * 2 ** 20,
  } = {}) {
    if (!zstd) throw new Error('FvvDecoder.create needs a zstd decompressor (fzstd.decompress)');
    const factory = moduleFactory ?? (await import(moduleUrl)).default;
    const m = await factory({
      fvvZstdDecompress: zstd, ...(wasmModule ? { instantiateWasm: instantiateFrom(wasmModule) } : {}),
    });
    return new FvvDecoder(m, { memoryCap, maxGopSamples, maxFragmentBytes });
  }

  constructor(m, { memoryCap, maxGopSamples, maxFragmentBytes }) {
    this.m = m;
    const settings = m._malloc(40);
    m._fvv_decoder_default_settings(settings);
    m.HEAPU32[settings >> 2] = 1;  // one thread: this build has none to start
    if (memoryCap) this.#setU64(settings + 8, memoryCap);
    m.HEAP32[(settings + 16) >> 2] = 0;  // nothing decoded ahead: the caller schedules
    this.#setU64(settings + 24, maxGopSamples);
    this.#setU64(settings + 32, maxFragmentBytes);
    const out = m._malloc(4);
    const status = m._fvv_decoder_create(settings, out);
    this.handle = m.HEAPU32[out >> 2];
    m._free(out);
    m._free(settings);
    if (status !== 0) throw this.#error(status, 'cannot create a decoder');
    this.scratch = m._malloc(256);  // structs read back from the C API
  }

  destroy() {
    if (!this.handle) return;
    this.m._fvv_decoder_destroy(this.handle);
    this.m._free(this.scratch);
    this.handle = 0;
  }

  // Input by byte ranges (HTTP Range requests), by pushed bytes (in order).
  openRanges(streamSize) {
    this.#check(this.m._fvv_decoder_open_ranges(this.handle, BigInt(streamSize)));
  }
  addRange(offset, bytes) {
    this.#withBytes(bytes, (p) =>
      this.#check(this.m._fvv_decoder_add_range(this.handle, BigInt(offset), p, bytes.length)));
  }
  // Several ranges in one call ([offset, bytes] pairs, in order): a page
  // whose decoder sits in a worker pays one message for a GOP's fragments.
  addRanges(ranges) {
    for (const [offset, bytes] of ranges) this.addRange(offset, bytes);
  }
  push(bytes) {
    this.#withBytes(bytes, (p) => this.#check(this.m._fvv_decoder_push(this.handle, p, bytes.length)));
  }
  pushEnd() {
    this.#check(this.m._fvv_decoder_push_end(this.handle));
  }
  // 'need', 'ready', 'frames' or 'end' (FVV_EVENT_*).
  process() {
    const s = this.scratch;
    this.#check(this.m._fvv_decoder_process(this.handle, s));
    return EVENTS[this.m.HEAP32[s >> 2]];
  }
  // The bytes the header boxes or index need next: { offset, size }, or null.
  wantedRange() {
    const s = this.scratch;
    if (!this.m._fvv_decoder_wanted_range(this.handle, s, s + 8)) return null;
    return { offset: this.#u64(s), size: this.#u64(s + 8) };
  }
  framesAvailable() {
    return this.m._fvv_decoder_frames_available(this.handle);
  }

  info() {
    const s = this.scratch;
    this.#check(this.m._fvv_decoder_get_info(this.handle, s));
    const u = this.m.HEAPU32.subarray(s >> 2, (s >> 2) + 15);
    return {
      formatVersion: u[0], profile: u[1], level: u[2], frameCount: u[3],
      frameRate: u[4] / u[5], frameRateNum: u[4], frameRateDen: u[5], cameraCount: u[6],
      atlasWidth: u[7], atlasHeight: u[8], gopFrames: u[9], gopCameras: u[10],
      boneCount: u[11], vertexCount: u[12], triangleCount: u[13], hasMasks: u[14] !== 0,
    };
  }

  camera(index) {
    const s = this.scratch, m = this.m;
    this.#check(m._fvv_decoder_get_camera(this.handle, index, s));
    const f64 = (o, n) => Array.from(m.HEAPF64.subarray((s + o) >> 3, ((s + o) >> 3) + n));
    const [fx, fy, cx, cy] = f64(16, 4);
    return {
      name: m.UTF8ToString(m.HEAPU32[s >> 2]), width: m.HEAPU32[(s + 4) >> 2],
      height: m.HEAPU32[(s + 8) >> 2], fx, fy, cx, cy, distortion: f64(48, 5),
      rotation: f64(88, 9), translation: f64(160, 3), centre: f64(184, 3),
    };
  }

  // The body model: typed arrays copied out of the module.
  model() {
    const s = this.scratch, m = this.m;
    this.#check(m._fvv_decoder_get_model(this.handle, s));
    const w = m.HEAPU32.subarray(s >> 2, (s >> 2) + 11);
    const [bones, parent, rest, vertices, pos, nrm, uv, joints, weights, triangles, tri] = w;
    const f32 = (p, n) => m.HEAPF32.slice(p >> 2, (p >> 2) + n);
    return {
      boneParent: m.HEAP32.slice(parent >> 2, (parent >> 2) + bones),
      boneRestWorld: f32(rest, bones * 16),
      positions: f32(pos, vertices * 3), normals: f32(nrm, vertices * 3), uvs: f32(uv, vertices * 2),
      joints: new Uint16Array(m.HEAPU8.slice(joints, joints + vertices * 8).buffer),
      weights: f32(weights, vertices * 4),
      triangles: m.HEAPU32.slice(tri >> 2, (tri >> 2) + triangles * 3),
    };
  }

  // The triangles both players' depth maps draw for this stream's model
  // (player/playback/depth_map_triangles.h), as FvvPlayback.depthMapTriangles
  // gives them: here, so that a page computes them in its decoder worker.
  depthMapTriangles() {
    const s = this.scratch, m = this.m;
    this.#check(m._fvv_decoder_get_model(this.handle, s));
    const [, , , vertices, pos, , , , , triangles, tri] = m.HEAPU32.subarray(s >> 2, (s >> 2) + 11);
    return depthMapTrianglesAt(m, pos, vertices, tri, triangles);
  }

  // Fragments [first, first + count) at once (one message to a worker).
  fragments(first, count) {
    const out = [];
    for (let i = first; i < Math.min(first + count, this.fragmentCount()); ++i) out.push(this.fragment(i));
    return out;
  }
  fragmentCount() {
    return this.m._fvv_decoder_fragment_count(this.handle);
  }
  // A GOP fragment's place in the stream: the prefix of at least headSize
  // bytes from offset decodes (streams with the texture in chunks);
  // surfaceSize, once a frame of it was decoded, the bytes past the head that
  // carry its surface whole (0 before, and without one).
  fragment(index) {
    const s = this.scratch, u = this.m.HEAPU32;
    this.#check(this.m._fvv_decoder_get_fragment(this.handle, index, s));
    return {
      index, firstFrame: u[s >> 2], frameCount: u[(s >> 2) + 1], firstCamera: u[(s >> 2) + 2],
      cameraCount: u[(s >> 2) + 3], offset: this.#u64(s + 16), size: this.#u64(s + 24),
      headSize: this.#u64(s + 32), held: this.#u64(s + 40), surfaceSize: this.#u64(s + 48),
    };
  }

  // The fetch policy (player/playback/fetch_plan.h, compiled into the module):
  // the prefix of each fragment ({ headSize, size, surfaceSize }) to fetch within `budget`
  // bytes; the bandwidth after a fetch; the bytes a GOP's fetch may take.
  planPrefixes(fragments, budget) {
    return planPrefixes(this.m, fragments, budget);
  }
  bandwidthAfter(bytesPerSecond, bytes, seconds) {
    return this.m._fvv_web_bandwidth_after(bytesPerSecond, BigInt(bytes), seconds);
  }
  gopFetchBudget(bytesPerSecond, gopSeconds) {
    return Number(this.m._fvv_web_gop_fetch_budget(bytesPerSecond, gopSeconds));
  }

  // Decodes frame `index` (fvv_decoder_decode_frame). options: maxBytes (per
  // fragment), maxMs, floorShare, format ('rgb' or 'yuv'), cameras (indices to
  // decode; all when absent). The views of cameras left out have null pixels.
  decodeFrame(index, { maxBytes = 0, maxMs = 0, floorShare = 0, format = 'rgb', cameras } = {}) {
    const m = this.m, b = this.scratch + 64;
    m.HEAPU8.fill(0, b, b + 40);
    this.#setU64(b, maxBytes);
    m.HEAPF64[(b + 8) >> 3] = maxMs;
    m.HEAPU32[(b + 16) >> 2] = FORMATS[format] ?? 99;
    let mask = 0n;
    for (const c of cameras ?? []) mask |= 1n << BigInt(c);
    this.#setU64(b + 24, mask);
    m.HEAPF64[(b + 32) >> 3] = floorShare;
    const out = this.scratch + 128;
    this.#check(m._fvv_decoder_decode_frame(this.handle, index, b, out));
    const f = m.HEAPU32[out >> 2];
    let frame;
    try {
      frame = this.#readFrame(f);
    } finally {
      m._fvv_frame_release(f);
    }
    // With a surface: its bytes past camera group 0's head in this GOP, which
    // a page fetching by ranges plans the next GOPs' prefixes with.
    if (frame.surface && this.fragmentCount() > 0) {
      this.grid ??= this.info();
      const groups = Math.ceil(this.grid.cameraCount / this.grid.gopCameras);
      frame.surfaceBytes = this.fragment(Math.floor(index / this.grid.gopFrames) * groups).surfaceSize;
    }
    return frame;
  }

  // Frames first .. first + count - 1 under the same options (decodeFrame's),
  // in one call: a GOP's frames for a worker's one message.
  decodeFrames(first, count, options = {}) {
    const frames = [];
    for (let i = first; i < first + count; ++i) frames.push(this.decodeFrame(i, options));
    return frames;
  }

  #readFrame(f) {
    const m = this.m, u = m.HEAPU32, q = f >> 2;
    const bones = u[q + 1], cameras = u[q + 4], width = u[q + 5], height = u[q + 6];
    const pixels = width * height * 3, views = [];
    for (let c = 0; c < cameras; ++c) {
      const pix = u[(u[q + 8] >> 2) + 2 * c], mask = u[(u[q + 8] >> 2) + 2 * c + 1];
      views.push({
        pixels: pix ? m.HEAPU8.slice(pix, pix + pixels) : null,
        mask: mask ? m.HEAPU8.slice(mask, mask + width * height) : null,
      });
    }
    const r = f + 40, surface = u[q + 24];
    if (surface && this.vertexCount === undefined) this.vertexCount = this.info().vertexCount;
    return {
      index: u[q], width, height, format: u[q + 7] === 1 ? 'yuv' : 'rgb',
      boneWorld: m.HEAPF32.slice(u[q + 2] >> 2, (u[q + 2] >> 2) + bones * 16),
      boneSkin: m.HEAPF32.slice(u[q + 3] >> 2, (u[q + 3] >> 2) + bones * 16),
      views,
      report: {
        bytesDecoded: this.#u64(r), bytesAvailable: this.#u64(r + 8),
        bitplanes: Array.from(u.subarray((r + 16) >> 2, ((r + 16) >> 2) + 3)),
        decodeMs: m.HEAPF64[(r + 32) >> 3], complete: m.HEAP32[(r + 40) >> 2] !== 0,
        maxMs: m.HEAPF64[(r + 48) >> 3],
      },
      // The frame's own surface in the bind pose (format version 12), or null.
      surface: surface ? m.HEAPF32.slice(surface >> 2, (surface >> 2) + this.vertexCount * 3) : null,
    };
  }

  #withBytes(bytes, use) {
    const p = this.m._malloc(Math.max(1, bytes.length));
    try {
      this.m.HEAPU8.set(bytes, p);
      use(p);
    } finally {
      this.m._free(p);
    }
  }
  #u64(p) {
    return readU64(this.m, p);
  }
  #setU64(p, v) {
    writeU64(this.m, p, v);
  }
  #check(status) {
    if (status !== 0) throw this.#error(status, this.m.UTF8ToString(this.m._fvv_decoder_error(this.handle)));
  }
  #error(status, message) {
    return new FvvError(status, this.m.UTF8ToString(this.m._fvv_status_name(status)), message);
  }
}
