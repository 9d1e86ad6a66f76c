// The decoder in a Web Worker, so that decoding never blocks the page's
// drawing. The page talks to it through FvvDecoderWorker (fvv_decoder_worker_client.mjs):
// each message { id, method, args } calls that FvvDecoder method here and is
// answered { id, result } or { id, error: { status, statusName, message } };
// the decoded views' pixel buffers are transferred, not copied.
//
// The first message is { id, method: 'create', args: [{ moduleUrl, zstdUrl, wasmModule,
// ...settings }] }: the worker imports the module and fzstd from those URLs
// (and instantiates wasmModule, when the page compiled it, rather than the .wasm).
// { method: 'warmMemory', args: [bytes] } is the worker's own: it readies that
// much memory for the decodes to come while the worker has nothing else to do.
import { FvvDecoder } from './fvv_decoder_api.mjs';

// The FvvDecoder methods a page may call (fvv_decoder_worker_client.mjs).
const METHODS = new Set(['openRanges', 'addRange', 'addRanges', 'push', 'pushEnd', 'process',
  'wantedRange', 'framesAvailable', 'info', 'camera', 'model', 'fragmentCount', 'fragment', 'fragments',
  'decodeFrame', 'decodeFrames', 'depthMapTriangles',
  'planPrefixes', 'bandwidthAfter', 'gopFetchBudget', 'destroy']);
let decoder = null;

// Fresh memory touched while the worker is idle (the stream's head read, its
// first GOP on its way), in steps between the page's messages, then given
// back to the heap when a decode starts: the first decode otherwise pays the
// page faults of its working set on the way to the first frame
// (docs/web.md: 0.4-0.7 s for 160 MB here).
const WARM_STEP = 8 << 20;
const warm = { target: 0, chunks: [], timer: 0 };

function warmStep() {
  warm.timer = 0;
  const m = decoder?.m;
  if (!m || warm.target <= 0) return;
  const p = m._malloc(WARM_STEP);
  if (!p) return;
  m.HEAPU8.fill(0, p, p + WARM_STEP);
  warm.chunks.push(p);
  warm.target -= WARM_STEP;
  warm.timer = setTimeout(warmStep, 0);
}

function warmEnd() {
  clearTimeout(warm.timer);
  warm.timer = 0;
  warm.target = 0;
  for (const p of warm.chunks.splice(0)) decoder?.m._free(p);
}

self.onmessage = async ({ data: { id, method, args } }) => {
  try {
    let result;
    if (method === 'warmMemory') {
      // Returns at once: the steps run while no other message waits.
      warm.target = Math.max(warm.target, Number(args[0]) || 0);
      if (!warm.timer) warm.timer = setTimeout(warmStep, 0);
    } else if (method === 'create') {
      warmEnd();
      const { moduleUrl, zstdUrl, ...settings } = args[0];
      const { decompress } = await import(zstdUrl);
      decoder?.destroy();
      decoder = await FvvDecoder.create({ moduleUrl, zstd: decompress, ...settings });
    } else if (!decoder) {
      throw new Error(`${method} before create`);
    } else if (!METHODS.has(method)) {
      throw new Error(`no decoder method ${method}`);
    } else {
      if (method.startsWith('decode') || method === 'destroy') warmEnd();
      result = decoder[method](...args);
    }
    const transfer = [];
    for (const frame of Array.isArray(result) ? result : [result]) {
      for (const v of frame?.views ?? []) {
        if (v.pixels) transfer.push(v.pixels.buffer);
        if (v.mask) transfer.push(v.mask.buffer);
      }
      if (frame?.surface) transfer.push(frame.surface.buffer);
    }
    self.postMessage({ id, result }, transfer);
  } catch (e) {
    self.postMessage({ id, error: { status: e.status ?? -1, statusName: e.statusName ?? 'error',
                                    message: e.message } });
  }
};
