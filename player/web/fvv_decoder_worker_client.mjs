// The page's side of the decoder in a Web Worker (fvv_decoder_worker.mjs):
// FvvDecoder's methods, each a promise.
//
//   const dec = await FvvDecoderWorker.create(new URL('./fvv_decoder_worker.mjs', import.meta.url),
//     { moduleUrl: '.../fvv_decoder.mjs', zstdUrl: '.../fzstd/esm/index.mjs' });
//   await dec.openRanges(size); ... const frame = await dec.decodeFrame(0);
//   dec.terminate();
export class FvvDecoderWorker {
  static async create(workerUrl, options) {
    const client = new FvvDecoderWorker(new Worker(workerUrl, { type: 'module' }));
    await client.call('create', options);
    return client;
  }

  constructor(worker) {
    this.worker = worker;
    this.pending = new Map();
    this.next = 1;
    worker.onmessage = ({ data }) => {
      const p = this.pending.get(data.id);
      this.pending.delete(data.id);
      if (!p) return;
      if (data.error) {
        const { statusName, message } = data.error;
        // The decoder's messages begin with their status's name already.
        const e = new Error(message.startsWith(statusName) ? message : `${statusName}: ${message}`);
        e.status = data.error.status;
        p.reject(e);
      } else {
        p.resolve(data.result);
      }
    };
    worker.onerror = (e) => {
      for (const p of this.pending.values()) p.reject(new Error(`decoder worker: ${e.message}`));
      this.pending.clear();
    };
  }

  call(method, ...args) {
    const id = this.next++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.worker.postMessage({ id, method, args });
    });
  }
  terminate() {
    this.worker.terminate();
  }
}
for (const method of ['openRanges', 'addRange', 'addRanges', 'push', 'pushEnd', 'process', 'wantedRange',
                      'framesAvailable', 'info', 'camera', 'model', 'fragmentCount', 'fragment', 'fragments',
                      'decodeFrame', 'decodeFrames', 'planPrefixes', 'bandwidthAfter', 'gopFetchBudget', 'destroy',
                      'warmMemory', 'depthMapTriangles']) {
  FvvDecoderWorker.prototype[method] = function (...args) {
    return this.call(method, ...args);
  };
}
