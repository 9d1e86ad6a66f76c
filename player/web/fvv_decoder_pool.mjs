// Several decoder workers as one (FvvDecoderWorker's methods): every byte
// range goes to each, and a frame's cameras are shared out among them, each
// worker decoding its cameras' fragments (and the motion) in parallel; the
// views come back merged into one frame. Parallel decoding for a page that
// has no SharedArrayBuffer for threads inside one module, and for one that
// has: the workers need no shared memory.
//
//   const pool = await FvvDecoderPool.create(workerUrl, options, 2);
//   ... the FvvDecoderWorker calls ...; pool.terminate();

import { FvvDecoderWorker } from './fvv_decoder_worker_client.mjs';

// Calls answered by the first worker alone (they read what every worker holds alike).
const FIRST = ['wantedRange', 'framesAvailable', 'info', 'camera', 'model', 'fragmentCount',
  'fragment', 'fragments', 'planPrefixes', 'bandwidthAfter', 'gopFetchBudget', 'depthMapTriangles'];
// Calls every worker makes (input, state).
const ALL = ['openRanges', 'addRange', 'addRanges', 'push', 'pushEnd', 'process', 'destroy',
  'warmMemory'];

export class FvvDecoderPool {
  static async create(workerUrl, options, count = 2) {
    const workers = await Promise.all(
      Array.from({ length: Math.max(1, count) }, () => FvvDecoderWorker.create(workerUrl, options)));
    return new FvvDecoderPool(workers);
  }

  constructor(workers) {
    this.workers = workers;
  }

  terminate() {
    for (const w of this.workers) w.terminate();
  }

  // Each worker's share of `cameras` (all the stream's when absent), one
  // fragment's cameras staying together (a camera group decodes as one).
  async #shares(cameras) {
    this.stream ??= await this.workers[0].info();
    const all = cameras ?? [...Array(this.stream.cameraCount).keys()];
    const groups = new Map();
    for (const c of all) {
      const g = Math.floor(c / this.stream.gopCameras);
      if (!groups.has(g)) groups.set(g, []);
      groups.get(g).push(c);
    }
    const shares = this.workers.map(() => []);
    [...groups.values()].forEach((list, i) => shares[i % shares.length].push(...list));
    return shares;
  }

  async decodeFrame(index, options = {}) {
    const shares = (await this.#shares(options.cameras)).filter((s) => s.length > 0);
    const frames = await Promise.all(shares.map((cameras, i) =>
      this.workers[i].decodeFrame(index, { ...options, cameras })));
    return merged(frames, shares);
  }

  // decodeFrames (a GOP's frames in one message per worker), merged frame by frame.
  async decodeFrames(first, count, options = {}) {
    const shares = (await this.#shares(options.cameras)).filter((s) => s.length > 0);
    const lists = await Promise.all(shares.map((cameras, i) =>
      this.workers[i].decodeFrames(first, count, { ...options, cameras })));
    return lists[0].map((_, k) => merged(lists.map((l) => l[k]), shares));
  }
}

// The views of each worker's cameras (shares[i] for frames[i]) in one frame;
// the report over all.
function merged(frames, shares) {
  const frame = frames[0];
  frames.slice(1).forEach((f, i) => {
    for (const c of shares[i + 1]) frame.views[c] = f.views[c];
    const r = frame.report, o = f.report;
    r.bytesDecoded += o.bytesDecoded;
    r.bytesAvailable += o.bytesAvailable;
    r.bitplanes = r.bitplanes.map((b, k) => Math.min(b, o.bitplanes[k]));
    r.decodeMs = Math.max(r.decodeMs, o.decodeMs);
    r.complete = r.complete && o.complete;
  });
  return frame;
}
for (const method of FIRST) {
  FvvDecoderPool.prototype[method] = function (...args) {
    return this.workers[0].call(method, ...args);
  };
}
for (const method of ALL) {
  FvvDecoderPool.prototype[method] = async function (...args) {
    const results = await Promise.all(this.workers.map((w) => w.call(method, ...args)));
    return results[0];
  };
}
// A method FvvDecoderWorker has and this pool does not would be a silent gap.
for (const method of Object.getOwnPropertyNames(FvvDecoderWorker.prototype)) {
  if (method === 'constructor' || method === 'call') continue;
  if (!(method in FvvDecoderPool.prototype)) throw new Error(`FvvDecoderPool lacks ${method}`);
}
