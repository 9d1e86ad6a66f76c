// A stream on a static HTTP server, as a page plays it: the header boxes and
// the index by Range requests, then for each GOP a prefix of each fragment the
// view needs, as long as the bandwidth measured allows (the fetch plan compiled
// into the module: player/playback/fetch_plan.h). Works with an FvvDecoder or
// the Web Worker's FvvDecoderWorker (every call is awaited).
//
//   const stream = await FvvStream.open(url, decoder, { onNotice: (text) => ... });
//   await stream.fetchGop(0, [0, 1]);          // GOP 0 for cameras 0 and 1
//   const frame = await stream.frame(0, [0, 1]);
//
// Faults end in an FvvStreamError whose message says what happened (not
// found, the server's answer, a damaged or cut stream), never a hang: every
// request has a timeout. What arrived before a connection closed is kept:
// the decoder verifies it chunk by chunk (SPEC.md 3.5.1).

export class FvvStreamError extends Error {}


export class FvvStream {
  // headBytes: the first request's length (the decoder asks for more as it needs).
  static async open(url, decoder, { timeoutMs = 10000, onNotice = () => {}, headBytes = 1 << 16 } = {}) {
    const s = new FvvStream(url, decoder, timeoutMs, onNotice);
    await s.#openHead(headBytes);
    return s;
  }

  constructor(url, decoder, timeoutMs, onNotice) {
    this.url = url;
    this.decoder = decoder;
    this.timeoutMs = timeoutMs;
    this.notice = onNotice;
    this.bandwidth = 0;       // bytes per second, measured (`measured` folded in)
    this.measured = [];       // fetches not yet folded in: [bytes, seconds]
    this.fetched = 0;         // every byte fetched, heads included
    this.fetchSeconds = 0;    // the time those fetches took, request to last byte
    this.wholeFile = false;   // the server ignored Range: the whole stream is held
  }

  // Bytes [offset, offset + size) of the stream: { bytes, total, complete }.
  // `complete` is false when the connection closed early (what came is kept).
  async #get(offset, size) {
    const controller = new AbortController();
    const timer = setTimeout(() => controller.abort(), this.timeoutMs);
    const started = performance.now();
    let response;
    try {
      response = await fetch(this.url, {
        headers: { Range: `bytes=${offset}-${offset + size - 1}` }, signal: controller.signal,
        cache: 'no-store',
      });
    } catch (e) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: no answer (${e.name === 'AbortError' ? 'timed out' : e.message})`);
    }
    if (response.status === 404) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: not found (404)`);
    }
    if (response.status !== 206 && response.status !== 200) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: the server answered ${response.status}`);
    }
    const parts = [];
    let received = 0, complete = true;
    try {
      const reader = response.body.getReader();
      for (;;) {
        const { done, value } = await reader.read();
        if (done) break;
        parts.push(value);
        received += value.length;
      }
    } catch {
      complete = false;  // closed mid-body: keep what came
    } finally {
      clearTimeout(timer);
    }
    const bytes = new Uint8Array(received);
    let at = 0;
    for (const p of parts) {
      bytes.set(p, at);
      at += p.length;
    }
    this.fetched += received;
    const seconds = (performance.now() - started) / 1000;
    this.fetchSeconds += seconds;
    if (received > 0 && seconds > 0) {
      // Folded in later: a fetch's end waits for no decoder.
      this.measured.push([received, seconds]);
    }
    if (response.status === 200) {
      // A server that ignores Range sends the whole stream: it is all held now.
      return { bytes, total: received, whole: true, complete };
    }
    const range = /^bytes (\d+)-(\d+)\/(\d+)$/.exec(response.headers.get('Content-Range') ?? '');
    if (!range || Number(range[1]) !== offset) {
      throw new FvvStreamError(`${this.url}: a range answer without a matching Content-Range`);
    }
    const expected = Number(range[2]) - Number(range[1]) + 1;
    return { bytes, total: Number(range[3]), whole: false, complete: complete && received === expected };
  }

  async #call(method, ...args) {
    try {
      return await this.decoder[method](...args);
    } catch (e) {
      throw new FvvStreamError(`${this.url}: ${e.message}`);
    }
  }

  async #openHead(headBytes) {
    const first = await this.#get(0, headBytes);
    await this.#call('openRanges', first.total);
    await this.#call('addRange', 0, first.bytes);
    if (first.whole) {
      this.wholeFile = true;
      this.notice('the server does not answer Range requests: the whole stream was fetched');
    }
    for (let guard = 0; ; ++guard) {
      const event = await this.#call('process');
      if (event !== 'need') break;
      const want = await this.#call('wantedRange');
      if (!want || guard > 1000) throw new FvvStreamError(`${this.url}: the stream's head never completes`);
      const part = await this.#get(want.offset, want.size);
      if (part.bytes.length === 0) throw new FvvStreamError(`${this.url}: the stream ends before its head does`);
      await this.#call('addRange', want.offset, part.bytes);
    }
    this.info = await this.#call('info');
    this.groups = Math.ceil(this.info.cameraCount / this.info.gopCameras);
    this.gopSeconds = this.info.gopFrames / this.info.frameRate;
    // Where each fragment is, from the index, once: later fetches ask the
    // decoder nothing (it may be busy decoding). `held` is kept here.
    this.fragmentList = await this.#call('fragments', 0, await this.#call('fragmentCount'));
  }

  // The fragments of GOP `span` for `cameras` (indices; all when absent):
  // camera group 0 always (it carries the motion).
  fragmentsFor(span, cameras) {
    const groups = new Set([0]);
    for (const c of cameras ?? [...Array(this.info.cameraCount).keys()]) {
      groups.add(Math.floor(c / this.info.gopCameras));
    }
    return [...groups].sort((a, b) => a - b).map((g) => {
      const f = this.fragmentList[span * this.groups + g];
      if (!f) throw new FvvStreamError(`${this.url}: no fragment for GOP ${span}, camera group ${g}`);
      return f;
    });
  }

  // Fetches GOP `span` for `cameras`: each fragment's prefix as the fetch plan
  // gives it for `budget` bytes (default: what the bandwidth allows while a
  // GOP plays; unmeasured, whole fragments), the requests together. Returns
  // { fetched, parts, cameras }: the bytes fetched, and of `cameras` those
  // whose fragments hold their heads (they decode). The bytes reach the
  // decoder with addParts(parts), which a player may leave until the decoder
  // is free, fetching on meanwhile.
  // lastFetchSeconds is the time from the first request to the last byte,
  // lastFetchWhole whether the plan took every fragment whole. `planner`
  // (FvvPlayback, on the page's thread) plans without waiting for the decoder.
  async fetchGopBytes(span, cameras, budget, planner = this.decoder) {
    this.lastFetchSeconds = 0;
    this.lastFetchWhole = true;
    if (this.wholeFile) return { fetched: 0, parts: [] };
    const fragments = this.fragmentsFor(span, cameras);
    if (budget === undefined) {
      for (const [bytes, seconds] of this.measured.splice(0)) {
        this.bandwidth = await this.#call('bandwidthAfter', this.bandwidth, bytes, seconds);
      }
    }
    const allowed = budget ?? (this.bandwidth > 0
      ? await this.#call('gopFetchBudget', this.bandwidth, this.gopSeconds) : Number.MAX_SAFE_INTEGER);
    const plan = await planner.planPrefixes(fragments, allowed);
    this.lastFetchWhole = fragments.every((f, i) => plan[i] >= f.size);
    const started = performance.now();
    const got = await Promise.all(fragments.map((f, i) => {
      const want = plan[i] - f.held;
      return want > 0 ? this.#get(f.offset + f.held, want).then((part) => ({ f, want, part })) : null;
    }));
    this.lastFetchSeconds = (performance.now() - started) / 1000;
    let fetched = 0;
    const parts = [];
    for (const g of got) {
      if (!g) continue;
      const { f, want, part } = g;
      if (part.bytes.length > 0) parts.push({ offset: f.offset + f.held, bytes: part.bytes });
      f.held += part.bytes.length;
      fetched += part.bytes.length;
      if (!part.complete) {
        this.notice(`the connection closed ${part.bytes.length} of ${want} bytes into fragment ` +
                    `${f.index}: it decodes from what arrived`);
      }
    }
    // The cameras whose fragments decode: each needs its head (a connection
    // that closed before the head left its camera out); the motion's too.
    const decodable = new Set(fragments.filter((f) => f.held >= f.headSize).map((f) => f.firstCamera));
    if (!decodable.has(0)) {  // fragments[0] is camera group 0's, which carries the motion
      throw new FvvStreamError(`${this.url}: GOP ${span}'s motion did not arrive (camera group 0's head)`);
    }
    const all = cameras ?? [...Array(this.info.cameraCount).keys()];
    const ready = all.filter((c) => decodable.has(c - (c % this.info.gopCameras)));
    return { fetched, parts, cameras: ready };
  }

  async addParts(parts) {
    for (const p of parts) await this.#call('addRange', p.offset, p.bytes);
  }

  // fetchGopBytes, its bytes given to the decoder: returns the bytes fetched.
  async fetchGop(span, cameras, budget) {
    const { fetched, parts } = await this.fetchGopBytes(span, cameras, budget);
    await this.addParts(parts);
    return fetched;
  }

  async frame(index, cameras) {
    return this.#call('decodeFrame', index, cameras ? { cameras } : {});
  }
}
