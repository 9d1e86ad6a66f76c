// The decoder in a Web Worker, so that decoding never blocks the page's
// drawing. The page talks to it through FvvDecoderWorker (fvv_decoder_worker_client.mjs):
// each message { id, method, args } calls that FvvDecoder method here and is
// answered { id, result } or { id, error: { status, statusName, message } };
// the decoded views' pixel buffers are transferred, not copied.
//
// The first message is { id, method: 'create', args: [{ moduleUrl, zstdUrl, wasmModule,
// ...settings }] }: the worker imports the module and fzstd from those URLs
// (and instantiates wasmModule, when the page compiled it, rather than the .wasm).
import { FvvDecoder } from './fvv_decoder_api.mjs';

// The FvvDecoder methods a page may call (fvv_decoder_worker_client.mjs).
const METHODS = new Set(['openRanges', 'addRange', 'push', 'pushEnd', 'process', 'wantedRange',
  'framesAvailable', 'info', 'camera', 'model', 'fragmentCount', 'fragment', 'fragments', 'decodeFrame',
  'planPrefixes', 'bandwidthAfter', 'gopFetchBudget', 'destroy']);
let decoder = null;

self.onmessage = async ({ data: { id, method, args } }) => {
  try {
    let result;
    if (method === 'create') {
      const { moduleUrl, zstdUrl, ...settings } = args[0];
      const { decompress } = await import(zstdUrl);
      decoder?.destroy();
      decoder = await FvvDecoder.create({ moduleUrl, zstd: decompress, ...settings });
    } else if (!decoder) {
      throw new Error(`${method} before create`);
    } else if (!METHODS.has(method)) {
      throw new Error(`no decoder method ${method}`);
    } else {
      result = decoder[method](...args);
    }
    const transfer = [];
    for (const v of result?.views ?? []) {
      if (v.pixels) transfer.push(v.pixels.buffer);
      if (v.mask) transfer.push(v.mask.buffer);
    }
    if (result?.surface) transfer.push(result.surface.buffer);
    self.postMessage({ id, result }, transfer);
  } catch (e) {
    self.postMessage({ id, error: { status: e.status ?? -1, statusName: e.statusName ?? 'error',
                                    message: e.message } });
  }
};
